// core/pixel_sequence.h: the samples of one pixel stratify, every sample is uniform over pixels.
#include <gtest/gtest.h>

#include <vector>

#include "core/pixel_sequence.h"
#include "stats.h"

using namespace smis;

// Any 2^k consecutive samples from a multiple of 2^k fall one per interval of length 2^-k.
TEST(PixelSequence, StratifiesTheSamplesOfAPixel) {
    for (uint32_t seed : {0u, 3u})
        for (uint32_t px : {0u, 17u, 1000u})
            for (uint32_t k : {2u, 4u, 5u}) {
                uint32_t n = 1u << k;
                for (uint32_t first : {0u, n, 7u * n}) {
                    std::vector<int> count(n, 0);
                    for (uint32_t s = first; s < first + n; ++s) {
                        float v = pixel_sequence(px, 2 * px + 1, s, seed, 11);
                        ASSERT_GE(v, 0.0f);
                        ASSERT_LT(v, 1.0f);
                        ++count[std::min(int(v * float(n)), int(n) - 1)];
                    }
                    for (uint32_t b = 0; b < n; ++b)
                        EXPECT_EQ(count[b], 1) << "pixel " << px << " seed " << seed << " n " << n << " bin " << b;
                }
            }
}

// A fixed sample index over many pixels (and over seeds, and for a second dimension) is uniform:
// chi-square over 64 bins. This is what keeps the estimators that use it unbiased.
TEST(PixelSequence, EverySampleIsUniformOverPixels) {
    constexpr int kBins = 64, kPixels = 256;
    double alpha = stats::sidak_significance(1e-3, 4);
    for (auto [sample, seed, salt] : {std::tuple{0u, 1u, 11ull}, {5u, 1u, 11ull}, {5u, 2u, 11ull}, {5u, 1u, 12ull}}) {
        std::vector<double> observed(kBins, 0.0), expected(kBins, double(kPixels * kPixels) / kBins);
        for (uint32_t y = 0; y < kPixels; ++y)
            for (uint32_t x = 0; x < kPixels; ++x)
                observed[std::min(int(pixel_sequence(x, y, sample, seed, salt) * kBins), kBins - 1)] += 1.0;
        stats::Chi2Result res;
        stats::chi2_statistic(observed, expected, 5.0, uint64_t(kPixels) * kPixels, &res);
        EXPECT_TRUE(res.error.empty()) << res.error;
        EXPECT_GT(res.p_value, alpha) << "sample " << sample << " seed " << seed << " salt " << salt;
    }
}
