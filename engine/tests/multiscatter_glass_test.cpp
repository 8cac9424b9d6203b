// Multiscatter GGX glass (scene/lobes/multi_glass.h, glass_multiple.h, scene/ggx_glass.h), in
// closure_lobes_test.cpp's style:
//  1. chi-square of sample() against pdf() for both lobes, wo outside and inside (eta and 1 / eta),
//     Sidak-corrected over this file's cases;
//  2. sample() / eval() / pdf() agreement;
//  3. white furnace: the pair as the compiler builds it keeps what Cycles' dielectric walk keeps
//     (scene/ggx_walk.h, glass_walk), reflection and transmission together, from both sides, and at
//     least 95% at roughness 1 (issue 19);
//  4. the table against fresh walks between its nodes: each side's albedo, mean cosine and colour,
//     and the analytic single scattering against the walks' one-bounce part;
//  5. the settings that act on closures: Cycles keeps its one multiscatter glass closure whole when
//     one caustics toggle is off, and Filter Glossy re-reads the multiple scattering at the new alpha.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "scene/ggx_glass.h"
#include "scene/ggx_walk.h"
#include "scene/lobe_ray_types.h"
#include "lobe_checks.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using lobe_checks::Chi2Case;
using lobe_checks::dir_from_cos;
using lobe_checks::NamedLobe;
using lobe_checks::rand2;
using st::num;

namespace {

// The pair for a Glass BSDF of colour c (variant kPerBounce) or a Principled base c (kPerRefraction).
struct Pair {
    Lobe single, multiple;
    bool has_multiple = false;
};
Pair glass_pair(float rough, float eta, Color c = Color(1.0f), uint8_t variant = GlassMultipleLobe::kPerBounce) {
    Pair p;
    p.single.kind = LobeKind::MultiGlass;
    p.single.alpha = rough * rough;
    p.single.eta = eta;
    p.single.weight = variant == GlassMultipleLobe::kPerBounce ? c : Color(1.0f);
    p.single.f0 = variant == GlassMultipleLobe::kPerBounce ? Color(1.0f) : c;
    p.has_multiple = glass_multiple_lobe(p.single, c, variant, &p.multiple);
    return p;
}


std::vector<NamedLobe> glass_lobes() {
    std::vector<NamedLobe> v;
    for (float rough : {0.3f, 0.7f, 1.0f})
        for (float eta : {1.45f, 1.0f / 1.45f}) {
            Pair p = glass_pair(rough, eta, Color(0.9f, 0.7f, 0.5f), GlassMultipleLobe::kPerRefraction);
            p.single.kind_colour.x = 0.5f;  // a Specular Tint
            v.push_back({"MultiGlass_r" + num(rough) + "_eta" + num(eta), p.single});
            if (p.has_multiple) v.push_back({"GlassMultiple_r" + num(rough) + "_eta" + num(eta), p.multiple});
        }
    return v;
}

// Each lobe from views high, middle and grazing and from inside.
const std::vector<Chi2Case>& all_chi2_cases() {
    static const std::vector<Chi2Case> cases = lobe_checks::chi2_cases_of(glass_lobes(), {{0.95f, 0.3f}, {0.5f, 1.9f}, {0.1f, 4.0f}, {-0.7f, 2.5f}});
    return cases;
}

class MultiGlassChi2 : public ::testing::TestWithParam<int> {};

TEST_P(MultiGlassChi2, SampleMatchesPdf) {
    const Chi2Case& c = all_chi2_cases()[GetParam()];
    lobe_checks::expect_sampling_matches_pdf(c.name, c.lobe, c.wo, 0x6150 + GetParam(), 400000,
                                             static_cast<int>(all_chi2_cases().size()));
}

INSTANTIATE_TEST_SUITE_P(All, MultiGlassChi2, ::testing::Range(0, static_cast<int>(all_chi2_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) { return all_chi2_cases()[info.param].name; });

TEST(MultiGlassConsistency, SampleAgreesWithEvalAndPdf) {
    Rng rng(7, 29);
    for (const NamedLobe& nl : glass_lobes())
        lobe_checks::expect_sample_agrees_with_eval(
            nl.name, nl.lobe, rng, true,
            [](const Vec3&, const BsdfSample& s) { return !s.transmission || s.eta != 1.0f; });
}

// Fresh walks from wo (z > 0) at relative IOR eta: per side (0 reflected, 1 transmitted), the
// fractions leaving after one bounce and after more, the mean |cos| of the latter, and their colour
// with c at each further bounce (the Glass BSDF) or at each refraction (the Principled BSDF), and the
// Principled colour with Specular Tint 1: also, at each reflection, Cycles' interpolated Fresnel colour
// FH + (1 - FH) c at its microfacet (mf_sample's interpolate_fresnel_color, cspec0 = c).
struct SideStats {
    st::MeanEstimator single, multiple, cos_multiple, per_bounce, per_refraction, tinted;
};
struct GlassWalkStats {
    SideStats side[2];
};
GlassWalkStats glass_walk_stats(const Vec3& wo, float alpha, float eta, float c, int n, uint32_t seed) {
    std::mt19937 gen(seed);
    auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
    GlassWalkStats w;
    const double f0 = ggx_walk::dielectric_fresnel(1.0f, eta);
    for (int k = 0; k < n; ++k) {
        double tinted = 1.0;
        ggx_walk::GlassExit x = ggx_walk::glass_walk(wo, alpha, eta, rand, [&](float cos_i, bool refracted) {
            double fh = (ggx_walk::dielectric_fresnel(cos_i, eta) - f0) / (1.0 - f0);
            tinted *= refracted ? c : fh + (1.0 - fh) * c;
        });
        int s = x.dir.z > 0.0f ? 0 : 1;
        bool multiple = x.bounces >= 2;
        for (int side = 0; side < 2; ++side) {
            bool here = x.bounces > 0 && side == s;
            SideStats& ss = w.side[side];
            ss.single.add(here && x.bounces == 1 ? 1.0 : 0.0);
            ss.multiple.add(here && multiple ? 1.0 : 0.0);
            ss.per_bounce.add(here && multiple ? std::pow(double(c), x.bounces - 1) : 0.0);
            ss.per_refraction.add(here && multiple ? std::pow(double(c), x.refractions) : 0.0);
            ss.tinted.add(here && multiple ? tinted : 0.0);
            if (here && multiple) ss.cos_multiple.add(std::fabs(x.dir.z));
        }
    }
    return w;
}

// The pair as the renderer samples it (one Bsdf, lobe selection by weight): the energy it keeps from
// wo, with each refracted sample's radiance scaling (eta_i / eta_t)^2 undone, so that a lossless
// interface keeps exactly 1.
st::MeanEstimator pair_energy(const Pair& p, const Vec3& wo, int n, uint64_t seed) {
    Bsdf bsdf(Frame(), Vec3(0, 0, 1));
    bsdf.add(p.single);
    if (p.has_multiple) bsdf.add(p.multiple);
    Rng rng(seed, 3);
    st::MeanEstimator m;
    for (int k = 0; k < n; ++k) {
        BsdfSample s = bsdf.sample(wo, rand2(rng), rng.next_float());
        m.add(s.valid() ? average(s.value) / s.pdf * (s.transmission ? s.eta * s.eta : 1.0f) : 0.0);
    }
    return m;
}

// Issue 19: multiscatter GGX glass at roughness 1 keeps at least 95% of a white furnace's energy,
// reflection and transmission together, from both sides; at every roughness what the walk keeps.
TEST(MultiGlassFurnace, KeepsTheWalksEnergyFromBothSides) {
    const float cosines[] = {0.95f, 0.5f, 0.15f};
    for (float rough : {0.5f, 1.0f})
        for (float eta : {1.45f, 1.0f / 1.45f, 2.2f})
            for (int i = 0; i < 3; ++i) {
                Pair p = glass_pair(rough, eta);
                ASSERT_TRUE(p.has_multiple);
                Vec3 wo = dir_from_cos(cosines[i], 0.7f);
                st::MeanEstimator pair = pair_energy(p, wo, 200000, 11 + i);
                GlassWalkStats w = glass_walk_stats(wo, p.single.alpha, eta, 1.0f, 200000, 5 + i);
                double walk = w.side[0].single.mean() + w.side[0].multiple.mean() + w.side[1].single.mean() +
                              w.side[1].multiple.mean();
                std::printf("[furnace] MultiGlass rough %.1f eta %.3f cos %.2f: pair %.5f +- %.2g, walk %.5f\n", rough,
                            eta, cosines[i], pair.mean(), pair.std_error(), walk);
                EXPECT_NEAR(pair.mean(), walk, 0.01) << rough << " " << eta << " " << cosines[i];
                if (rough == 1.0f) {
                    EXPECT_GE(pair.mean(), 0.95) << eta << " " << cosines[i];
                }
            }
}

// The table between its nodes (roughness 0.75, eta 1.4 and 1 / 1.4, cos 0.7) against fresh walks:
// each side's multiple-scattering albedo and mean |cos| (the lobe's shape), its colour (c = 0.7 per
// bounce, the Glass BSDF; per refraction, the Principled BSDF, untinted and with Specular Tint 1, whose
// reflections Cycles' walk colours too), and the analytic single scattering per side against the
// walks' one-bounce part.
TEST(MultiGlassFurnace, TableIsTheWalk) {
    float alpha = 0.75f * 0.75f;
    Vec3 wo = dir_from_cos(0.7f, 0.4f);
    for (float eta : {1.4f, 1.0f / 1.4f}) {
        GlassWalkStats w = glass_walk_stats(wo, alpha, eta, 0.7f, 400000, 77);
        for (int model = 0; model < 3; ++model) {  // Glass; Principled; Principled with Specular Tint 1
            uint8_t variant = model == 0 ? GlassMultipleLobe::kPerBounce : GlassMultipleLobe::kPerRefraction;
            Pair p = glass_pair(0.75f, eta, Color(0.7f), variant);
            ASSERT_TRUE(p.has_multiple);
            p.single.kind_colour.x = p.multiple.kind_colour.x = model == 2 ? 1.0f : 0.0f;
            for (int side = 0; side < 2; ++side) {
                auto on_side = [&](const Vec3& wi) { return (wi.z > 0.0f) == (side == 0); };
                const SideStats& ss = w.side[side];
                double table = ggx_glass_multiple_albedo(wo.z, alpha, eta, side);
                double energy = st::integrate_sphere([&](const Vec3& wi) {
                    return on_side(wi) ? double(ggx_glass_multiple_bsdf(wo, wi, alpha, eta)) * std::fabs(wi.z) : 0.0;
                });
                double first = st::integrate_sphere([&](const Vec3& wi) {
                    return on_side(wi) ? double(ggx_glass_multiple_bsdf(wo, wi, alpha, eta)) * sqr(wi.z) : 0.0;
                });
                // The multiple lobe's colour on this side: its albedo there (radiance scaling undone) over
                // the white table's, over the closure weight.
                double scale = side == 1 ? double(eta) * eta : 1.0;
                double lobe = st::integrate_sphere([&](const Vec3& wi) {
                    return on_side(wi) ? double(average(lobe_eval(p.multiple, wo, wi))) : 0.0;
                }) * scale;
                double weight = variant == GlassMultipleLobe::kPerBounce ? 0.7 : 1.0;
                double tint = lobe / energy / weight;
                const st::MeanEstimator& colour = model == 0 ? ss.per_bounce : model == 1 ? ss.per_refraction : ss.tinted;
                double walk_tint = colour.mean() / ss.multiple.mean();
                double single = st::integrate_sphere([&](const Vec3& wi) {
                    return on_side(wi) ? double(average(lobe_eval(p.single, wo, wi))) : 0.0;
                }) * scale / (variant == GlassMultipleLobe::kPerBounce ? 0.7 : (side == 1 ? 0.7 : 1.0));
                std::printf("[walk] eta %.3f model %d side %d: multiple %.5f (table %.5f, lobe %.5f), mean cos %.4f "
                            "(lobe %.4f), colour %.4f (lobe %.4f), single %.5f (lobe %.5f)\n",
                            eta, model, side, ss.multiple.mean(), table, energy, ss.cos_multiple.mean(), first / energy,
                            walk_tint, tint, ss.single.mean(), single);
                EXPECT_NEAR(table, ss.multiple.mean(), 0.03 * ss.multiple.mean() + 1e-3);
                EXPECT_NEAR(energy, ss.multiple.mean(), 0.03 * ss.multiple.mean() + 1e-3);
                EXPECT_NEAR(first / energy, ss.cos_multiple.mean(), 0.015);
                EXPECT_NEAR(tint, walk_tint, 0.02);
                if (model < 2) {
                    EXPECT_NEAR(single, ss.single.mean(), 0.01 * ss.single.mean() + 2e-3);
                }
            }
        }
    }
}

TEST(MultiGlassSettings, CausticsTogglesKeepTheClosureWholeAndFilterGlossyBlursBoth) {
    Pair p = glass_pair(0.5f, 1.45f);
    ASSERT_TRUE(p.has_multiple);
    for (const Lobe& l : {p.single, p.multiple}) {
        EXPECT_FALSE(lobe_is_caustic(l, true, false));
        EXPECT_FALSE(lobe_is_caustic(l, false, true));
        EXPECT_TRUE(lobe_is_caustic(l, true, true));
        Lobe half = l;
        glass_half_left(half, true, false);
        EXPECT_EQ(half.glass_events, kGlassBoth);  // both events stay: no single half of the closure
        EXPECT_EQ(lobe_ray_types(l), kRayTransmission);
    }
    // Filter Glossy: alpha raised on both lobes; the multiple scattering's energy is the table's at the
    // new alpha (its weight's albedo divided out again), as Cycles' walk at the blurred roughness.
    Lobe single = p.single, multiple = p.multiple;
    blur_lobe(single, 0.81f);
    blur_lobe(multiple, 0.81f);
    EXPECT_EQ(single.alpha, 0.81f);
    EXPECT_EQ(multiple.alpha, 0.81f);
    Vec3 wo = dir_from_cos(0.6f, 0.2f);
    double blurred = st::integrate_sphere([&](const Vec3& wi) {
        return double(average(lobe_eval(multiple, wo, wi))) * (wi.z < 0.0f ? 1.45 * 1.45 : 1.0);
    });
    double table = ggx_glass_multiple_albedo(wo.z, 0.81f, 1.45f, 0) + ggx_glass_multiple_albedo(wo.z, 0.81f, 1.45f, 1);
    EXPECT_NEAR(blurred, table, 0.01 * table);
    EXPECT_GT(table, 1.5 * (ggx_glass_multiple_albedo(wo.z, 0.25f, 1.45f, 0) + ggx_glass_multiple_albedo(wo.z, 0.25f, 1.45f, 1)));
}

}  // namespace
