// The stratified prefix of the pixel samples (core/stratified.h): stratified within a pixel, uniform
// and independent across pixels (so estimators stay unbiased), and less noise in a render.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <vector>

#include "core/stratified.h"
#include "integrators/tiles.h"
#include "integrators/volume.h"
#include "stats.h"
#include "test_scenes.h"

namespace smis {
namespace {

// Whether the 2^k points (x, y interleaved) form a (0, k, 2)-net: every elementary interval of area
// 2^-k (2^a x 2^(k-a) cells, every a) holds exactly one point.
bool is_02_net(const std::vector<float>& pts, int k) {
    const int n = 1 << k;
    for (int a = 0; a <= k; ++a) {
        const int nx = 1 << a, ny = 1 << (k - a);
        std::vector<int> count(n, 0);
        for (int s = 0; s < n; ++s) {
            int cx = std::min(nx - 1, int(pts[2 * s] * nx)), cy = std::min(ny - 1, int(pts[2 * s + 1] * ny));
            ++count[cy * nx + cx];
        }
        for (int c : count)
            if (c != 1) return false;
    }
    return true;
}

// The first 2^k points of a pixel's 2D group form a (0, k, 2)-net. Independent random points do not.
TEST(Stratified, FirstSamplesOfAPixelAreA02Net) {
    for (uint64_t key : {1ull, 77ull, 0xdeadbeefull}) {
        for (int k : {2, 4, 6}) {
            const int n = 1 << k;
            std::vector<float> pts(2 * n);
            for (int s = 0; s < n; ++s) stratified::sample_2d(uint32_t(s), key, 3, &pts[2 * s]);
            ASSERT_TRUE(is_02_net(pts, k)) << "key " << key << " k " << k;
        }
        // 1D groups: the first 2^k values fall one per interval of length 2^-k.
        std::vector<int> count(16, 0);
        for (int s = 0; s < 16; ++s) ++count[int(stratified::sample_1d(uint32_t(s), key, 2) * 16)];
        for (int c : count) EXPECT_EQ(c, 1);
    }
}

// One sample index over many pixels (random scrambles): uniform on [0,1)^2 (chi-square over 8x8
// cells) and uncorrelated between groups. This is what keeps every estimator unbiased.
TEST(Stratified, OneSampleAcrossPixelsIsUniformAndGroupsIndependent) {
    for (uint32_t sample : {0u, 1u, 5u, 1000u}) {
        const int n = 64000, cells = 64;
        std::vector<double> observed(cells, 0.0);
        double sxy = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0;
        for (int p = 0; p < n; ++p) {
            uint64_t key = mix64(uint64_t(p) * 7919u + 13u);
            float v[2];
            stratified::sample_2d(sample, key, 0, v);
            ASSERT_GE(v[0], 0.0f);
            ASSERT_LT(v[0], 1.0f);
            ASSERT_LT(v[1], 1.0f);
            ++observed[std::min(7, int(v[0] * 8)) + 8 * std::min(7, int(v[1] * 8))];
            double a = v[0], b = stratified::sample_1d(sample, key, 2);  // another group
            sx += a, sy += b, sxx += a * a, syy += b * b, sxy += a * b;
        }
        double chi2 = 0.0, e = double(n) / cells;
        for (double o : observed) chi2 += (o - e) * (o - e) / e;
        EXPECT_GT(stats::chi2_survival(chi2, cells - 1), 1e-3) << "sample " << sample;
        double cov = sxy / n - (sx / n) * (sy / n);
        double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
        EXPECT_LT(std::fabs(corr), 4.0 / std::sqrt(double(n))) << "sample " << sample;
    }
}

// In a scene seen through a medium, the camera ray's first scattering segment (volume.h,
// segment_numbers) takes its numbers from stratified groups of its own: over a pixel's first 16
// samples (light choice, distance), the light point and the focus each form a (0, 4, 2)-net. A second
// segment draws from the stream; the first vertex, asking by name after both (VertexSampler), still
// finds its groups' numbers.
TEST(Stratified, TheFirstScatteringSegmentHasGroupsOfItsOwnAndTheFirstVertexKeepsItsNames) {
    auto scene = testing::small_room(8, 8);
    RenderSettings st;
    st.seed = 7;
    Film film(8, 8);
    PixelFilter filter;
    RenderCounters counters;
    std::atomic<bool> cancel{false};
    RenderContext ctx{*scene, st, film, filter, counters, cancel, std::chrono::steady_clock::time_point::max()};
    const int x = 3, y = 5, k = 4;
    PixelCamera pixel(ctx, x, y);
    std::vector<float> choice_dist, light, focus, second;
    for (uint32_t s = 0; s < (1u << k); ++s) {
        Sampler sampler;
        pixel.ray(s, &sampler);
        Rng& rng = sampler.rng();
        const SegmentNumbers n = segment_numbers(rng);
        choice_dist.insert(choice_dist.end(), {n.select, n.dist});
        light.insert(light.end(), {n.light.x, n.light.y});
        focus.insert(focus.end(), {n.focus.x, n.focus.y});
        const SegmentNumbers later = segment_numbers(rng);
        second.insert(second.end(), {later.select, later.dist});
        const VertexSampler first(rng, &sampler);
        const LightNumbers l = first.light();
        const float lobe = first.lobe();
        const Point2 d = first.direction();
        Sampler fresh = pixel.pixel_sampler().start(s);
        const LightNumbers l0 = fresh.first_light();
        const float lobe0 = fresh.first_lobe();
        const Point2 d0 = fresh.first_direction();
        const float got[6] = {l.choice, l.point.x, l.point.y, lobe, d.x, d.y};
        const float named[6] = {l0.choice, l0.point.x, l0.point.y, lobe0, d0.x, d0.y};
        for (int i = 0; i < 6; ++i) ASSERT_EQ(got[i], named[i]) << "sample " << s << " value " << i;
    }
    EXPECT_TRUE(is_02_net(choice_dist, k));
    EXPECT_TRUE(is_02_net(light, k));
    EXPECT_TRUE(is_02_net(focus, k));
    EXPECT_FALSE(is_02_net(second, k));  // independent numbers: a net by chance is most unlikely
}

// The point of it: a diffuse room lit by an area light (soft shadows, first-bounce light and BSDF
// samples) has a lower error at 16 spp with the stratified prefix than with independent numbers,
// measured against a 1024-spp reference over 4 seeds each; and both converge to the same image
// (image means agree).
TEST(Stratified, LessNoiseThanIndependentNumbersAndTheSameMean) {
    auto scene = testing::small_room(32, 32);
    RenderSettings st;
    st.max_bounces = 3;
    st.samples = 1024;
    st.seed = 999;
    st.sampling_pattern = SamplingPattern::Random;
    const std::vector<float> ref = testing::render(scene, st);
    double mse[2] = {0.0, 0.0};
    stats::MeanEstimator mean[2];
    for (int strat = 0; strat < 2; ++strat) {
        for (uint32_t seed = 1; seed <= 4; ++seed) {
            st.samples = 16;
            st.seed = seed;
            st.sampling_pattern = strat == 1 ? SamplingPattern::Stratified : SamplingPattern::Random;
            auto img = testing::render(scene, st);
            for (size_t i = 0; i < img.size(); i += 4)
                for (int c = 0; c < 3; ++c) mse[strat] += double(img[i + c] - ref[i + c]) * (img[i + c] - ref[i + c]);
            mean[strat].add(testing::channel_mean(img, 1).mean());
        }
    }
    std::printf("MSE at 16 spp: random %.5g, stratified %.5g (ratio %.3f)\n", mse[0], mse[1], mse[1] / mse[0]);
    EXPECT_LT(mse[1], 0.9 * mse[0]);
    EXPECT_GT(stats::z_test(mean[1].mean(), mean[0].mean(),
                            std::sqrt(mean[0].variance() / 4 + mean[1].variance() / 4), 1e-6)
                  .p_value,
              1e-3);
}

}  // namespace
}  // namespace smis
