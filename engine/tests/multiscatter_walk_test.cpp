// Cycles' own Multiscatter GGX estimator (the setting multiscatter_cycles_walk, lobes/multiscatter_walk.h,
// scene/ggx_walk.h's cycles_eval / cycles_pdf), checked against the sampled walk it is built on:
//  1. where the view is the shallower direction, Cycles' eval walks from the view and its next-event
//     estimates are that walk's exit density: over the light directions steeper than the view, the
//     eval integrates to the fraction of sampled walks (ggx_walk::walk) that leave there;
//  2. its white furnace at (near) normal view is what the walks entering from every direction leave
//     towards the normal (the swap: Cycles walks from the shallower light direction), which is not the
//     sampled walk's 100%: about 94% at the closure scene's Roughness 0.8, Anisotropy 0.7;
//  3. the lobe: sampled weight = the walk's throughput c^(bounces - 1), pdf() = Cycles' mf_pdf, the eval
//     the same for the same directions (deterministic);
//  4. the Principled BSDF's one reflection closure (kFresnel): a walk's weight is the product of the
//     interpolated Fresnel colours at its microfacets (the half vector's for a single reflection).
// The glass closure's estimator: multi_glass_walk_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "scene/ggx_walk.h"
#include "scene/lobes/multiscatter_walk.h"
#include "lobe_checks.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using lobe_checks::cycles_alphas;
using lobe_checks::dir_from_cos;

namespace {

Lobe walk_lobe(float ax, float ay, Color c = Color(1.0f)) {
    Lobe l;
    l.kind = LobeKind::MultiGgxWalk;
    l.alpha = ax;
    l.alpha_y = ay;
    l.weight = c;
    l.f0 = c;
    return l;
}

struct Rand {
    Rng& rng;
    float operator()() { return rng.next_float(); }
};

// ggx_walk::cycles_eval over cosine-sampled light directions (eval / pdf), those with keep(wi) only.
template <class Keep>
st::MeanEstimator eval_integral(const Vec3& view, const ggx_walk::Anisotropic& s, Rng& rng, int n, Keep&& keep) {
    st::MeanEstimator m;
    for (int i = 0; i < n; ++i) {
        Vec3 wi = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
        if (!(wi.z > 0.0f) || !keep(wi)) {
            m.add(0.0);
            continue;
        }
        Rand r{rng};
        m.add(ggx_walk::cycles_eval(view, wi, s, Color(1.0f), r).x / (wi.z * kInvPi));
    }
    return m;
}

}  // namespace

TEST(MultiscatterWalk, EvalIsTheSampledWalkWhereTheViewIsShallower) {
    for (auto [roughness, anisotropy] : {std::pair{0.8f, 0.7f}, std::pair{1.0f, -0.5f}, std::pair{0.6f, 0.0f}}) {
        auto [ax, ay] = cycles_alphas(roughness, anisotropy);
        ggx_walk::Anisotropic s{ax, ay};
        for (float cos_v : {0.25f, 0.5f}) {
            Vec3 view = dir_from_cos(cos_v, 0.7f);
            Rng rng(11, uint64_t(1000 * roughness + 10 * cos_v));
            const int n = 400000;
            st::MeanEstimator eval = eval_integral(view, s, rng, n, [&](const Vec3& wi) { return wi.z >= view.z; });
            st::MeanEstimator walks;
            for (int i = 0; i < n; ++i) {
                Rand r{rng};
                ggx_walk::Exit e = ggx_walk::walk_on(view, s, r);
                walks.add(e.bounces > 0 && e.dir.z >= view.z ? 1.0 : 0.0);
            }
            // Within 1% beyond the noise: the walk samples its visible normals through Heitz's rational
            // approximation of the inverse CDF (ggx_walk::sample_unit_slopes, as Cycles), the eval's phase
            // function has the exact D (measured: +0.0-0.9%, eval above).
            st::ZTest z = st::z_test_difference(eval, walks, 0.01 * walks.mean());
            std::printf("roughness %.1f anisotropy %+.1f cos_view %.2f: eval %.4f +- %.4f, walks %.4f +- %.4f (z %.2f)\n",
                        roughness, anisotropy, cos_v, eval.mean(), eval.std_error(), walks.mean(), walks.std_error(), z.z);
            EXPECT_GT(z.p_value, 1e-3) << roughness << " " << anisotropy << " " << cos_v;
        }
    }
}

TEST(MultiscatterWalk, FurnaceNearNormalViewIsTheWalksTowardsTheNormal) {
    // Views uniform in the cap cos > kCap; there the light is (nearly) always the shallower direction,
    // so Cycles' eval is the exit density towards the view of walks entering from the light, times
    // cos(light) / cos(view). Its furnace averaged over the cap is then pi x the share of walks entering
    // cosine-distributed that leave into the cap, over the cap's solid angle (up to cos(view) in [kCap, 1]
    // and the cap's own light directions: < 0.3%).
    constexpr float kCap = 0.995f;
    const double cap_solid_angle = 2.0 * st::kPiD * (1.0 - kCap);
    auto [ax, ay] = cycles_alphas(0.8f, 0.7f);
    ggx_walk::Anisotropic s{ax, ay};
    Rng rng(29, 3);
    const int n = 400000;
    st::MeanEstimator furnace, into_cap, albedo;
    for (int i = 0; i < n; ++i) {
        float cos_v = 1.0f - (1.0f - kCap) * rng.next_float();
        Vec3 view = dir_from_cos(cos_v, 2.0f * kPi * rng.next_float());
        Vec3 wi = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
        if (!(wi.z > 0.0f)) {
            furnace.add(0.0);
        } else {
            Rand r{rng};
            furnace.add(ggx_walk::cycles_eval(view, wi, s, Color(1.0f), r).x / (wi.z * kInvPi));
        }
        Rand r1{rng};
        ggx_walk::Exit e2 = ggx_walk::walk_on(view, s, r1);
        albedo.add(e2.bounces > 0 ? 1.0 : 0.0);
    }
    // The walks are cheaper than the eval and rarely leave into the cap: many more of them.
    for (int i = 0; i < 20 * n; ++i) {
        Vec3 entry = sample_cosine_hemisphere({rng.next_float(), rng.next_float()});
        Rand r1{rng};
        ggx_walk::Exit e = ggx_walk::walk_on(entry, s, r1);
        into_cap.add(e.bounces > 0 && e.dir.z > kCap ? st::kPiD / cap_solid_angle : 0.0);
    }
    std::printf("furnace near normal view: Cycles' eval %.4f +- %.4f, walks towards the normal %.4f +- %.4f, "
                "sampled walk %.4f\n",
                furnace.mean(), furnace.std_error(), into_cap.mean(), into_cap.std_error(), albedo.mean());
    EXPECT_GT(st::z_test_difference(furnace, into_cap, 0.003 * into_cap.mean()).p_value, 1e-3);
    // Not the sampled walk's energy: Cycles' eval keeps less (its walk is not reciprocal).
    EXPECT_LT(furnace.mean(), albedo.mean() - 0.02);
}

TEST(MultiscatterWalk, LobeIsCyclesEstimator) {
    auto [ax, ay] = cycles_alphas(0.8f, 0.7f);
    const Color c(0.9f, 0.7f, 0.5f);
    Lobe lobe = walk_lobe(ax, ay, c);
    Rng rng(5, 7);
    ggx_walk::Anisotropic s{ax, ay};
    int valid = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 wo = dir_from_cos(0.1f + 0.9f * rng.next_float(), 2.0f * kPi * rng.next_float());
        Point2 u{rng.next_float(), rng.next_float()};
        float ue = rng.next_float();
        BsdfSample bs = lobe_sample(lobe, wo, u, ue);
        if (!bs.valid()) continue;
        ++valid;
        // The weight is the walk's throughput, a power of the colour, and the pdf Cycles' mf_pdf.
        ASSERT_NEAR(bs.pdf, ggx_walk::cycles_pdf(wo, bs.wi, s, std::sqrt(ax * ay)), 1e-5f * bs.pdf);
        ASSERT_NEAR(lobe_pdf(lobe, wo, bs.wi), bs.pdf, 1e-6f * bs.pdf);
        ASSERT_GE(lobe_checks::power_of(bs.value / (bs.pdf * lobe.weight), c), 0);
        // Deterministic: the same directions, the same estimate.
        ASSERT_EQ(lobe_eval(lobe, wo, bs.wi).x, lobe_eval(lobe, wo, bs.wi).x);
    }
    EXPECT_GT(valid, 19000);
}

TEST(MultiscatterWalk, PrincipledReflectionCarriesFresnelColoursPerBounce) {
    // The Principled BSDF's one reflection closure (variant kFresnel, f0 = cspec0, eta the specular IOR):
    // its sampled weight is the product of the interpolated Fresnel colours at the walk's microfacets. A
    // walk that reflects once leaves about its microfacet normal, the half vector of view and light, so
    // its weight is the Fresnel colour there: at roughness 0.5 most samples are such single reflections.
    auto [ax, ay] = cycles_alphas(0.5f, 0.0f);
    Lobe lobe = walk_lobe(ax, ay, Color(0.9f, 0.5f, 0.1f));
    lobe.variant = MultiGgxWalkLobe::kFresnel;
    lobe.eta = 1.5f;
    lobe.weight = Color(1.0f);
    Rng rng(31, 2);
    int valid = 0, single = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec3 wo = dir_from_cos(0.2f + 0.8f * rng.next_float(), 2.0f * kPi * rng.next_float());
        BsdfSample bs = lobe_sample(lobe, wo, {rng.next_float(), rng.next_float()}, rng.next_float());
        if (!bs.valid()) continue;
        ++valid;
        Color t = bs.value / bs.pdf;
        Color once = ggx_walk::fresnel_colour(dot(wo, normalize(wo + bs.wi)), lobe.eta, lobe.f0);
        // Every factor lies between cspec0 and 1, per channel.
        ASSERT_LE(t.x, 1.0f + 1e-5f);
        ASSERT_GE(t.z, 0.0f);
        single += std::fabs(t.x - once.x) < 1e-4f && std::fabs(t.z - once.z) < 1e-4f;
    }
    std::printf("Principled reflection walk: %d of %d samples weighted by the Fresnel colour at their half vector\n",
                single, valid);
    EXPECT_GT(valid, 19000);
    EXPECT_GT(single, valid / 2);
    // White cspec0: every Fresnel colour is 1, so the eval is the Glossy BSDF's white eval.
    lobe.f0 = Color(1.0f);
    Lobe plain = walk_lobe(ax, ay);
    for (int i = 0; i < 200; ++i) {
        Vec3 wo = dir_from_cos(0.1f + 0.9f * rng.next_float(), 2.0f * kPi * rng.next_float());
        Vec3 wi = dir_from_cos(0.1f + 0.9f * rng.next_float(), 2.0f * kPi * rng.next_float());
        float a = lobe_eval(lobe, wo, wi).x, b = lobe_eval(plain, wo, wi).x;
        ASSERT_NEAR(a, b, 1e-4f * b + 1e-7f);
    }
}
