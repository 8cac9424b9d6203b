// The lobes of Cycles' closures added for issue 19 (scene/lobes/: oren_nayar.h, velvet.h, translucent.h,
// refraction.h, beckmann.h), in bsdf_test.cpp's style:
//  1. chi-square of sample() against pdf() (stats.h), Sidak-corrected over this file's cases;
//  2. sample() / eval() / pdf() agreement;
//  3. white furnace: the importance-sampled albedo against quadrature of eval(), and exact energy
//     conservation where the lobe conserves it (Translucent; smooth Refraction of a white glass);
//  4. the closed forms of Cycles 3.4's kernels at hand-picked directions (bsdf_oren_nayar.h,
//     bsdf_ashikhmin_velvet.h, bsdf_diffuse.h, bsdf_microfacet.h's Beckmann), written out again here
//     in double precision;
//  5. the lobe interface: every kind has a name that maps back to it, and its routines stay finite.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;

namespace {

constexpr uint64_t kChi2Samples = 1000000;
constexpr double kFamilySignificance = 0.01;
const float kCosThetas[] = {0.95f, 0.5f, 0.05f};
const float kPhis[] = {0.3f, 1.9f, 4.0f};

Point2 rand2(Rng& rng) { return {rng.next_float(), rng.next_float()}; }

Vec3 dir_from_cos(float cos_theta, float phi) {
    float s = safe_sqrt(1.0f - cos_theta * cos_theta);
    return normalize(Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta));
}

Lobe lobe_of(LobeKind kind, float param, Color weight = Color(1.0f), float eta = 1.5f) {
    Lobe l;
    l.kind = kind;
    l.alpha = param;
    l.weight = weight;
    l.eta = eta;
    return l;
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    std::string s;
    for (char c : std::string(buf)) s += c == '.' ? 'p' : (c == '-' ? 'm' : c);
    return s;
}

bool close_rel(double a, double b, double rel = 1e-3, double abs_floor = 1e-7) {
    return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs_floor;
}

// The new lobes with the parameters the tests sweep (name, lobe, whether wo may be under the surface).
struct NamedLobe {
    std::string name;
    Lobe lobe;
    bool two_sided = false;
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
    for (float alpha : {0.1f, 0.5f})
        v.push_back({"Refraction_a" + num(alpha), lobe_of(LobeKind::Refraction, alpha, Color(0.9f, 1.0f, 0.8f), 1.5f),
                     true});
    return v;
}

struct Chi2Case {
    std::string name;
    std::function<st::DirSample(Rng&)> sample;
    std::function<double(const Vec3&)> pdf;
};

std::vector<Chi2Case> build_chi2_cases() {
    std::vector<Chi2Case> cases;
    for (const NamedLobe& nl : new_lobes())
        for (int i = 0; i < (nl.two_sided ? 6 : 3); ++i) {
            Lobe lobe = nl.lobe;
            // wo inside the glass for i >= 3, inside the critical angle (cos 0.745 at eta 1.5): beyond it
            // almost every sample is totally reflected, and a histogram of the rest would be vacuous.
            const float inside_cos[] = {0.95f, 0.85f, 0.8f};
            float c = i < 3 ? kCosThetas[i] : -inside_cos[i - 3];
            Vec3 wo = dir_from_cos(c, kPhis[i % 3]);
            cases.push_back({nl.name + "_cos" + num(c),
                             [lobe, wo](Rng& rng) {
                                 Point2 u = rand2(rng);
                                 BsdfSample s = lobe_sample(lobe, wo, u, rng.next_float());
                                 if (!s.valid()) return st::DirSample::invalid();
                                 if (s.delta) return st::DirSample::delta();
                                 return st::DirSample::valid(s.wi, s.pdf);
                             },
                             [lobe, wo](const Vec3& wi) { return double(lobe_pdf(lobe, wo, wi)); }});
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
    st::Chi2Options opt;
    opt.seed = 0x5150 + GetParam();
    st::Chi2Result r = st::chi2_test_directions(c.sample, c.pdf, kChi2Samples, opt);
    double alpha = st::sidak_significance(kFamilySignificance, static_cast<int>(chi2_cases().size()));
    std::printf("[chi2] %-40s %s\n", c.name.c_str(), r.summary().c_str());
    EXPECT_TRUE(r.passes(alpha)) << c.name << ": " << r.summary() << "\n" << r.residual_map();
    EXPECT_GT(r.n_valid, kChi2Samples / 10) << c.name;
}

INSTANTIATE_TEST_SUITE_P(All, ClosureChi2, ::testing::Range(0, static_cast<int>(chi2_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) { return chi2_cases()[info.param].name; });

TEST(ClosureConsistency, SampleAgreesWithEvalAndPdf) {
    Rng rng(7, 19);
    for (const NamedLobe& nl : new_lobes()) {
        int valid = 0, mismatches = 0;
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sample_uniform_sphere(rand2(rng));
            if (!nl.two_sided) wo.z = std::fabs(wo.z);
            BsdfSample s = lobe_sample(nl.lobe, wo, rand2(rng), rng.next_float());
            if (!s.valid()) continue;
            ++valid;
            Color e = lobe_eval(nl.lobe, wo, s.wi);
            float p = lobe_pdf(nl.lobe, wo, s.wi);
            bool ok = !s.delta && close_rel(s.value.x, e.x) && close_rel(s.value.y, e.y) && close_rel(s.value.z, e.z) &&
                      close_rel(s.pdf, p) && std::fabs(length(s.wi) - 1.0f) < 1e-4f &&
                      s.transmission == (s.wi.z * wo.z < 0.0f);
            mismatches += !ok;
        }
        EXPECT_EQ(mismatches, 0) << nl.name;
        EXPECT_GT(valid, 5000) << nl.name;
    }
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

// Cycles' toon: inside the Size cone the value is the cone's uniform density, on the Smooth ramp a
// linear fraction of it, beyond it 0.
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
