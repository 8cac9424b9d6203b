// The lobes of Cycles' closures added for issue 19 (scene/lobes/: oren_nayar.h, velvet.h, translucent.h,
// refraction.h, beckmann.h, toon_*.h, multiscatter_ggx.h, anisotropic.h, principled_glass.h), in
// bsdf_test.cpp's style:
//  1. chi-square of sample() against pdf() (stats.h), Sidak-corrected over this file's cases;
//  2. sample() / eval() / pdf() agreement;
//  3. white furnace: the importance-sampled albedo against quadrature of eval(), and exact energy
//     conservation where the lobe conserves it (Translucent; smooth Refraction of a white glass);
//  4. the closed forms of Cycles 3.4's kernels at hand-picked directions (bsdf_oren_nayar.h,
//     bsdf_ashikhmin_velvet.h, bsdf_diffuse.h, bsdf_microfacet.h's Beckmann), written out again here
//     in double precision;
//  5. multiscatter GGX: its pair of lobes keeps what Cycles' random walk keeps, and its table is the walk; anisotropic GGX and Beckmann
//     against Cycles' slope-form formulas and equal to the isotropic lobes at alpha_x = alpha_y;
//  6. the lobe interface: every kind has a name that maps back to it, and its routines stay finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <random>
#include <initializer_list>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "scene/ggx_multiple.h"
#include "scene/ggx_walk.h"
#include "lobe_checks.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using st::close_rel;
using st::num;

namespace {

constexpr uint64_t kChi2Samples = 1000000;
constexpr double kFamilySignificance = 0.01;
const float kCosThetas[] = {0.95f, 0.5f, 0.05f};
const float kPhis[] = {0.3f, 1.9f, 4.0f};

using lobe_checks::dir_from_cos;
using lobe_checks::rand2;

Lobe lobe_of(LobeKind kind, float param, Color weight = Color(1.0f), float eta = 1.5f) {
    Lobe l;
    l.kind = kind;
    l.alpha = param;
    l.weight = weight;
    l.eta = eta;
    return l;
}

Lobe principled_glass_lobe(float alpha_r, float alpha_t, Color base = Color(1.0f), float tint = 0.0f,
                           float eta = 1.5f) {
    Lobe l = lobe_of(LobeKind::PrincipledGlass, alpha_r, Color(1.0f), eta);
    l.alpha_y = alpha_t;
    l.f0 = base;
    l.kind_colour.x = tint;
    return l;
}


// The new lobes with the parameters the tests sweep (name, lobe, whether wo may be under the surface).
struct NamedLobe {
    std::string name;
    Lobe lobe;
    bool two_sided = false;
    // A lobe with a nearly Dirac part (alpha kDeltaAlpha) defeats the chi-square's quadrature of the
    // pdf over its cells: its other tests still run.
    bool chi2 = true;
};
std::vector<NamedLobe> new_lobes() {
    std::vector<NamedLobe> v;
    for (float sigma : {0.0f, 0.3f, 1.0f})
        v.push_back({"OrenNayar_s" + num(sigma), lobe_of(LobeKind::OrenNayar, sigma, Color(0.8f, 0.6f, 0.4f))});
    for (float sigma : {0.0f, 0.2f, 0.5f, 1.0f})
        v.push_back({"Velvet_s" + num(sigma), lobe_of(LobeKind::Velvet, sigma, Color(0.7f, 0.5f, 0.9f))});
    v.push_back({"Translucent", lobe_of(LobeKind::Translucent, 0.0f, Color(0.9f, 0.8f, 0.3f))});
    for (float alpha : {0.05f, 0.2f, 0.6f})
        v.push_back({"Beckmann_a" + num(alpha), lobe_of(LobeKind::Beckmann, alpha, Color(0.8f, 0.9f, 0.6f))});
    for (auto [size, smooth] : {std::pair{0.5f, 0.0f}, std::pair{0.3f, 0.4f}, std::pair{0.9f, 0.5f}}) {
        Lobe d = lobe_of(LobeKind::ToonDiffuse, size, Color(0.6f, 0.7f, 0.9f)), g = d;
        g.kind = LobeKind::ToonGlossy;
        d.f0.x = g.f0.x = smooth;
        v.push_back({"ToonDiffuse_" + num(size) + "_" + num(smooth), d});
        v.push_back({"ToonGlossy_" + num(size) + "_" + num(smooth), g});
    }
    for (float alpha : {0.1f, 0.5f, 1.0f})
        v.push_back({"MultiGgx_a" + num(alpha), lobe_of(LobeKind::MultiGgx, alpha, Color(0.9f, 0.7f, 0.5f))});
    // The Principled metal with Multiscatter GGX: the single scattering with Schlick's Fresnel.
    Lobe metal = lobe_of(LobeKind::MultiGgx, 0.49f, Color(1.0f));
    metal.fresnel = FresnelMode::Schlick;
    metal.f0 = Color(0.9f, 0.7f, 0.5f);
    v.push_back({"MultiGgxMetal_a0p49", metal});
    for (float alpha : {0.25f, 1.0f})
        v.push_back({"GgxMultiple_a" + num(alpha), lobe_of(LobeKind::GgxMultiple, alpha, Color(0.3f, 0.2f, 0.1f))});
    for (auto [ax, ay] : {std::pair{0.05f, 0.4f}, std::pair{0.6f, 0.15f}, std::pair{1.0f, 0.3f}}) {
        Lobe g = lobe_of(LobeKind::AnisoGgx, ax, Color(0.8f, 0.7f, 0.9f)), b = g;
        g.alpha_y = b.alpha_y = ay;
        b.kind = LobeKind::AnisoBeckmann;
        v.push_back({"AnisoGgx_" + num(ax) + "_" + num(ay), g});
        v.push_back({"AnisoBeckmann_" + num(ax) + "_" + num(ay), b});
    }
    // Ashikhmin-Shirley: the Glossy BSDF's (alpha_x = alpha_y) and the Anisotropic BSDF's.
    for (auto [ax, ay] : {std::pair{0.09f, 0.09f}, std::pair{0.49f, 0.49f}, std::pair{1.0f, 1.0f},
                          std::pair{0.05f, 0.4f}, std::pair{0.6f, 0.15f}}) {
        Lobe l = lobe_of(LobeKind::AshikhminShirley, ax, Color(0.9f, 0.6f, 0.3f));
        l.alpha_y = ay;
        v.push_back({"AshikhminShirley_" + num(ax) + "_" + num(ay), l});
    }
    // Anisotropic lobes about their own tangent, turned from the frame's (lobe.h, to_lobe_tangent).
    for (LobeKind kind : {LobeKind::AnisoGgx, LobeKind::AnisoBeckmann, LobeKind::AshikhminShirley}) {
        Lobe l = lobe_of(kind, 0.1f, Color(0.6f, 0.8f, 0.9f));
        l.alpha_y = 0.5f;
        l.kind_colour = Color(std::cos(2.2f) - 1.0f, std::sin(2.2f), 0.0f);
        v.push_back({"OwnTangent_" + std::to_string(int(kind)), l});
    }
    // Hair BSDF: r1 = Roughness U (alpha), r2 = Roughness V (alpha_y), Offset (f0.x, radians).
    for (auto [r1, r2, offset] : {std::tuple{0.1f, 1.0f, 0.0f}, std::tuple{0.3f, 0.4f, 0.05f}, std::tuple{0.02f, 0.1f, -0.1f}}) {
        Lobe r = lobe_of(LobeKind::HairReflection, r1, Color(0.8f, 0.6f, 0.4f)), t = r;
        r.alpha_y = t.alpha_y = r2;
        r.f0.x = t.f0.x = offset;
        t.kind = LobeKind::HairTransmission;
        v.push_back({"HairReflection_" + num(r1) + "_" + num(r2) + "_" + num(offset), r});
        v.push_back({"HairTransmission_" + num(r1) + "_" + num(r2) + "_" + num(offset), t});
    }
    // Principled Hair paths: v (alpha, after Cycles' remapping), s (alpha_y), IOR, tilt (f0.x).
    for (auto [v_p, s_p, tilt] : {std::tuple{0.02f, 0.3f, 0.0f}, std::tuple{0.15f, 0.1f, 0.07f}, std::tuple{0.6f, 0.8f, -0.3f}})
        for (int p = 0; p < 4; ++p) {
            Lobe l = lobe_of(LobeKind(int(LobeKind::PrincipledHairR) + p), v_p, Color(0.6f, 0.4f, 0.2f), 1.55f);
            l.alpha_y = s_p;
            l.f0.x = tilt;
            v.push_back({"PrincipledHair" + std::to_string(p) + "_" + num(v_p) + "_" + num(s_p) + "_" + num(tilt), l});
        }
    for (float alpha : {0.1f, 0.5f})
        v.push_back({"Refraction_a" + num(alpha), lobe_of(LobeKind::Refraction, alpha, Color(0.9f, 1.0f, 0.8f), 1.5f),
                     true});
    // Glass and Refraction with the Beckmann distribution (variant; lobes/dielectric.h).
    for (float alpha : {0.1f, 0.5f}) {
        Lobe refraction = lobe_of(LobeKind::Refraction, alpha, Color(0.9f, 1.0f, 0.8f), 1.5f);
        Lobe glass = lobe_of(LobeKind::Dielectric, alpha, Color(0.8f, 0.9f, 1.0f), 1.45f);
        refraction.variant = glass.variant = kBeckmannDistribution;
        v.push_back({"BeckmannRefraction_a" + num(alpha), refraction, true});
        v.push_back({"BeckmannGlass_a" + num(alpha), glass, true});
    }
    // Principled transmission: reflection and refraction roughness apart, one of them smooth, tinted.
    for (auto [ar, at] : {std::pair{0.09f, 0.36f}, std::pair{0.0f, 0.25f}, std::pair{0.3f, 0.0f}}) {
        Lobe g = principled_glass_lobe(ar, at, Color(0.9f, 0.5f, 0.2f), 0.7f);
        v.push_back({"PrincipledGlass_" + num(ar) + "_" + num(at), g, true, ar > 0.0f && at > 0.0f});
    }
    // Subsurface scattering's parts of the principled diffuse (lobes/principled_part.h).
    for (uint8_t variant : {PrincipledPartLobe::kLambert, PrincipledPartLobe::kExit, PrincipledPartLobe::kRetro}) {
        Lobe l = lobe_of(LobeKind::PrincipledPart, 0.36f, Color(0.8f, 0.5f, 0.3f));
        l.variant = variant;
        v.push_back({"PrincipledPart_" + num(variant), l});
    }
    return v;
}

using lobe_checks::Chi2Case;

std::vector<Chi2Case> build_chi2_cases() {
    std::vector<Chi2Case> cases;
    for (const NamedLobe& nl : new_lobes())
        for (int i = 0; i < (!nl.chi2 ? 0 : nl.two_sided ? 6 : 3); ++i) {
            Lobe lobe = nl.lobe;
            // wo inside the glass for i >= 3, inside the critical angle (cos 0.745 at eta 1.5): beyond it
            // almost every sample is totally reflected, and a histogram of the rest would be vacuous.
            const float inside_cos[] = {0.95f, 0.85f, 0.8f};
            float c = i < 3 ? kCosThetas[i] : -inside_cos[i - 3];
            cases.push_back({nl.name + "_cos" + num(c), lobe, dir_from_cos(c, kPhis[i % 3])});
        }
    return cases;
}

const std::vector<Chi2Case>& chi2_cases() {
    static const std::vector<Chi2Case> cases = build_chi2_cases();
    return cases;
}

class ClosureChi2 : public ::testing::TestWithParam<int> {};

TEST_P(ClosureChi2, SampleMatchesPdf) {
    const Chi2Case& c = chi2_cases()[GetParam()];
    lobe_checks::expect_sampling_matches_pdf(c.name, c.lobe, c.wo, 0x5150 + GetParam(), kChi2Samples,
                                             static_cast<int>(chi2_cases().size()), kFamilySignificance);
}

INSTANTIATE_TEST_SUITE_P(All, ClosureChi2, ::testing::Range(0, static_cast<int>(chi2_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) { return chi2_cases()[info.param].name; });

TEST(ClosureConsistency, SampleAgreesWithEvalAndPdf) {
    Rng rng(7, 19);
    for (const NamedLobe& nl : new_lobes()) lobe_checks::expect_sample_agrees_with_eval(nl.name, nl.lobe, rng, nl.two_sided);
}

// ---------------------------------------------------------------------------------------------
// White furnace

st::MeanEstimator sampled_albedo(const Lobe& lobe, const Vec3& wo, int n, uint64_t seed) {
    Rng rng(seed, 0);
    st::MeanEstimator m;
    for (int i = 0; i < n; ++i) {
        BsdfSample s = lobe_sample(lobe, wo, rand2(rng), rng.next_float());
        m.add(s.valid() ? average(s.value) / s.pdf : 0.0);
    }
    return m;
}

double quadrature_albedo(const Lobe& lobe, const Vec3& wo) {
    return st::integrate_sphere([&](const Vec3& wi) { return double(average(lobe_eval(lobe, wo, wi))); });
}

::testing::AssertionResult matches_quadrature(const st::MeanEstimator& is, double quad) {
    double z = st::z_test(is.mean(), quad, is.std_error(), 2e-5).z;
    if (std::fabs(z) <= 3.0) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << "IS " << is.mean() << " +- " << is.std_error() << " vs quadrature " << quad
                                         << " (z = " << z << ")";
}

// Translucent is Lambert turned over: all of a white furnace goes through (value / pdf = 1 exactly).
TEST(ClosureFurnace, TranslucentTransmitsEverything) {
    for (int i = 0; i < 3; ++i) {
        Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
        st::MeanEstimator is = sampled_albedo(lobe_of(LobeKind::Translucent, 0.0f), wo, 200000, 3 + i);
        std::printf("[furnace] Translucent cos %.2f: %.6f +- %.2g\n", kCosThetas[i], is.mean(), is.std_error());
        EXPECT_LE(std::fabs(st::z_test_mean(is, 1.0, 1e-5).z), 3.0) << is.mean();
        EXPECT_NEAR(quadrature_albedo(lobe_of(LobeKind::Translucent, 0.0f), wo), 1.0, 2e-3);
    }
}

// Refraction without its Fresnel factor: a smooth interface passes all the energy that is not totally
// reflected (value / pdf = weight (eta_i/eta_t)^2, undone here); a rough one loses only what its
// microfacets reflect back or totally reflect.
TEST(ClosureFurnace, RefractionPassesEnergyOnly) {
    for (float alpha : {0.0f, 0.1f, 0.5f})
        for (bool inside : {false, true})
            for (int i = 0; i < 3; ++i) {
                Lobe lobe = lobe_of(LobeKind::Refraction, alpha, Color(1.0f), 1.5f);
                float c = inside ? -kCosThetas[i] : kCosThetas[i];
                Vec3 wo = dir_from_cos(c, kPhis[i]);
                float etap = inside ? 1.0f / 1.5f : 1.5f;
                Rng rng(33 + i, 1);
                st::MeanEstimator m;
                for (int k = 0; k < 200000; ++k) {
                    BsdfSample s = lobe_sample(lobe, wo, rand2(rng), rng.next_float());
                    m.add(s.valid() ? average(s.value) / s.pdf * double(etap) * etap : 0.0);
                }
                // Total internal reflection from inside beyond the critical angle (sin > 1/1.5).
                bool tir = inside && std::sqrt(1.0 - double(c) * c) > 1.0 / 1.5;
                std::printf("[furnace] Refraction a=%.1f %s cos %.2f: %.5f +- %.2g\n", alpha, inside ? "inside" : "outside",
                            kCosThetas[i], m.mean(), m.std_error());
                if (alpha == 0.0f) {
                    EXPECT_NEAR(m.mean(), tir ? 0.0 : 1.0, 1e-5) << c;
                } else {
                    EXPECT_TRUE(st::at_most(m, 1.0)) << alpha << " " << c << ": " << m.mean();
                }
                if (!tir && !inside) {
                    EXPECT_GT(m.mean(), 0.5) << alpha << " " << c;
                }
            }
}

// For every parameter (kept in alpha) and incident angle: the importance-sampled albedo, which must
// match quadrature of eval(); `check` adds the lobe's own bound.
void furnace_sweep(const char* name, LobeKind kind, std::initializer_list<float> params, uint64_t seed,
                   const std::function<void(float, int, const st::MeanEstimator&)>& check) {
    for (float param : params)
        for (int i = 0; i < 3; ++i) {
            Lobe lobe = lobe_of(kind, param);
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
            st::MeanEstimator is = sampled_albedo(lobe, wo, 400000, seed + i);
            double quad = quadrature_albedo(lobe, wo);
            std::printf("[furnace] %s %.2f cos %.2f: IS %.5f +- %.2g, quadrature %.5f\n", name, param, kCosThetas[i],
                        is.mean(), is.std_error(), quad);
            EXPECT_TRUE(matches_quadrature(is, quad)) << name << " " << param << " cos " << kCosThetas[i];
            check(param, i, is);
        }
}

// Fresh random walks (scene/ggx_walk.h, Cycles' walk) from wo: the fraction leaving after one bounce,
// after more (white, and with colour c at each further bounce), and the mean cosine of the latter.
struct WalkStats {
    st::MeanEstimator single, multiple, tinted, cos_multiple;
};
WalkStats walk_stats(const Vec3& wo, float alpha, float c, int n, uint32_t seed) {
    std::mt19937 gen(seed);
    auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
    WalkStats w;
    for (int k = 0; k < n; ++k) {
        ggx_walk::Exit e = ggx_walk::walk(wo, alpha, rand);
        bool multiple = e.bounces >= 2;
        w.single.add(e.bounces == 1 ? 1.0 : 0.0);
        w.multiple.add(multiple ? 1.0 : 0.0);
        w.tinted.add(multiple ? std::pow(double(c), e.bounces - 1) : 0.0);
        if (multiple) w.cos_multiple.add(e.dir.z);
    }
    return w;
}

// Multiscatter GGX as the compiler builds it (lobes/multiscatter_ggx.h): its two lobes in one Bsdf,
// sampled as the renderer samples a mixture, against fresh walks of Cycles' random walk:
//  * the analytic single scattering (height-correlated G2) is the walk's one-bounce part;
//  * the pair keeps what the walk keeps: a white furnace's energy, at least the 95% issue 19 asks for
//    at roughness 1 (the walk loses only what is left after 10 bounces).
TEST(ClosureFurnace, MultiscatterGgxKeepsTheWalksEnergy) {
    for (float rough : {0.3f, 0.8f, 1.0f})
        for (int i = 0; i < 3; ++i) {
            Lobe single = lobe_of(LobeKind::MultiGgx, rough * rough), multiple;
            ASSERT_TRUE(multiple_scattering_lobe(single, Color(1.0f), &multiple));
            Bsdf bsdf(Frame(), Vec3(0, 0, 1));
            bsdf.add(single);
            bsdf.add(multiple);
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
            Rng rng(71 + i, 3);
            st::MeanEstimator pair;
            for (int k = 0; k < 300000; ++k) {
                BsdfSample s = bsdf.sample(wo, rand2(rng), rng.next_float());
                pair.add(s.valid() ? average(s.value) / s.pdf : 0.0);
            }
            st::MeanEstimator alone = sampled_albedo(single, wo, 200000, 91 + i);
            WalkStats w = walk_stats(wo, single.alpha, 1.0f, 200000, 5 + i);
            double walk_total = w.single.mean() + w.multiple.mean();
            std::printf("[furnace] MultiscatterGgx rough %.1f cos %.2f: pair %.5f +- %.2g (walk %.5f), single %.5f "
                        "(walk %.5f)\n", rough, kCosThetas[i], pair.mean(), pair.std_error(), walk_total,
                        alone.mean(), w.single.mean());
            EXPECT_GE(pair.mean(), 0.95) << rough << " " << kCosThetas[i];
            EXPECT_NEAR(pair.mean(), walk_total, 0.01) << rough << " " << kCosThetas[i];
            EXPECT_LE(std::fabs(st::z_test(alone.mean(), w.single.mean(),
                                           std::hypot(alone.std_error(), w.single.std_error()), 1e-3).z), 3.0)
                << rough << " " << kCosThetas[i];
            EXPECT_TRUE(matches_quadrature(alone, quadrature_albedo(single, wo))) << rough;
        }
}

// The tabulated multiple scattering against fresh walks between the table's cells (roughness 0.75,
// cos 0.7): its albedo, the mean cosine of where it leaves (the lobe's shape), and its colour with
// c = 0.7 applied at each further bounce (the table fits c = 0.5 and 1).
TEST(ClosureFurnace, MultiscatterGgxTableIsTheWalk) {
    float alpha = 0.75f * 0.75f;
    Vec3 wo = dir_from_cos(0.7f, 0.4f);
    Color c(0.7f);
    Lobe single = lobe_of(LobeKind::MultiGgx, alpha, c), multiple;
    ASSERT_TRUE(multiple_scattering_lobe(single, c, &multiple));
    WalkStats w = walk_stats(wo, alpha, c.x, 400000, 77);
    double table = ggx_multiple_albedo(wo.z, alpha);
    double energy = st::integrate_sphere([&](const Vec3& wi) { return double(ggx_multiple_brdf(wo, wi, alpha)) * std::max(wi.z, 0.0f); });
    double first = st::integrate_sphere([&](const Vec3& wi) {
        return double(ggx_multiple_brdf(wo, wi, alpha)) * sqr(std::max(wi.z, 0.0f));
    });
    // The lobe's colour: its albedo over the white table's, over the closure weight c.
    double tint = quadrature_albedo(multiple, wo) / energy / c.x;
    std::printf("[walk] multiple %.5f (table %.5f, lobe %.5f), mean cos %.4f (lobe %.4f), tinted %.5f (lobe %.5f)\n",
                w.multiple.mean(), table, energy, w.cos_multiple.mean(), first / energy, w.tinted.mean() / w.multiple.mean(),
                tint);
    EXPECT_NEAR(table, w.multiple.mean(), 0.02 * w.multiple.mean());
    EXPECT_NEAR(energy, w.multiple.mean(), 0.02 * w.multiple.mean());
    EXPECT_NEAR(first / energy, w.cos_multiple.mean(), 0.01);
    EXPECT_NEAR(tint, w.tinted.mean() / w.multiple.mean(), 0.01);
}

// Anisotropic GGX and Beckmann (single scattering, no Fresnel) lose energy only; with alpha_x = alpha_y
// they are the isotropic lobes exactly.
TEST(ClosureFurnace, AnisotropicLosesEnergyOnlyAndIsIsotropicAtEqualAlphas) {
    for (LobeKind kind : {LobeKind::AnisoGgx, LobeKind::AnisoBeckmann})
        for (auto [ax, ay] : {std::pair{0.1f, 0.5f}, std::pair{0.8f, 0.2f}})
            for (int i = 0; i < 3; ++i) {
                Lobe lobe = lobe_of(kind, ax);
                lobe.alpha_y = ay;
                Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
                st::MeanEstimator is = sampled_albedo(lobe, wo, 300000, 57 + i);
                double quad = quadrature_albedo(lobe, wo);
                std::printf("[furnace] %s %.1f/%.1f cos %.2f: IS %.5f +- %.2g, quadrature %.5f\n",
                            kind == LobeKind::AnisoGgx ? "AnisoGgx" : "AnisoBeckmann", ax, ay, kCosThetas[i], is.mean(),
                            is.std_error(), quad);
                EXPECT_TRUE(matches_quadrature(is, quad)) << ax << " " << ay << " cos " << kCosThetas[i];
                EXPECT_TRUE(st::at_most(is, 1.0)) << is.mean();
            }
    Rng rng(3, 9);
    for (int k = 0; k < 2000; ++k) {
        Vec3 wo = sample_cosine_hemisphere(rand2(rng)), wi = sample_cosine_hemisphere(rand2(rng));
        for (float alpha : {0.05f, 0.3f, 0.9f}) {
            Lobe aniso = lobe_of(LobeKind::AnisoGgx, alpha), iso = lobe_of(LobeKind::Microfacet, alpha);
            aniso.alpha_y = alpha;
            ASSERT_TRUE(close_rel(lobe_eval(aniso, wo, wi).x, lobe_eval(iso, wo, wi).x, 1e-4)) << alpha;
            ASSERT_TRUE(close_rel(lobe_pdf(aniso, wo, wi), lobe_pdf(iso, wo, wi), 1e-4)) << alpha;
            aniso.kind = LobeKind::AnisoBeckmann;
            iso.kind = LobeKind::Beckmann;
            ASSERT_TRUE(close_rel(lobe_eval(aniso, wo, wi).x, lobe_eval(iso, wo, wi).x, 1e-4)) << alpha;
        }
    }
}

// Ashikhmin-Shirley (no Fresnel; eval / pdf = cos_i / max(cos_i, cos_o)) loses energy only, isotropic
// or not; its sampling matches quadrature of eval().
TEST(ClosureFurnace, AshikhminShirleyLosesEnergyOnly) {
    for (auto [ax, ay] : {std::pair{0.09f, 0.09f}, std::pair{1.0f, 1.0f}, std::pair{0.1f, 0.5f}, std::pair{0.8f, 0.2f}})
        for (int i = 0; i < 3; ++i) {
            Lobe lobe = lobe_of(LobeKind::AshikhminShirley, ax);
            lobe.alpha_y = ay;
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
            st::MeanEstimator is = sampled_albedo(lobe, wo, 300000, 71 + i);
            double quad = quadrature_albedo(lobe, wo);
            std::printf("[furnace] AshikhminShirley %.2f/%.2f cos %.2f: IS %.5f +- %.2g, quadrature %.5f\n", ax, ay,
                        kCosThetas[i], is.mean(), is.std_error(), quad);
            EXPECT_TRUE(matches_quadrature(is, quad)) << ax << " " << ay << " cos " << kCosThetas[i];
            EXPECT_TRUE(st::at_most(is, 1.0)) << is.mean();
        }
}

// Cycles 3.4's anisotropic Beckmann sampler (the setting beckmann_cycles_sampling, AnisoBeckmannLobe::
// kCyclesSampler), written out again here in double precision: bsdf_microfacet_beckmann_sample draws the
// visible normal of the isotropic Beckmann of roughness alpha_x (microfacet_sample_stretched(..., alpha_x,
// alpha_x, ...)), so its directions follow
//   p_iso(wi) = G1s(wo, ax) D_iso(m; ax) / (4 cos_o)                       (Heitz & d'Eon 2014, eq. 2, x 1/(4 wo.m))
// with Smith's exact G1s; it returns pdf = G1s(wo, ax) D(m; ax, ay) / (4 cos_o), the anisotropic D, and
// value = pdf G1(wi) (Walter's rational G1 at the direction's alpha). Its eval's pdf (light samples'
// MIS) is G1(wo) D / (4 cos_o). The directions are chi-squared against p_iso (and fail against the
// returned pdf: Cycles' mismatch), the values checked at every sample.
namespace cycles_beckmann {
double smith_g1(const Vec3& w, double alpha) {
    double a = w.z / (alpha * std::sqrt(double(w.x) * w.x + double(w.y) * w.y));
    return 1.0 / (1.0 + 0.5 * (std::erf(a) - 1.0) + std::exp(-a * a) / (2.0 * a * std::sqrt(kPi)));
}
double rational_g1(const Vec3& w, double ax, double ay) {
    double a = w.z / std::sqrt(sqr(ax * w.x) + sqr(ay * w.y));
    return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
}
double d_aniso(const Vec3& m, double ax, double ay) {
    double c2 = double(m.z) * m.z;
    return std::exp(-(sqr(m.x / ax) + sqr(m.y / ay)) / c2) / (kPi * ax * ay * c2 * c2);
}
Vec3 half(const Vec3& wo, const Vec3& wi) { return normalize(wo + wi); }
// Cycles drops the samples whose returned pdf underflows (the anisotropic D in single precision, at
// normals far beyond alpha_y: about 0.1% of them at 0.32 / 0.08), as the lobe does.
double p_iso(const Vec3& wo, const Vec3& wi, double ax, double ay) {
    if (!(wi.z > 0.0f)) return 0.0;
    const Vec3 m = half(wo, wi);
    if (!(AnisoBeckmannLobe::D(m, float(ax), float(ay)) > 0.0f)) return 0.0;
    return smith_g1(wo, ax) * d_aniso(m, ax, ax) / (4.0 * wo.z);
}
Lobe lobe(float ax, float ay) {
    Lobe l = lobe_of(LobeKind::AnisoBeckmann, ax, Color(0.7f, 0.8f, 0.9f));
    l.alpha_y = ay;
    l.variant = AnisoBeckmannLobe::kCyclesSampler;
    return l;
}
// The closures scene's sphere (Roughness 0.4, Anisotropy -0.5: 0.32 / 0.08), and a wider pair.
const std::pair<float, float> kAlphas[] = {{0.32f, 0.08f}, {0.15f, 0.6f}};
const std::pair<float, float> kViews[] = {{0.9f, 0.4f}, {0.5f, 1.3f}, {0.2f, 2.6f}};
}  // namespace cycles_beckmann

TEST(ClosureChi2, AnisoBeckmannCyclesSamplerDrawsTheIsotropicAlphaX) {
    using namespace cycles_beckmann;
    const int cases = 2 * 3;
    uint64_t seed = 401;
    for (auto [ax, ay] : kAlphas)
        for (auto [cos_o, phi] : kViews) {
            Lobe l = lobe(ax, ay);
            Vec3 wo = dir_from_cos(cos_o, phi);
            std::string name = "AnisoBeckmannCycles_" + num(ax) + "_" + num(ay) + "_cos" + num(cos_o);
            auto sample = [&](Rng& rng) { return lobe_checks::dir_sample(l, wo, rng); };
            st::Chi2Options opt;
            opt.seed = ++seed;
            opt.pdf_rel_tolerance = 0.0;  // the samples report Cycles' pdf, not their density
            st::Chi2Result iso = st::chi2_test_directions(sample, [&](const Vec3& wi) { return p_iso(wo, wi, ax, ay); },
                                                          kChi2Samples, opt);
            std::printf("[chi2] %-40s %s\n", name.c_str(), iso.summary().c_str());
            EXPECT_TRUE(iso.passes(st::sidak_significance(kFamilySignificance, cases))) << name << ": "
                                                                                       << iso.summary() << "\n"
                                                                                       << iso.residual_map();
            EXPECT_GT(iso.n_valid, kChi2Samples / 10) << name;
            // What Cycles weighs them with is not their density.
            st::Chi2Result own = st::chi2_test_directions(sample, [&](const Vec3& wi) { return lobe_pdf(l, wo, wi); },
                                                          kChi2Samples / 5, opt);
            EXPECT_FALSE(own.passes(1e-6)) << name << ": " << own.summary();
        }
}

TEST(ClosureClosedForm, AnisoBeckmannCyclesSamplerReturnsCyclesValueAndPdf) {
    using namespace cycles_beckmann;
    Rng rng(9, 4);
    for (auto [ax, ay] : kAlphas) {
        Lobe l = lobe(ax, ay), plain = l;
        plain.variant = 0;
        int valid = 0;
        for (int k = 0; k < 5000; ++k) {
            Vec3 wo = sample_cosine_hemisphere(rand2(rng));
            BsdfSample s = lobe_sample(l, wo, rand2(rng), rng.next_float());
            if (!s.valid()) continue;
            ++valid;
            Vec3 m = half(wo, s.wi);
            double pdf = smith_g1(wo, ax) * d_aniso(m, ax, ay) / (4.0 * wo.z);
            ASSERT_TRUE(close_rel(s.pdf, pdf, 2e-3)) << ax << " " << s.pdf << " " << pdf;
            ASSERT_TRUE(close_rel(s.value.y, 0.8 * pdf * rational_g1(s.wi, ax, ay), 2e-3)) << ax;
            // eval is the lobe's BRDF; pdf() Cycles' eval pdf, the anisotropic visible normals'.
            ASSERT_TRUE(close_rel(lobe_eval(l, wo, s.wi).y, lobe_eval(plain, wo, s.wi).y, 1e-5)) << ax;
            ASSERT_TRUE(close_rel(lobe_pdf(l, wo, s.wi), rational_g1(wo, ax, ay) * d_aniso(m, ax, ay) / (4.0 * wo.z),
                                  2e-3)) << ax;
        }
        EXPECT_GT(valid, 4000) << ax;
    }
}

// An anisotropic lobe about its own tangent at angle phi from the frame's s axis is the same lobe about
// the frame's, seen in directions turned by -phi: what Cycles' per-closure frame gives.
TEST(ClosureClosedForm, OwnTangentTurnsTheLobe) {
    Rng rng(5, 33);
    for (LobeKind kind : {LobeKind::AnisoGgx, LobeKind::AnisoBeckmann, LobeKind::AshikhminShirley})
        for (float phi : {0.7f, -2.5f}) {
            Lobe about_frame = lobe_of(kind, 0.15f);
            about_frame.alpha_y = 0.6f;
            Lobe own = about_frame;
            own.kind_colour = Color(std::cos(phi) - 1.0f, std::sin(phi), 0.0f);
            auto turned = [&](const Vec3& w) {  // w in the lobe's own frame
                return Vec3(std::cos(-phi) * w.x - std::sin(-phi) * w.y, std::sin(-phi) * w.x + std::cos(-phi) * w.y, w.z);
            };
            int compared = 0;
            for (int k = 0; k < 2000; ++k) {
                Vec3 wo = sample_cosine_hemisphere(rand2(rng)), wi = sample_cosine_hemisphere(rand2(rng));
                float e = lobe_eval(about_frame, turned(wo), turned(wi)).x;
                ASSERT_TRUE(close_rel(lobe_eval(own, wo, wi).x, e, 1e-3, 1e-6)) << int(kind) << " " << phi;
                ASSERT_TRUE(close_rel(lobe_pdf(own, wo, wi), lobe_pdf(about_frame, turned(wo), turned(wi)), 1e-3, 1e-6));
                compared += e > 1e-3f;
            }
            EXPECT_GT(compared, 200) << int(kind);
            // and it is not the lobe about the frame's tangent
            Vec3 wo = dir_from_cos(0.7f, 0.0f), wi = dir_from_cos(0.3f, 2.0f);
            EXPECT_FALSE(close_rel(lobe_eval(own, wo, wi).x, lobe_eval(about_frame, wo, wi).x, 1e-2)) << int(kind);
        }
}

// The Principled transmission (lobes/principled_glass.h): untinted white, at one roughness, it is the
// Glass lobe exactly (Cycles' pair of closures at the same alpha); apart, a smooth one keeps all the
// energy (value / pdf 1 for a reflection, (eta_i / eta_t)^2 for a refraction, undone here) and a rough
// one loses only what its microfacets lose; its sampling matches quadrature of eval().
TEST(ClosureFurnace, PrincipledGlassIsTheGlassLobeAtOneRoughness) {
    Rng rng(4, 21);
    for (int k = 0; k < 4000; ++k) {
        Vec3 wo = sample_uniform_sphere(rand2(rng)), wi = sample_uniform_sphere(rand2(rng));
        for (float alpha : {0.05f, 0.3f, 0.8f}) {
            Lobe glass = lobe_of(LobeKind::Dielectric, alpha), principled = principled_glass_lobe(alpha, alpha);
            ASSERT_TRUE(close_rel(lobe_eval(principled, wo, wi).x, lobe_eval(glass, wo, wi).x, 1e-4)) << alpha;
            ASSERT_TRUE(close_rel(lobe_pdf(principled, wo, wi), lobe_pdf(glass, wo, wi), 1e-4)) << alpha;
        }
    }
    for (auto [ar, at] : {std::pair{0.0f, 0.0f}, std::pair{0.0f, 0.3f}, std::pair{0.5f, 0.1f}})
        for (bool inside : {false, true})
            for (int i = 0; i < 3; ++i) {
                Lobe lobe = principled_glass_lobe(ar, at);
                float c = inside ? -kCosThetas[i] : kCosThetas[i];
                Vec3 wo = dir_from_cos(c, kPhis[i]);
                float etap = inside ? 1.0f / 1.5f : 1.5f;
                Rng r(61 + i, 2);
                st::MeanEstimator m, plain;
                for (int n = 0; n < 200000; ++n) {
                    BsdfSample s = lobe_sample(lobe, wo, rand2(r), r.next_float());
                    double v = s.valid() ? average(s.value) / s.pdf : 0.0;
                    plain.add(v);
                    m.add(s.transmission ? v * etap * etap : v);
                }
                std::printf("[furnace] PrincipledGlass %.1f/%.1f %s cos %.2f: %.5f +- %.2g\n", ar, at,
                            inside ? "inside" : "outside", kCosThetas[i], m.mean(), m.std_error());
                if (ar == 0.0f && at == 0.0f) {
                    EXPECT_NEAR(m.mean(), 1.0, 1e-5) << c;
                } else {
                    EXPECT_TRUE(st::at_most(m, 1.0)) << ar << " " << at << " " << c << ": " << m.mean();
                    EXPECT_GT(m.mean(), 0.6) << ar << " " << at << " " << c;
                    if (ar > 0.0f) {
                        EXPECT_TRUE(matches_quadrature(plain, quadrature_albedo(lobe, wo))) << ar << " " << at << " " << c;
                    }
                }
            }
}

// Its colours are Cycles 3.4's, written out again in double: the refraction the base colour, the
// reflection interpolate_fresnel_color(L, H, ior, F0, cspec0) with cspec0 = base tint + 1 - tint
// (bsdf_util.h, svm/closure.h), here smooth at normal and grazing incidence and rough off-specular.
TEST(ClosureClosedForm, PrincipledGlassColoursAreCycles) {
    auto fresnel = [](double c, double eta) {  // fresnel_dielectric_cos
        double g = eta * eta - 1.0 + c * c;
        if (g <= 0.0) return 1.0;
        g = std::sqrt(g);
        double a = (g - c) / (g + c), b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
        return 0.5 * a * a * (1.0 + b * b);
    };
    const Color base(0.9f, 0.5f, 0.2f);
    for (float tint : {0.0f, 0.4f, 1.0f})
        for (float eta : {1.45f, 1.0f / 1.45f})
            for (float cos_d : {1.0f, 0.6f, 0.1f}) {
                Lobe lobe = principled_glass_lobe(0.2f, 0.2f, base, tint, eta);
                Color got = PrincipledGlassLobe::fresnel(lobe, cos_d);
                double f0 = fresnel(1.0, eta), fh = (fresnel(cos_d, eta) - f0) / (1.0 - f0);
                for (int ch = 0; ch < 3; ++ch) {
                    double cspec0 = double(base[ch]) * tint + (1.0 - tint);
                    EXPECT_NEAR(got[ch], cspec0 * (1.0 - fh) + fh, 1e-5) << tint << " " << eta << " " << cos_d;
                    EXPECT_EQ(PrincipledGlassLobe::fresnel(lobe, -cos_d)[ch], base[ch]);
                }
            }
    // A smooth glass: value / pdf of each event is its colour (and the refraction's radiance scaling).
    Lobe smooth = principled_glass_lobe(0.0f, 0.0f, base, 1.0f);
    Vec3 wo = dir_from_cos(0.8f, 0.3f);
    BsdfSample refl = lobe_sample(smooth, wo, {0.5f, 0.5f}, 0.0f), refr = lobe_sample(smooth, wo, {0.5f, 0.5f}, 0.99f);
    ASSERT_TRUE(refl.delta && refr.delta && refr.transmission && !refl.transmission);
    for (int ch = 0; ch < 3; ++ch) {
        double f0 = fresnel(1.0, 1.5), fh = (fresnel(0.8, 1.5) - f0) / (1.0 - f0);
        EXPECT_NEAR(refl.value[ch] / refl.pdf, double(base[ch]) * (1.0 - fh) + fh, 1e-5);
        EXPECT_NEAR(refr.value[ch] / refr.pdf, base[ch] / (1.5 * 1.5), 1e-5);
    }
}

// Oren-Nayar (Cycles' form) loses energy only; sigma 0 is Lambert (all of it).
TEST(ClosureFurnace, OrenNayarLosesEnergyOnly) {
    furnace_sweep("OrenNayar", LobeKind::OrenNayar, {0.0f, 0.3f, 1.0f}, 13, [](float sigma, int, const st::MeanEstimator& is) {
        EXPECT_TRUE(st::at_most(is, 1.0)) << sigma << ": " << is.mean();
        if (sigma == 0.0f) {
            EXPECT_LE(std::fabs(st::z_test_mean(is, 1.0, 1e-5).z), 3.0) << is.mean();
        }
    });
}

// Beckmann reflection (single scattering, no Fresnel) loses energy only.
TEST(ClosureFurnace, BeckmannLosesEnergyOnly) {
    furnace_sweep("Beckmann", LobeKind::Beckmann, {0.2f, 0.6f, 1.0f}, 43, [](float alpha, int, const st::MeanEstimator& is) {
        EXPECT_TRUE(st::at_most(is, 1.0)) << alpha << ": " << is.mean();
        EXPECT_GT(is.mean(), 0.2) << alpha;
    });
}

// Velvet is not energy conserving in Cycles' form (its G is not derived from D): the check is the
// quadrature match; the albedos are printed for the README.
TEST(ClosureFurnace, VelvetMatchesQuadrature) {
    furnace_sweep("Velvet", LobeKind::Velvet, {0.2f, 0.5f, 1.0f}, 23,
                  [](float, int, const st::MeanEstimator&) {});
}

// ---------------------------------------------------------------------------------------------
// Cycles' closed forms, evaluated independently in double precision

TEST(ClosureClosedForm, OrenNayarIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    for (double sigma : {0.25, 0.8})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(kCosThetas[2 - i], kPhis[i] + 0.7f);
            double a = 1.0 / (pi + (3.0 * pi - 4.0) / 6.0 * sigma), b = sigma * a;
            double nl = wi.z, nv = wo.z, t = double(dot(wi, wo)) - nl * nv;
            if (t > 0.0) t /= std::max(nl, nv);
            double expected = nl * (a + b * t);
            Color e = lobe_eval(lobe_of(LobeKind::OrenNayar, float(sigma)), wo, wi);
            EXPECT_NEAR(e.x, expected, 1e-5 * expected + 1e-7) << sigma << " " << i;
        }
}

TEST(ClosureClosedForm, VelvetIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    for (double sigma : {0.3, 0.9})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(0.4f, kPhis[i] + 2.0f);
            Vec3 h = normalize(wo + wi);
            double cnh = h.z, cho = std::fabs(dot(wo, h));
            double r = std::max(cnh / cho, 1e-5);
            double g = std::min(1.0, std::min(2.0 * r * wo.z, 2.0 * r * wi.z));
            double s2 = 1.0 - cnh * cnh, cot2 = cnh * cnh / s2;
            double d = std::exp(-cot2 / (sigma * sigma)) / (sigma * sigma) / pi / (s2 * s2);
            double expected = 0.25 * d * g / wo.z;
            Color e = lobe_eval(lobe_of(LobeKind::Velvet, float(sigma)), wo, wi);
            EXPECT_NEAR(e.x, expected, 1e-4 * expected + 1e-7) << sigma << " " << i;
            EXPECT_FLOAT_EQ(lobe_pdf(lobe_of(LobeKind::Velvet, float(sigma)), wo, wi), float(0.5 / pi));
        }
}

TEST(ClosureClosedForm, BeckmannIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    auto g1 = [](double alpha, double c) {  // Walter 2007 eq. 27, as bsdf_beckmann_G1
        double a = 1.0 / (alpha * std::sqrt(1.0 - c * c) / c);
        return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
    };
    for (double alpha : {0.15, 0.5})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(0.6f, kPhis[i] + 2.5f);
            Vec3 m = normalize(wo + wi);
            double c2 = double(m.z) * m.z, a2 = alpha * alpha;
            double d = std::exp(-(1.0 - c2) / c2 / a2) / (pi * a2 * c2 * c2);
            double expected = d * g1(alpha, wo.z) * g1(alpha, wi.z) / (4.0 * wo.z);
            Color e = lobe_eval(lobe_of(LobeKind::Beckmann, float(alpha)), wo, wi);
            EXPECT_NEAR(e.x, expected, 1e-4 * expected + 1e-7) << alpha << " " << i;
        }
}

// Cycles' Beckmann refraction (bsdf_microfacet_beckmann_eval_transmit): D G |cos_hi cos_ho| eta^2 /
// (cos_no |eta wi + wo|^2), which ours is times the radiance scaling 1 / eta^2; and the Beckmann
// glass is the reflection weighted by F at the normal plus the refraction weighted by 1 - F.
TEST(ClosureClosedForm, BeckmannRefractionIsCyclesFormula) {
    const double pi = 3.14159265358979323846, eta = 1.5;
    auto g1 = [](double alpha, double c) {
        c = std::fabs(c);
        double a = 1.0 / (alpha * std::sqrt(1.0 - c * c) / c);
        return a >= 1.6 ? 1.0 : (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
    };
    for (double alpha : {0.15, 0.5})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(-0.7f, kPhis[i] + 2.8f);
            Vec3 ht = -(wi * float(eta) + wo);
            Vec3 m = normalize(ht);
            double c2 = double(m.z) * m.z, a2 = alpha * alpha;
            double d = std::exp(-(1.0 - c2) / c2 / a2) / (pi * a2 * c2 * c2);
            double cycles = d * g1(alpha, wo.z) * g1(alpha, wi.z) * std::fabs(dot(m, wi) * dot(m, wo)) * eta * eta /
                            (wo.z * length_sq(ht));
            Lobe refraction = lobe_of(LobeKind::Refraction, float(alpha), Color(1.0f), float(eta));
            refraction.variant = kBeckmannDistribution;
            Color e = lobe_eval(refraction, wo, wi);
            EXPECT_NEAR(e.x * eta * eta, cycles, 1e-4 * cycles + 1e-7) << alpha << " " << i;
            Lobe glass = refraction;
            glass.kind = LobeKind::Dielectric;
            double F = fresnel_dielectric(wo.z, float(eta));
            EXPECT_NEAR(lobe_eval(glass, wo, wi).x, (1.0 - F) * e.x, 1e-4 * e.x + 1e-7) << alpha << " " << i;
            Lobe beckmann = lobe_of(LobeKind::Beckmann, float(alpha));
            Vec3 wr = dir_from_cos(0.6f, kPhis[i] + 2.5f);
            EXPECT_NEAR(lobe_eval(glass, wo, wr).x, F * lobe_eval(beckmann, wo, wr).x, 1e-4 * F + 1e-7) << alpha << " " << i;
        }
}

// Cycles' toon: inside the Size cone the value is the cone's uniform density, on the Smooth ramp a
// linear fraction of it, beyond it 0.
// bsdf_microfacet.h's anisotropic GGX and Beckmann reflection, in its slope form: D from the slopes
// -m_x / (m_z alpha_x), -m_y / (m_z alpha_y), G1 at alphaO^2 = (cos^2 phi ax^2 + sin^2 phi ay^2) /
// (cos^2 phi + sin^2 phi); f cos_i = D G1(wo) G1(wi) / (4 cos_o).
TEST(ClosureClosedForm, AnisotropicIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    auto alpha_o2 = [](const Vec3& w, double ax, double ay) {
        double c2 = double(w.x) * w.x, s2 = double(w.y) * w.y;
        return (c2 * ax * ax + s2 * ay * ay) / (c2 + s2);
    };
    for (auto [ax, ay] : {std::pair{0.2, 0.6}, std::pair{0.7, 0.1}})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(0.6f, kPhis[i] + 2.5f);
            Vec3 m = normalize(wo + wi);
            double sx = -m.x / (m.z * ax), sy = -m.y / (m.z * ay), c4 = std::pow(double(m.z), 4.0);
            double tan2_o = (1.0 - double(wo.z) * wo.z) / (double(wo.z) * wo.z);
            double tan2_i = (1.0 - double(wi.z) * wi.z) / (double(wi.z) * wi.z);
            double slope_len = 1.0 + sx * sx + sy * sy;
            double d_ggx = 1.0 / (slope_len * slope_len * pi * ax * ay * c4);
            auto g1_ggx = [&](const Vec3& w, double tan2) { return 2.0 / (1.0 + std::sqrt(1.0 + alpha_o2(w, ax, ay) * tan2)); };
            double ggx = d_ggx * g1_ggx(wo, tan2_o) * g1_ggx(wi, tan2_i) / (4.0 * wo.z);
            double d_beck = std::exp(-sx * sx - sy * sy) / (pi * ax * ay * c4);
            auto g1_beck = [&](const Vec3& w, double tan2) {
                double inv_a = std::sqrt(alpha_o2(w, ax, ay) * tan2);
                if (inv_a < 0.625) return 1.0;
                double a = 1.0 / inv_a;
                return ((2.181 * a + 3.535) * a) / ((2.577 * a + 2.276) * a + 1.0);
            };
            double beck = d_beck * g1_beck(wo, tan2_o) * g1_beck(wi, tan2_i) / (4.0 * wo.z);
            Lobe l = lobe_of(LobeKind::AnisoGgx, float(ax));
            l.alpha_y = float(ay);
            EXPECT_NEAR(lobe_eval(l, wo, wi).x, ggx, 1e-4 * ggx + 1e-7) << ax << " " << i;
            l.kind = LobeKind::AnisoBeckmann;
            EXPECT_NEAR(lobe_eval(l, wo, wi).x, beck, 1e-4 * beck + 1e-7) << ax << " " << i;
        }
}

// bsdf_ashikhmin_shirley.h's eval, as Cycles writes it (its isotropic branch where n_x = n_y, else the
// exponent from H's projections on the tangent frame over 1 - (H.N)^2), value and pdf, and a roughness
// at or under 0.01 (alpha 1e-4) is Cycles' mirror.
TEST(ClosureClosedForm, AshikhminShirleyIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    auto exponent = [](double alpha) {
        alpha = std::min(std::max(alpha, 1e-4), 1.0);
        return 2.0 / (alpha * alpha) - 2.0;
    };
    for (auto [ax, ay] : {std::pair{0.3, 0.3}, std::pair{0.81, 0.81}, std::pair{0.2, 0.6}, std::pair{0.7, 0.05}})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]), wi = dir_from_cos(0.6f, kPhis[i] + 2.5f);
            Vec3 h = normalize(wo + wi);
            double n_dot_o = wo.z, n_dot_i = wi.z, h_dot_o = std::fabs(dot(h, wo)), h_dot_n = h.z;
            double pump = 1.0 / (h_dot_o * std::max(n_dot_o, n_dot_i));
            double nx = exponent(ax), ny = exponent(ay), lobe, norm;
            if (nx == ny) {
                lobe = std::pow(h_dot_n, nx);
                norm = (nx + 1.0) / (8.0 * pi);
            } else {
                double e = (nx * h.x * h.x + ny * h.y * h.y) / (1.0 - h_dot_n * h_dot_n);
                lobe = std::pow(h_dot_n, e);
                norm = std::sqrt((nx + 1.0) * (ny + 1.0)) / (8.0 * pi);
            }
            double expected = n_dot_i * norm * lobe * pump, expected_pdf = norm * lobe / h_dot_o;
            Lobe l = lobe_of(LobeKind::AshikhminShirley, float(ax));
            l.alpha_y = float(ay);
            EXPECT_NEAR(lobe_eval(l, wo, wi).x, expected, 1e-4 * expected + 1e-7) << ax << " " << ay << " " << i;
            EXPECT_NEAR(lobe_pdf(l, wo, wi), expected_pdf, 1e-4 * expected_pdf + 1e-7) << ax << " " << ay << " " << i;
        }
    Lobe mirror = lobe_of(LobeKind::AshikhminShirley, 1e-4f, Color(0.5f));
    mirror.alpha_y = 1e-4f;
    Vec3 wo = dir_from_cos(0.5f, 1.0f);
    BsdfSample s = lobe_sample(mirror, wo, {0.3f, 0.7f}, 0.5f);
    EXPECT_TRUE(s.delta && s.valid());
    EXPECT_NEAR(s.wi.z, wo.z, 1e-6f);
    EXPECT_FLOAT_EQ(s.value.x, 0.5f);
}

TEST(ClosureClosedForm, ToonIsCyclesFormula) {
    const double pi = 3.14159265358979323846;
    Lobe d = lobe_of(LobeKind::ToonDiffuse, 0.4f);  // full within 36 degrees, ramp to 36 + 27 = 63 degrees
    d.f0.x = 0.3f;
    double cone_pdf = 1.0 / (2.0 * pi * (1.0 - std::cos(0.7 * pi / 2.0)));
    Vec3 wo = dir_from_cos(0.8f, 0.0f);
    auto at = [](double deg) { return dir_from_cos(float(std::cos(deg * 3.14159265358979 / 180.0)), 1.0f); };
    EXPECT_NEAR(lobe_eval(d, wo, at(20.0)).x, cone_pdf, 1e-5 * cone_pdf);
    EXPECT_NEAR(lobe_eval(d, wo, at(50.0)).x, cone_pdf * (1.0 - (50.0 - 36.0) / 27.0), 1e-4 * cone_pdf);
    EXPECT_EQ(lobe_eval(d, wo, at(70.0)).x, 0.0f);
    EXPECT_NEAR(lobe_pdf(d, wo, at(50.0)), cone_pdf, 1e-5 * cone_pdf);
    // Glossy: the same about the mirror direction of wo.
    Lobe g = d;
    g.kind = LobeKind::ToonGlossy;
    Vec3 mirror(-wo.x, -wo.y, wo.z);
    EXPECT_NEAR(lobe_eval(g, wo, mirror).x, cone_pdf, 1e-5 * cone_pdf);
    EXPECT_EQ(lobe_eval(g, wo, dir_from_cos(0.8f, 0.0f)).x, 0.0f);  // wo itself: 74 degrees from the mirror
}

// Cycles' Hair BSDF eval (bsdf_hair.h), written as Cycles writes it with the tangent T, the normal N
// and the directions as vectors; ours works in the frame x = T, z = N. Cycles' eval returns its
// pdf as the value; where its sampler cannot reach (TT beyond |phi - pi| = pi/2) our pdf differs.
double cycles_hair_eval(bool transmission, const Vec3& T, const Vec3& N, const Vec3& I, const Vec3& wi, float r1,
                        float r2, float offset) {
    const double half_pi = kPi / 2.0;
    if (transmission ? dot(N, wi) >= 0.0f : dot(N, wi) < 0.0f) return 0.0;
    double Iz = dot(T, I);
    Vec3 locy = normalize(I - T * float(Iz));
    double theta_r = half_pi - std::acos(Iz);
    double wz = dot(T, wi);
    Vec3 wy = normalize(wi - T * float(wz));
    double theta_i = half_pi - std::acos(wz);
    double cos_phi = std::clamp(double(dot(wy, locy)), -1.0, 1.0);
    if (half_pi - std::fabs(theta_i) < 0.001 || (!transmission && cos_phi < 0.0)) return 0.0;
    double a = std::atan(((half_pi + theta_r) * 0.5 - offset) / r1);
    double b = std::atan(((-half_pi + theta_r) * 0.5 - offset) / r1);
    double t = (theta_i + theta_r) * 0.5 - offset;
    double theta_pdf = r1 / (2.0 * (t * t + double(r1) * r1) * (a - b) * std::cos(theta_i));
    if (!transmission) {
        double phi = std::min(std::acos(cos_phi) / r2, double(kPi));
        return std::cos(phi * 0.5) * 0.25 / r2 * theta_pdf;
    }
    double c = 2.0 * std::atan(half_pi / r2);
    double p = kPi - std::acos(cos_phi);
    return theta_pdf * r2 / (c * (p * p + double(r2) * r2));
}

TEST(ClosureClosedForm, HairIsCyclesFormula) {
    Rng rng(19, 3);
    const float r1 = 0.25f, r2 = 0.7f, offset = 0.06f;
    int nonzero = 0;
    for (bool transmission : {false, true}) {
        Lobe lobe = lobe_of(transmission ? LobeKind::HairTransmission : LobeKind::HairReflection, r1);
        lobe.alpha_y = r2;
        lobe.f0.x = offset;
        for (int i = 0; i < 4000; ++i) {
            Vec3 wo = sample_uniform_sphere(rand2(rng)), wi = sample_uniform_sphere(rand2(rng));
            wo.z = std::fabs(wo.z);
            double ours = lobe_eval(lobe, wo, wi).x;
            double cycles = cycles_hair_eval(transmission, Vec3(1, 0, 0), Vec3(0, 0, 1), wo, wi, r1, r2, offset);
            nonzero += cycles > 0.0;
            ASSERT_TRUE(close_rel(ours, cycles, 2e-3, 1e-5)) << transmission << " " << ours << " vs " << cycles;
        }
    }
    EXPECT_GT(nonzero, 2000);
}

// The hair lobes are their sampler's density where Cycles' eval is not zero: R keeps all but the
// back half and the part below N (value / pdf 1 or 0); TT holds more than its Cycles sampler reaches.
TEST(ClosureFurnace, HairMatchesQuadratureAndLosesEnergyOnlyInReflection) {
    for (bool transmission : {false, true})
        for (int i = 0; i < 3; ++i) {
            Lobe lobe = lobe_of(transmission ? LobeKind::HairTransmission : LobeKind::HairReflection, 0.2f);
            lobe.alpha_y = 0.8f;
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
            st::MeanEstimator is = sampled_albedo(lobe, wo, 400000, 71 + i);
            double quad = quadrature_albedo(lobe, wo);
            std::printf("[furnace] Hair %s cos %.2f: IS %.5f +- %.2g, quadrature %.5f\n", transmission ? "TT" : "R",
                        kCosThetas[i], is.mean(), is.std_error(), quad);
            EXPECT_TRUE(matches_quadrature(is, quad)) << transmission << " cos " << kCosThetas[i];
            if (!transmission) {
                EXPECT_TRUE(st::at_most(is, 1.0)) << is.mean();
            }
            EXPECT_GT(is.mean(), 0.1);
        }
}

// Cycles 3.4's longitudinal numbers of the Principled Hair sample (its shading point's LCG, seeded
// rng_hash + rng_offset + sample * scramble, rng_offset 16 per bounce): the values of Cycles'
// arithmetic (computed apart, in Python: key 12345678), and the fixed step between bounces
// (16 a^2 / 2^32, 16 a^3 / 2^32 mod 1, a the LCG's multiplier) that correlates a path's samples.
// A lobe marked kBounceLcg samples theta from them, whatever the path's own numbers.
TEST(ClosureClosedForm, PrincipledHairTakesCyclesBounceLcgNumbers) {
    Point2 d0 = principled_hair::cycles_bounce_lcg(12345678u, 0), d1 = principled_hair::cycles_bounce_lcg(12345678u, 1);
    EXPECT_NEAR(d0.x, 0.30149186f, 1e-6f);
    EXPECT_NEAR(d0.y, 0.05706831f, 1e-6f);
    EXPECT_NEAR(d1.x, 0.46618989f, 1e-6f);
    EXPECT_NEAR(d1.y, 0.08776585f, 1e-6f);
    auto frac = [](float v) { return v - std::floor(v); };
    for (uint32_t key : {1u, 977u, 0xdeadbeefu})
        for (int depth : {0, 3}) {
            Point2 a = principled_hair::cycles_bounce_lcg(key, depth), b = principled_hair::cycles_bounce_lcg(key, depth + 1);
            EXPECT_NEAR(frac(b.x - a.x + 1.0f), 0.16469804f, 2e-6f) << key;
            EXPECT_NEAR(frac(b.y - a.y + 1.0f), 0.03069754f, 2e-6f) << key;
        }
    Lobe l = lobe_of(LobeKind::PrincipledHairTRT, 0.1f, Color(0.5f), 1.55f);
    l.alpha_y = 0.3f;
    l.variant = PrincipledHairTRTLobe::kBounceLcg;
    l.kind_colour = Color(d0.x, d0.y, 0.0f);
    Vec3 wo = dir_from_cos(0.6f, 0.4f);
    BsdfSample s1 = lobe_sample(l, wo, Point2{0.1f, 0.7f}, 0.2f), s2 = lobe_sample(l, wo, Point2{0.9f, 0.7f}, 0.8f);
    ASSERT_TRUE(s1.valid() && s2.valid());
    EXPECT_NEAR(s1.wi.x, s2.wi.x, 1e-6f);  // theta from the LCG; phi (u.y) the same here
}

// Under hair_cycles_sampling (kBounceLcg) the lobes return Cycles' pdf, M_p N_p at the tilted
// angle (bsdf_principled_hair_sample's F_energy), so every sample's value / pdf is the lobe's weight
// as in Cycles' estimator; by default pdf() is the sampler's density, which the tilt makes differ by
// cos(theta') / cos(theta_i).
TEST(ClosureClosedForm, PrincipledHairCyclesSamplingTakesCyclesPdf) {
    Rng rng(5, 0);
    const float tilt = 0.035f;
    int differs = 0;
    for (int p = 0; p < 3; ++p) {
        const float tilts[3] = {-2.0f * tilt, tilt, 4.0f * tilt};
        Lobe l = lobe_of(LobeKind(int(LobeKind::PrincipledHairR) + p), 0.1f, Color(0.4f), 1.55f);
        l.alpha_y = 0.3f;
        l.f0.x = tilts[p];
        Lobe cycles = l;
        cycles.variant = PrincipledHairRLobe::kBounceLcg;
        for (int i = 0; i < 300; ++i) {
            Vec3 wo = sample_uniform_sphere(rand2(rng));
            Point2 lcg = rand2(rng);
            cycles.kind_colour = Color(lcg.x, lcg.y, 0.0f);
            Point2 u = rand2(rng);
            BsdfSample s = lobe_sample(cycles, wo, u, 0.5f);
            if (!s.valid()) continue;
            ASSERT_TRUE(close_rel(s.value.x / s.pdf, 0.4, 1e-3, 1e-6)) << p << " " << s.value.x / s.pdf;
            float density = lobe_pdf(l, wo, s.wi);
            differs += std::fabs(density / s.pdf - 1.0f) > 1e-3f;
        }
    }
    EXPECT_GT(differs, 300);
}

// Chiang et al.'s model keeps all the energy of a fibre that absorbs nothing: its paths' A_p sum to 1
// (Fresnel f, (1 - f)^2, (1 - f)^2 f, and the closed sum of the rest) and each path's M_p N_p is a
// density, so the four lobes of a closure with sigma = 0 reflect or transmit all of a white furnace:
// checked by quadrature of eval() (the lobes' normalisation) and by their samples. With the cuticle
// tilt, Cycles' M_p is evaluated at the tilted angle without the change of measure, so a white
// furnace gains or loses a little, most at grazing wo (+4.5% at cos 0.05 for 2 degrees).
TEST(ClosureFurnace, PrincipledHairWithoutAbsorptionConservesEnergy) {
    for (float tilt : {0.0f, 0.035f})
        for (int i = 0; i < 3; ++i) {
            Vec3 wo = dir_from_cos(kCosThetas[i], kPhis[i]);
            float abs_h = std::fabs(wo.y) / std::sqrt(wo.y * wo.y + wo.z * wo.z);
            principled_hair::Attenuation at = principled_hair::attenuation(wo.x, abs_h, 1.55f, Color(0.0f));
            const float v = 0.12f, v_p[4] = {v, 0.25f * v, 4.0f * v, 4.0f * v};
            const float tilts[4] = {-2.0f * tilt, tilt, 4.0f * tilt, 0.0f};
            double sampled = 0.0, var = 0.0, quad = 0.0, attenuation_sum = 0.0;
            for (int p = 0; p < 4; ++p) {
                Lobe l = lobe_of(LobeKind(int(LobeKind::PrincipledHairR) + p), v_p[p], at.a[p], 1.55f);
                l.alpha_y = 0.3f;
                l.f0.x = tilts[p];
                st::MeanEstimator is = sampled_albedo(l, wo, 100000, 91 + 4 * i + p);
                sampled += is.mean();
                var += sqr(is.std_error());
                quad += quadrature_albedo(l, wo);
                attenuation_sum += average(at.a[p]);
            }
            std::printf("[furnace] Principled Hair sigma 0 tilt %.3f cos %.2f: sampled %.5f +- %.2g, quadrature %.5f "
                        "(A_p sum %.6f)\n", tilt, kCosThetas[i], sampled, std::sqrt(var), quad, attenuation_sum);
            EXPECT_NEAR(attenuation_sum, 1.0, 1e-5);
            EXPECT_NEAR(quad, sampled, 3.0 * std::sqrt(var) + 5e-3) << "cos " << kCosThetas[i];
            EXPECT_NEAR(sampled, 1.0, tilt == 0.0f ? 3.0 * std::sqrt(var) + 1e-4 : 0.05) << "cos " << kCosThetas[i];
        }
}

TEST(ClosureClosedForm, TranslucentIsLambertThrough) {
    Lobe lobe = lobe_of(LobeKind::Translucent, 0.0f, Color(0.5f));
    Vec3 wo = dir_from_cos(0.7f, 0.2f);
    EXPECT_NEAR(lobe_eval(lobe, wo, dir_from_cos(-0.6f, 1.0f)).x, 0.5 * 0.6 / 3.14159265358979, 1e-6);
    EXPECT_EQ(lobe_eval(lobe, wo, dir_from_cos(0.6f, 1.0f)).x, 0.0f);  // no reflection
}

// ---------------------------------------------------------------------------------------------
// The interface

TEST(LobeInterface, EveryKindHasItsName) {
    int kinds = 0;
    for_each_lobe_kind([&](auto k) {
        using L = decltype(k);
        LobeKind back = LobeKind::Count;
        EXPECT_TRUE(lobe_kind_from_name(L::kName, &back)) << L::kName;
        EXPECT_EQ(back, L::kKind) << L::kName;
        EXPECT_EQ(int(L::kKind), kinds) << L::kName << ": AllLobeKinds is not in LobeKind order";
        ++kinds;
    });
    EXPECT_EQ(kinds, int(LobeKind::Count));
    LobeKind k;
    EXPECT_FALSE(lobe_kind_from_name("no_such_lobe", &k));
}

TEST(LobeInterface, NewLobesStayFinite) {
    Rng rng(5, 5);
    for (const NamedLobe& nl : new_lobes())
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sample_uniform_sphere(rand2(rng)), wi = sample_uniform_sphere(rand2(rng));
            if (i % 7 == 0) wo = normalize(Vec3(1.0f, 0.0f, 1e-7f));  // grazing
            if (i % 11 == 0) wi = normalize(wo + Vec3(0, 0, 1e-6f));  // half vector at the normal
            Color e = lobe_eval(nl.lobe, wo, wi);
            float p = lobe_pdf(nl.lobe, wo, wi);
            ASSERT_TRUE(is_finite(e) && e.x >= 0.0f && std::isfinite(p) && p >= 0.0f) << nl.name;
            BsdfSample s = lobe_sample(nl.lobe, wo, rand2(rng), rng.next_float());
            ASSERT_TRUE(!s.valid() || (is_finite(s.value) && s.value.x >= 0.0f)) << nl.name;
        }
}

}  // namespace
