// Cycles' own Multiscatter GGX glass estimator (the setting multiscatter_cycles_walk,
// lobes/multi_glass_walk.h, scene/ggx_glass_walk.h), checked against the walks it is built on:
//  1. where Cycles' eval does not swap the directions (the light steeper than the view), its next-event
//     estimates are the exit density of the walk it runs, which mirrors the height at each refraction
//     (mf_eval; its sampled walk mf_sample does not): over those light directions the white eval
//     integrates to the fraction of such walks leaving there, on both sides of the interface (those
//     whose last bounce refracted counted 1 / eta^2: Cycles' refraction phase lacks that Jacobian);
//  2. the Principled glass' Fresnel-coloured eval (its order 0 a one-sample estimate at the first
//     height) has the analytic order 0's expectation when its colours are white;
//  3. the lobe: sampled weight = the walk's colour product (a power of the Glass BSDF's colour), pdf() =
//     Cycles' mf_glass_pdf, the same from the back face at the inverted IOR, the eval deterministic;
//  4. a white glass furnace of the sampled walk: all the light but the walks that die after 10 bounces.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <tuple>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "scene/ggx_glass_walk.h"
#include "scene/lobes/multi_glass_walk.h"
#include "lobe_checks.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using lobe_checks::dir_from_cos;

namespace {

Lobe glass_walk_lobe(float roughness, float eta, Color c = Color(1.0f), uint8_t variant = 0, float tint = 0.0f) {
    Lobe l;
    l.kind = LobeKind::MultiGlassWalk;
    l.alpha = roughness * roughness;
    l.eta = eta;
    l.weight = c;
    l.f0 = c;
    l.variant = variant;
    l.kind_colour.x = tint;
    return l;
}

struct Rand {
    Rng& rng;
    float operator()() { return rng.next_float(); }
};

// The walk Cycles' eval runs (mf_eval_glass): glass_walk's, but the height mirrored at each refraction.
// Returns where it left (z < 0: through), or z = 0 when it died. *weight: what Cycles' next-event
// estimate of its last bounce counts of it, 1 after a reflection and 1 / eta^2 after a refraction at
// relative IOR eta (Cycles' refraction phase lacks the eta^2 of the refracted direction's density).
Vec3 mirrored_glass_walk(const Vec3& wi, float alpha, float eta, Rng& rng, float* weight) {
    using namespace ggx_walk;
    State s;
    s.dir = -wi;
    s.lam = lambda(s.dir, alpha);
    bool outside = true;
    *weight = 1.0f;
    for (int bounces = 0; bounces < kMaxBounces; ++bounces) {
        if (!next_height(&s, rng.next_float())) return outside ? s.dir : -s.dir;
        float uy = rng.next_float(), ux = rng.next_float();
        Vec3 back = -s.dir;
        Vec3 wm = visible_normal(back, alpha, ux, uy);
        float rel = outside ? eta : 1.0f / eta;
        float cos_i = dot(back, wm);
        if (rng.next_float() < dielectric_fresnel(cos_i, rel)) {
            s.dir = wm * (2.0f * cos_i) - back;
            *weight = 1.0f;
        } else {
            *weight = 1.0f / (rel * rel);
            float inv = 1.0f / rel;
            float cos_t = -safe_sqrt(1.0f - (1.0f - cos_i * cos_i) * inv * inv);
            s.dir = -normalize(wm * (cos_i * inv + cos_t) - back * inv);
            outside = !outside;
            s.cdf = height_cdf(-height_of_cdf(s.cdf));
        }
        s.lam = lambda(s.dir, alpha);
        s.escape = escape_probability(s.dir, s.cdf, s.lam);
    }
    return Vec3(0.0f);
}

// Light directions where Cycles' eval walks from the view: at least as steep as the view on their side.
bool unswapped(const Vec3& view, const Vec3& light) { return std::fabs(light.z) >= view.z; }

}  // namespace

TEST(MultiGlassWalk, EvalIsItsWalkWhereTheViewIsShallower) {
    const ggx_walk::GlassColours white;
    for (float roughness : {0.6f, 1.0f}) {
        for (float eta : {1.45f, 1.0f / 1.45f}) {
            for (float cos_v : {0.3f, 0.7f}) {
                const float alpha = roughness * roughness;
                Vec3 view = dir_from_cos(cos_v, 0.4f);
                Rng rng(17, uint64_t(1000 * roughness + 100 * eta + 10 * cos_v));
                const int n = 300000;
                st::MeanEstimator reflected_eval, through_eval, reflected_walks, through_walks;
                for (int i = 0; i < n; ++i) {
                    // The light uniform over the sphere: eval / (1 / 4 pi).
                    Vec3 light = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                    double e = 0.0;
                    if (unswapped(view, light)) {
                        Rand r{rng};
                        e = 4.0 * st::kPiD * ggx_walk::cycles_glass_eval(view, light, alpha, eta, white, r).x;
                    }
                    reflected_eval.add(light.z > 0.0f ? e : 0.0);
                    through_eval.add(light.z < 0.0f ? e : 0.0);
                    float w;
                    Vec3 exit = mirrored_glass_walk(view, alpha, eta, rng, &w);
                    bool counted = exit.z != 0.0f && unswapped(view, exit);
                    reflected_walks.add(counted && exit.z > 0.0f ? w : 0.0);
                    through_walks.add(counted && exit.z < 0.0f ? w : 0.0);
                }
                // Within 1% beyond the noise: the walk samples visible normals through Heitz's rational
                // approximation (ggx_walk::sample_unit_slopes, as Cycles), the eval's phase has the exact D.
                for (auto [eval, walks, side] : {std::tuple{&reflected_eval, &reflected_walks, "reflected"},
                                                 std::tuple{&through_eval, &through_walks, "through"}}) {
                    st::ZTest z = st::z_test_difference(*eval, *walks, 0.01 * walks->mean() + 1e-4);
                    std::printf("roughness %.1f eta %.3f cos_view %.1f %-9s: eval %.4f +- %.4f, walks %.4f +- %.4f (z %.2f)\n",
                                roughness, eta, cos_v, side, eval->mean(), eval->std_error(), walks->mean(),
                                walks->std_error(), z.z);
                    EXPECT_GT(z.p_value, 1e-4) << roughness << " " << eta << " " << cos_v << " " << side;
                }
            }
        }
    }
}

TEST(MultiGlassWalk, FresnelColouredOrderZeroHasTheAnalyticExpectation) {
    ggx_walk::GlassColours plain, fresnel;
    fresnel.fresnel = true;  // white cspec0 and colour: every Fresnel colour is 1
    fresnel.eta = 1.45f;
    const float alpha = 0.49f;
    for (float cos_l : {0.5f, 0.9f}) {
        Vec3 view = dir_from_cos(0.4f, 0.0f), light = dir_from_cos(cos_l, 2.5f);
        Rng rng(3, uint64_t(10 * cos_l));
        st::MeanEstimator a, b;
        for (int i = 0; i < 200000; ++i) {
            Rand r{rng};
            a.add(ggx_walk::cycles_glass_eval(view, light, alpha, 1.45f, plain, r).x);
            b.add(ggx_walk::cycles_glass_eval(view, light, alpha, 1.45f, fresnel, r).x);
        }
        st::ZTest z = st::z_test_difference(a, b);
        std::printf("cos_light %.1f: analytic order 0 %.5f +- %.5f, one-sample %.5f +- %.5f (z %.2f)\n", cos_l,
                    a.mean(), a.std_error(), b.mean(), b.std_error(), z.z);
        EXPECT_GT(z.p_value, 1e-4) << cos_l;
    }
}

TEST(MultiGlassWalk, LobeIsCyclesEstimator) {
    const Color c(0.9f, 0.7f, 0.5f);
    for (float eta : {1.45f, 2.0f}) {
        Lobe lobe = glass_walk_lobe(0.8f, eta, c);
        Rng rng(5, uint64_t(eta * 10));
        int valid = 0, through = 0;
        for (int i = 0; i < 20000; ++i) {
            // Both faces: from below the lobe sees the inverted IOR.
            float side = i % 2 ? -1.0f : 1.0f;
            Vec3 wo = dir_from_cos(0.1f + 0.9f * rng.next_float(), 2.0f * kPi * rng.next_float()) * side;
            BsdfSample bs = lobe_sample(lobe, wo, {rng.next_float(), rng.next_float()}, rng.next_float());
            if (!bs.valid()) continue;
            ++valid;
            float etap = side > 0.0f ? eta : 1.0f / eta;
            ASSERT_EQ(bs.transmission, bs.wi.z * wo.z < 0.0f);
            through += bs.transmission;
            ASSERT_EQ(bs.eta, bs.transmission ? etap : 1.0f);
            ASSERT_NEAR(bs.pdf, ggx_walk::cycles_glass_pdf(wo * side, bs.wi * side, lobe.alpha, etap), 1e-5f * bs.pdf);
            ASSERT_NEAR(lobe_pdf(lobe, wo, bs.wi), bs.pdf, 1e-6f * bs.pdf);
            // The Glass BSDF's sampled weight: its colour at every bounce after the first.
            ASSERT_GE(lobe_checks::power_of(bs.value / (bs.pdf * lobe.weight), c), 0);
            ASSERT_EQ(lobe_eval(lobe, wo, bs.wi).x, lobe_eval(lobe, wo, bs.wi).x);
        }
        EXPECT_GT(valid, 19000);
        EXPECT_GT(through, 5000);
    }
}

TEST(MultiGlassWalk, PrincipledWalkCarriesBaseAndFresnelColours) {
    // The Principled glass: the base at each refraction, the interpolated Fresnel colour of cspec0 at
    // each reflection. Specular Tint 0 leaves cspec0 white: the sampled weight is base^refractions.
    const Color base(0.9f, 0.6f, 0.3f);
    Lobe lobe = glass_walk_lobe(0.7f, 1.45f, base, MultiGlassWalkLobe::kFresnel, 0.0f);
    lobe.weight = Color(1.0f);
    Rng rng(9, 1);
    int valid = 0, coloured = 0;
    for (int i = 0; i < 5000; ++i) {
        Vec3 wo = dir_from_cos(0.2f + 0.8f * rng.next_float(), 0.3f);
        BsdfSample bs = lobe_sample(lobe, wo, {rng.next_float(), rng.next_float()}, rng.next_float());
        if (!bs.valid()) continue;
        ++valid;
        int n = lobe_checks::power_of(bs.value / bs.pdf, base);
        ASSERT_GE(n, 0);
        if (bs.transmission) {
            ASSERT_EQ(n % 2, 1);  // through: an odd number of refractions
        }
        coloured += n > 0;
    }
    EXPECT_GT(valid, 4900);
    EXPECT_GT(coloured, 2000);
}

TEST(MultiGlassWalk, WhiteFurnaceOfTheSampledWalk) {
    // The walk's throughput stays 1 through refractions (an energy density): a white glass returns all
    // the light but for the walks that die after kMaxBounces (a few tenths of a percent at roughness 1).
    for (float roughness : {0.5f, 1.0f}) for (float eta : {1.45f, 2.0f}) {
        Lobe lobe = glass_walk_lobe(roughness, eta);
        for (float cos_o : {0.2f, 0.9f, -0.2f, -0.5f, -0.9f}) {
            Rng rng(23, uint64_t(100 * roughness + 10 * cos_o));
            Vec3 wo = dir_from_cos(cos_o, 1.0f);
            st::MeanEstimator furnace, eval_furnace;
            for (int i = 0; i < 100000; ++i) {
                BsdfSample bs = lobe_sample(lobe, wo, {rng.next_float(), rng.next_float()}, rng.next_float());
                furnace.add(bs.valid() ? double(bs.value.x / bs.pdf) : 0.0);
                Vec3 wi = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                eval_furnace.add(4.0 * st::kPiD * lobe_eval(lobe, wo, wi).x);
            }
            std::printf("eta %.2f roughness %.1f cos_o %.1f: sampled walk %.4f +- %.4f; Cycles' eval %.4f +- %.4f\n", eta, roughness,
                        cos_o, furnace.mean(), furnace.std_error(), eval_furnace.mean(), eval_furnace.std_error());
            EXPECT_LE(furnace.mean(), 1.0 + 1e-6);
            EXPECT_GT(furnace.mean(), 0.98);
        }
    }
}

namespace {
// The fraction of a uniform World's light that a slab of the glass (relative IOR eta) returns to a
// view tilted 10 degrees from its normal within max_bounces bounces (Cycles' meaning), the lobe's walks
// given Cycles' per-vertex LCG states along each path (cycles_path) or their own numbers.
double slab_light(float roughness, float eta, int max_bounces, bool cycles_path, int paths) {
    Rng rng(41, cycles_path);
    double sum = 0.0;
    for (int p = 0; p < paths; ++p) {
        const uint32_t key = rng.next_u32();
        Vec3 wo = normalize(Vec3(0.1763f, 0.0f, 1.0f));  // tan 10 degrees
        for (int depth = 0; depth <= max_bounces; ++depth) {
            Lobe lobe = glass_walk_lobe(roughness, depth == 0 ? eta : 1.0f / eta);  // inside: the back face
            if (cycles_path) seed_cycles_glass_walk(lobe, key, depth);
            BsdfSample bs = lobe_sample(lobe, wo, {rng.next_float(), rng.next_float()}, rng.next_float());
            if (!bs.valid()) break;
            if (depth == 0 ? !bs.transmission : bs.transmission) {  // back out of the slab
                sum += bs.value.x / bs.pdf;
                break;
            }
            // On to the opposite face, whose frame faces the way the ray came from.
            wo = Vec3(-bs.wi.x, -bs.wi.y, std::fabs(bs.wi.z));
        }
    }
    return sum / paths;
}
}  // namespace

TEST(MultiGlassWalk, CyclesLcgStatesAreItsSeedsAlongAPath) {
    // Cycles' seed at the vertex `depth` bounces along a path: rng_hash + rng_offset + sample * scramble,
    // rng_offset = 16 (depth + 1), then lcg_init's step.
    for (uint32_t key : {0u, 12345u, 0xfffffff0u})
        for (int depth : {0, 1, 7}) {
            uint32_t x = key + 16u * uint32_t(depth + 1);
            EXPECT_EQ(cycles_lcg_state(key, depth), 1103515245u * x + 12345u);
        }
    // A seeded lobe draws its walks from that state, not from its sample's numbers: its BSDF sample is
    // the walk run on the LCG, its eval Cycles' eval run on it.
    Lobe lobe = glass_walk_lobe(1.0f, 2.0f);
    uint32_t state = 0;
    EXPECT_FALSE(cycles_lcg_of(lobe, &state));
    for (int depth = 0; depth < 50; ++depth) {
        seed_cycles_glass_walk(lobe, 987654321u, depth);
        ASSERT_TRUE(cycles_lcg_of(lobe, &state));
        ASSERT_EQ(state, cycles_lcg_state(987654321u, depth));
        const Vec3 wo = dir_from_cos(0.3f + 0.01f * depth, 0.5f), wi = dir_from_cos(-0.6f, 2.0f);
        BsdfSample a = lobe_sample(lobe, wo, {0.1f, 0.2f}, 0.3f), b = lobe_sample(lobe, wo, {0.7f, 0.9f}, 0.6f);
        CyclesLcg lcg{state};
        ggx_walk::GlassExit e = ggx_walk::glass_walk(wo, lobe.alpha, lobe.eta, lcg);
        ASSERT_EQ(a.valid(), e.bounces > 0);
        if (a.valid()) {
            ASSERT_EQ(a.wi.x, b.wi.x);
            ASSERT_EQ(a.wi.z, e.dir.z);
        }
        CyclesLcg lcg2{state};
        ggx_walk::GlassColours c;
        c.eta = lobe.eta;
        ASSERT_EQ(lobe_eval(lobe, wo, wi).x, ggx_walk::cycles_glass_eval(wo, wi, lobe.alpha, lobe.eta, c, lcg2).x);
    }
}

TEST(MultiGlassWalk, CorrelatedLcgAlongAPathDarkensASlabAsInCycles) {
    // Walks at successive vertices drawn from Cycles' seeds 16 apart are correlated: a slab of the IOR 2,
    // roughness 1 glass under a uniform World returns less light within 3 bounces than with independent
    // walks. Cycles 3.4 rendered that slab (a 100 x 100 x 1 box, orthographic view tilted 10 degrees,
    // World 0.25, max bounces 3, 16 x 16 px, 1024 spp, seed 3): mean 0.12302, i.e. 0.4921 of the World.
    const int paths = 200000;
    const double cycles = slab_light(1.0f, 2.0f, 3, true, paths), independent = slab_light(1.0f, 2.0f, 3, false, paths);
    std::printf("slab, 3 bounces: Cycles' LCG %.4f, independent walks %.4f, Cycles 3.4's render 0.4921\n", cycles, independent);
    EXPECT_NEAR(cycles, 0.4921, 0.01);
    EXPECT_GT(independent, 0.55);
}
