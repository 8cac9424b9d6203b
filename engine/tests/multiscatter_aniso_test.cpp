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
//  5. the table's lobe against fresh walks cell by cell near normal incidence, where the exit's profile
//     turns fastest;
//  6. at alpha_x = alpha_y the anisotropic table is the isotropic one (the walks are the same).
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
#include "lobe_checks.h"
#include "stats.h"

using namespace smis;
namespace st = smis::stats;
using lobe_checks::Chi2Case;
using lobe_checks::cycles_alphas;
using lobe_checks::dir_from_cos;
using lobe_checks::NamedLobe;
using lobe_checks::rand2;
using st::num;

namespace {

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

// Each lobe from views high, middle and grazing.
const std::vector<Chi2Case>& all_chi2_cases() {
    static const std::vector<Chi2Case> cases = lobe_checks::chi2_cases_of(aniso_lobes(), {{0.95f, 0.3f}, {0.5f, 1.9f}, {0.1f, 4.0f}});
    return cases;
}

class MultiAnisoChi2 : public ::testing::TestWithParam<int> {};

TEST_P(MultiAnisoChi2, SampleMatchesPdf) {
    const Chi2Case& c = all_chi2_cases()[GetParam()];
    lobe_checks::expect_sampling_matches_pdf(c.name, c.lobe, c.wo, 0xa150 + GetParam(), 400000,
                                             static_cast<int>(all_chi2_cases().size()));
}

INSTANTIATE_TEST_SUITE_P(All, MultiAnisoChi2, ::testing::Range(0, static_cast<int>(all_chi2_cases().size())),
                         [](const ::testing::TestParamInfo<int>& info) { return all_chi2_cases()[info.param].name; });

TEST(MultiAnisoConsistency, SampleAgreesWithEvalAndPdf) {
    Rng rng(7, 31);
    for (const NamedLobe& nl : aniso_lobes())
        lobe_checks::expect_sample_agrees_with_eval(nl.name, nl.lobe, rng, true,
                                                    [](const Vec3&, const BsdfSample& s) { return s.wi.z > 0.0f; });
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
            if (rough == 1.0f) {
                EXPECT_GE(pair.mean(), 0.95) << rough << " " << aniso << " " << cosines[i];
            }
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

// The table's lobe against fresh walks exit cell by exit cell (4 x 8 cells of cos^2 and azimuth from the
// tangent), at views near normal incidence, where the exit's profile turns fastest (ggx_aniso_layout.h),
// and one further down; at alphas on and between the table's rows. The share of the exits the table
// misplaces, measured: 0.9-1.5% at cos 0.97-0.995 and 2.6-3.1% at 0.85 for alphas 0.18-0.19 / 1; 2.8-8.5%
// at 0.05 / 0.6 (between two rows, where the narrow lobe is interpolated across roughness). With the view
// flat beyond theta = 2 nodes (as the cells in cos theta left it beyond 0.9375) the first goes red.
TEST(MultiAnisoFurnace, TableShapeIsTheWalkNearNormalIncidence) {
    constexpr int kC = 4, kP = 8;
    for (auto [ax, ay] : {std::pair{0.18367347f, 1.0f}, std::pair{0.192f, 1.0f}, std::pair{0.05f, 0.6f}})
        for (auto [cos_o, phi_o] : {std::pair{0.995f, 0.3f}, std::pair{0.99f, 1.2f}, std::pair{0.97f, 0.7f},
                                    std::pair{0.85f, 2.0f}}) {
            Vec3 wo = dir_from_cos(cos_o, phi_o);
            std::mt19937 gen(uint32_t(1000 * cos_o + 7 * phi_o));
            auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
            constexpr int kWalks = 400000;
            std::vector<double> walked(kC * kP, 0.0), table(kC * kP, 0.0);
            auto cell_of = [&](const Vec3& w) {
                float d = std::atan2(w.y, w.x);
                d += d < 0.0f ? 2.0f * kPi : 0.0f;
                return std::min(int(w.z * w.z * kC), kC - 1) * kP + std::min(int(d * (0.5f * kInvPi) * kP), kP - 1);
            };
            for (int n = 0; n < kWalks; ++n) {
                ggx_walk::Exit e = ggx_walk::walk(wo, ax, ay, rand);
                if (e.bounces >= 2 && e.dir.z > 0.0f) walked[size_t(cell_of(e.dir))] += 1.0 / kWalks;
            }
            // The table's share of exits per cell: f_ms cos_i over the cell, on an 8 x 8 grid in
            // (cos^2, azimuth) per cell (equal projected solid angle: cos_i d omega = d(cos^2) dphi / 2).
            for (int c = 0; c < kC; ++c)
                for (int p = 0; p < kP; ++p)
                    for (int a = 0; a < 8; ++a)
                        for (int b = 0; b < 8; ++b) {
                            float c2 = (float(c) + (float(a) + 0.5f) / 8.0f) / kC;
                            float phi = (float(p) + (float(b) + 0.5f) / 8.0f) * 2.0f * kPi / kP;
                            double measure = 0.5 * (1.0 / (kC * 8)) * (2.0 * kPi / (kP * 8));
                            table[size_t(c * kP + p)] += ggx_aniso_brdf(wo, dir_from_cos(std::sqrt(c2), phi), ax, ay) * measure;
                        }
            // The share of the exits the table puts in the wrong cell.
            double err = 0.0, all = 0.0;
            for (int k = 0; k < kC * kP; ++k) {
                err += 0.5 * std::fabs(table[size_t(k)] - walked[size_t(k)]);
                all += walked[size_t(k)];
            }
            err /= all;
            std::printf("[shape] %.3f/%.3f cos %.3f phi %.1f: misplaced %.2f%%\n", ax, ay, cos_o, phi_o, 100.0 * err);
            EXPECT_LT(err, ax < 0.1f ? 0.11 : 0.045) << ax << " " << ay << " " << cos_o;
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
