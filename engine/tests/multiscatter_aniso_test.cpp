// Anisotropic multiscatter GGX (scene/lobes/multiscatter_aniso_ggx.h, scene/ggx_aniso.h), in
// multiscatter_glass_test.cpp's style:
//  1. chi-square of sample() against pdf() for both lobes, about the frame's tangent and their own,
//     Sidak-corrected over this file's cases;
//  2. sample() / eval() / pdf() agreement;
//  3. white furnace at several (Roughness, Anisotropy) pairs of the Anisotropic BSDF (Cycles' alphas):
//     the pair as the compiler builds it keeps what Cycles' walk on the stretched microsurface keeps
//     (within 1.5%), at least 95% at Roughness 1 (issue 19);
//  4. the table against fresh walks between its nodes: the albedo, the mean cosine of the exit, the
//     anisotropy of where it leaves (<x^2 - y^2> of the exit) and its colour; the analytic single
//     scattering against the walks' one-bounce part;
//  5. at alpha_x = alpha_y the anisotropic table is the isotropic one (the walks are the same).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/rng.h"
#include "core/sampling.h"
#include "scene/bsdf.h"
#include "scene/ggx_aniso.h"
#include "scene/ggx_multiple.h"
#include "scene/ggx_walk.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using st::close_rel;
using st::num;

namespace {

Point2 rand2(Rng& rng) { return {rng.next_float(), rng.next_float()}; }

Vec3 dir_from_cos(float cos_theta, float phi) {
    float s = safe_sqrt(1.0f - cos_theta * cos_theta);
    return normalize(Vec3(s * std::cos(phi), s * std::sin(phi), cos_theta));
}

// Cycles' alpha_x, alpha_y of the Anisotropic BSDF (svm/closure.h), clamped to [1e-4, 1] as its
// multiscatter setup does.
std::pair<float, float> cycles_alphas(float roughness, float anisotropy) {
    float alpha = roughness * roughness;
    float ax = anisotropy < 0.0f ? alpha / (1.0f + anisotropy) : alpha * (1.0f - anisotropy);
    float ay = anisotropy < 0.0f ? alpha * (1.0f + anisotropy) : alpha / (1.0f - anisotropy);
    return {clampf(ax, 1e-4f, 1.0f), clampf(ay, 1e-4f, 1.0f)};
}

struct Pair {
    Lobe single, multiple;
    bool has_multiple = false;
};
Pair aniso_pair(float ax, float ay, Color c = Color(1.0f), float tangent_phi = 0.0f) {
    Pair p;
    p.single.kind = LobeKind::MultiAnisoGgx;
    p.single.alpha = ax;
    p.single.alpha_y = ay;
    p.single.weight = c;
    p.single.kind_colour = Color(std::cos(tangent_phi) - 1.0f, std::sin(tangent_phi), 0.0f);
    p.has_multiple = aniso_multiple_scattering_lobe(p.single, c, &p.multiple);
    return p;
}

struct NamedLobe {
    std::string name;
    Lobe lobe;
};
std::vector<NamedLobe> aniso_lobes() {
    std::vector<NamedLobe> v;
    for (auto [ax, ay, phi] : {std::tuple{0.1f, 0.6f, 0.0f}, std::tuple{1.0f, 0.25f, 0.0f}, std::tuple{0.5f, 0.9f, 2.2f}}) {
        Pair p = aniso_pair(ax, ay, Color(0.9f, 0.7f, 0.5f), phi);
        std::string name = num(ax) + "_" + num(ay) + "_t" + num(phi);
        v.push_back({"MultiAnisoGgx_" + name, p.single});
        if (p.has_multiple) v.push_back({"AnisoGgxMultiple_" + name, p.multiple});
    }
    // The Principled metal's single scattering (Schlick Fresnel).
    Pair metal = aniso_pair(0.3f, 0.8f);
    metal.single.fresnel = FresnelMode::Schlick;
    metal.single.f0 = Color(0.9f, 0.7f, 0.5f);
    v.push_back({"MultiAnisoGgxMetal", metal.single});
    return v;
}

struct Chi2Case {
    std::string name;
    Lobe lobe;
    Vec3 wo;
};
std::vector<Chi2Case> chi2_cases() {
    std::vector<Chi2Case> cases;
    const float cosines[] = {0.95f, 0.5f, 0.1f};
    const float phis[] = {0.3f, 1.9f, 4.0f};
    for (const NamedLobe& nl : aniso_lobes())
        for (int i = 0; i < 3; ++i) cases.push_back({nl.name + "_cos" + num(cosines[i]), nl.lobe, dir_from_cos(cosines[i], phis[i])});
    return cases;
}
const std::vector<Chi2Case>& all_chi2_cases() {
    static const std::vector<Chi2Case> cases = chi2_cases();
    return cases;
}

class MultiAnisoChi2 : public ::testing::TestWithParam<int> {};

TEST_P(MultiAnisoChi2, SampleMatchesPdf) {
    const Chi2Case& c = all_chi2_cases()[GetParam()];
    const Lobe lobe = c.lobe;
    const Vec3 wo = c.wo;
    st::Chi2Options opt;
    opt.seed = 0xa150 + GetParam();
    constexpr uint64_t kSamples = 400000;
    st::Chi2Result r = st::chi2_test_directions(
        [&](Rng& rng) {
            BsdfSample s = lobe_sample(lobe, wo, rand2(rng), rng.next_float());
            if (!s.valid()) return st::DirSample::invalid();
            if (s.delta) return st::DirSample::delta();
            return st::DirSample::valid(s.wi, s.pdf);
        },
        [&](const Vec3& wi) { return double(lobe_pdf(lobe, wo, wi)); }, kSamples, opt);
    double alpha = st::sidak_significance(0.01, static_cast<int>(all_chi2_cases().size()));
    std::printf("[chi2] %-40s %s\n", c.name.c_str(), r.summary().c_str());
    EXPECT_TRUE(r.passes(alpha)) << c.name << ": " << r.summary() << "\n" << r.residual_map();
    EXPECT_GT(r.n_valid, kSamples / 10) << c.name;
}

INSTANTIATE_TEST_SUITE_P(All, MultiAnisoChi2, ::testing::Range(0, static_cast<int>(all_chi2_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) { return all_chi2_cases()[info.param].name; });

TEST(MultiAnisoConsistency, SampleAgreesWithEvalAndPdf) {
    Rng rng(7, 31);
    for (const NamedLobe& nl : aniso_lobes()) {
        int valid = 0, mismatches = 0;
        for (int i = 0; i < 20000; ++i) {
            Vec3 wo = sample_uniform_sphere(rand2(rng));
            BsdfSample s = lobe_sample(nl.lobe, wo, rand2(rng), rng.next_float());
            if (!s.valid()) continue;
            ++valid;
            Color e = lobe_eval(nl.lobe, wo, s.wi);
            float p = lobe_pdf(nl.lobe, wo, s.wi);
            bool ok = !s.delta && close_rel(s.value.x, e.x) && close_rel(s.value.y, e.y) && close_rel(s.value.z, e.z) &&
                      close_rel(s.pdf, p) && std::fabs(length(s.wi) - 1.0f) < 1e-4f && s.wi.z > 0.0f;
            mismatches += !ok;
        }
        EXPECT_EQ(mismatches, 0) << nl.name;
        EXPECT_GT(valid, 5000) << nl.name;
    }
}

// Fresh walks on the anisotropic microsurface from wo (lobe frame): the fractions leaving after one
// bounce and after more (white, and with colour c at each further bounce), and of the latter the mean
// cosine and mean x^2 - y^2 of the exit (how far it is stretched along the tangent).
struct WalkStats {
    st::MeanEstimator single, multiple, tinted, cos_multiple, stretch_multiple;
};
WalkStats walk_stats(const Vec3& wo, float ax, float ay, float c, int n, uint32_t seed) {
    std::mt19937 gen(seed);
    auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
    WalkStats w;
    for (int k = 0; k < n; ++k) {
        ggx_walk::Exit e = ggx_walk::walk(wo, ax, ay, rand);
        bool multiple = e.bounces >= 2;
        w.single.add(e.bounces == 1 ? 1.0 : 0.0);
        w.multiple.add(multiple ? 1.0 : 0.0);
        w.tinted.add(multiple ? std::pow(double(c), e.bounces - 1) : 0.0);
        if (multiple) {
            w.cos_multiple.add(e.dir.z);
            w.stretch_multiple.add(double(e.dir.x) * e.dir.x - double(e.dir.y) * e.dir.y);
        }
    }
    return w;
}

// The pair as the renderer samples it (one Bsdf, lobe selection by weight): the energy it keeps.
st::MeanEstimator pair_energy(const Pair& p, const Vec3& wo, int n, uint64_t seed) {
    Bsdf bsdf(Frame(), Vec3(0, 0, 1));
    bsdf.add(p.single);
    if (p.has_multiple) bsdf.add(p.multiple);
    Rng rng(seed, 3);
    st::MeanEstimator m;
    for (int k = 0; k < n; ++k) {
        BsdfSample s = bsdf.sample(wo, rand2(rng), rng.next_float());
        m.add(s.valid() ? average(s.value) / s.pdf : 0.0);
    }
    return m;
}

// Issue 19: anisotropic multiscatter GGX at Roughness 1 keeps at least 95% of a white furnace's
// energy; at every (Roughness, Anisotropy) what Cycles' walk keeps, within 1.5% (the table's
// interpolation between its roughness rows and view cells).
TEST(MultiAnisoFurnace, KeepsTheWalksEnergy) {
    const float cosines[] = {0.95f, 0.5f, 0.15f};
    const float phis[] = {0.3f, 1.2f, 2.6f};
    for (auto [rough, aniso] : {std::pair{0.5f, 0.5f}, std::pair{0.8f, 0.7f}, std::pair{0.8f, -0.5f},
                                std::pair{1.0f, 0.3f}, std::pair{1.0f, 0.9f}})
        for (int i = 0; i < 3; ++i) {
            auto [ax, ay] = cycles_alphas(rough, aniso);
            Pair p = aniso_pair(ax, ay);
            ASSERT_TRUE(p.has_multiple);
            Vec3 wo = dir_from_cos(cosines[i], phis[i]);
            st::MeanEstimator pair = pair_energy(p, wo, 200000, 11 + i);
            WalkStats w = walk_stats(wo, ax, ay, 1.0f, 200000, 5 + i);
            double walk = w.single.mean() + w.multiple.mean();
            std::printf("[furnace] MultiAniso rough %.1f aniso %+.1f (alphas %.3f/%.3f) cos %.2f: pair %.5f +- %.2g, "
                        "walk %.5f (single %.5f)\n",
                        rough, aniso, ax, ay, cosines[i], pair.mean(), pair.std_error(), walk, w.single.mean());
            if (rough == 1.0f) EXPECT_GE(pair.mean(), 0.95) << rough << " " << aniso << " " << cosines[i];
            EXPECT_NEAR(pair.mean(), walk, 0.015) << rough << " " << aniso << " " << cosines[i];
        }
}

// The analytic single scattering is the walk's one-bounce part; the table between its nodes (alphas
// and views between its nodes) is the walks' multiple scattering: albedo, mean cosine, stretch along
// the tangent (<x^2 - y^2> of the exit), and colour with c = 0.7 applied at each further bounce.
TEST(MultiAnisoFurnace, TableIsTheWalk) {
    for (auto [ax, ay] : {std::pair{0.3f, 0.75f}, std::pair{0.9f, 0.2f}})
        for (Vec3 wo : {dir_from_cos(0.7f, 0.4f), dir_from_cos(0.35f, 2.0f)}) {
            Color c(0.7f);
            Pair p = aniso_pair(ax, ay, c);
            ASSERT_TRUE(p.has_multiple);
            WalkStats w = walk_stats(wo, ax, ay, c.x, 400000, 77);
            auto brdf = [&](const Vec3& wi) { return double(ggx_aniso_brdf(wo, wi, ax, ay)) * std::max(wi.z, 0.0f); };
            double energy = st::integrate_sphere(brdf);
            double first = st::integrate_sphere([&](const Vec3& wi) { return brdf(wi) * std::max(wi.z, 0.0f); });
            double stretch = st::integrate_sphere([&](const Vec3& wi) { return brdf(wi) * (wi.x * wi.x - wi.y * wi.y); });
            double tint = st::integrate_sphere([&](const Vec3& wi) { return double(lobe_eval(p.multiple, wo, wi).x); }) /
                          energy / c.x;
            double single = st::integrate_sphere([&](const Vec3& wi) { return double(lobe_eval(p.single, wo, wi).x); }) / c.x;
            double table = ggx_aniso_albedo(wo, ax, ay);
            std::printf("[walk] %.2f/%.2f cos %.2f: single %.5f (walk %.5f), multiple %.5f (table %.5f, lobe %.5f), "
                        "mean cos %.4f (lobe %.4f), stretch %+.4f (lobe %+.4f), tinted %.5f (lobe %.5f)\n",
                        ax, ay, wo.z, single, w.single.mean(), w.multiple.mean(), table, energy, w.cos_multiple.mean(),
                        first / energy, w.stretch_multiple.mean(), stretch / energy, w.tinted.mean() / w.multiple.mean(),
                        tint);
            EXPECT_NEAR(single, w.single.mean(), 0.004);
            EXPECT_NEAR(table, w.multiple.mean(), 0.03 * w.multiple.mean() + 0.002);
            EXPECT_NEAR(energy, w.multiple.mean(), 0.03 * w.multiple.mean() + 0.002);
            EXPECT_NEAR(first / energy, w.cos_multiple.mean(), 0.01);
            // Measured 0.005-0.017 (32 exit azimuths); 0.021 and 0.058 with the exit's azimuth taken from
            // the view's instead of the tangent's.
            EXPECT_NEAR(stretch / energy, w.stretch_multiple.mean(), 0.02);
            // The colour model is the isotropic lobe's (multiscatter_tint: a geometric number of further
            // bounces fitted at c = 0.5 per roughness pair, averaged over the views): up to 0.017 here.
            EXPECT_NEAR(tint, w.tinted.mean() / w.multiple.mean(), 0.02);
        }
}

// At alpha_x = alpha_y the walks are the isotropic ones: the anisotropic table's albedo is the
// isotropic table's, whatever the view's azimuth.
TEST(MultiAnisoFurnace, EqualAlphasAreTheIsotropicTable) {
    for (float alpha : {0.36f, 0.64f, 1.0f})
        for (float phi : {0.0f, 0.8f, 2.0f, 4.5f})
            for (float c : {0.9f, 0.5f, 0.2f}) {
                Vec3 wo = dir_from_cos(c, phi);
                double iso = ggx_multiple_albedo(c, alpha), aniso = ggx_aniso_albedo(wo, alpha, alpha);
                EXPECT_NEAR(aniso, iso, 0.03 * iso + 0.002) << alpha << " " << phi << " " << c;
            }
}

}  // namespace
