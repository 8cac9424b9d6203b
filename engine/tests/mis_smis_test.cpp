// Unit tests of engine/mis/smis.h: the weights, the guards, the DMIS special case and the technique
// selection helpers. The statistical test of the estimators is mis_fig2_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "core/math.h"
#include "core/rng.h"
#include "mis/smis.h"
#include "stats.h"

using namespace smis;
using namespace smis::mis;

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(MisSmis, BalanceWeightIsOwnPdfOverSum) {
    const float pdfs[] = {1.0f, 3.0f, 4.0f};
    EXPECT_FLOAT_EQ(balance_weight(pdfs, 3, 0), 1.0f / 8.0f);
    EXPECT_FLOAT_EQ(balance_weight(pdfs, 3, 1), 3.0f / 8.0f);
    EXPECT_FLOAT_EQ(balance_weight(pdfs, 3, 2), 4.0f / 8.0f);
    const double single[] = {0.25};
    EXPECT_EQ(balance_weight(single, 1, 0), 1.0);
}

TEST(MisSmis, PowerWeightIsSquaredPdfOverSumOfSquares) {
    const float pdfs[] = {1.0f, 3.0f, 4.0f};
    EXPECT_FLOAT_EQ(power_weight(pdfs, 3, 0), 1.0f / 26.0f);
    EXPECT_FLOAT_EQ(power_weight(pdfs, 3, 2), 16.0f / 26.0f);
    EXPECT_FLOAT_EQ(power_weight(pdfs, 3, 2, 3.0), 64.0f / 92.0f);
    // Densities whose squares overflow float (near-specular lobes) still give finite weights.
    const float huge[] = {1e30f, 3e30f};
    EXPECT_FLOAT_EQ(power_weight(huge, 2, 1), 9.0f / 10.0f);
    EXPECT_FLOAT_EQ(balance_weight(huge, 2, 1), 3.0f / 4.0f);
}

TEST(MisSmis, WeightsSumToOneOverSelectedTechniques) {
    Rng rng(3, 4);
    for (int trial = 0; trial < 1000; ++trial) {
        int n = 1 + static_cast<int>(rng.next_u32() % 16);
        std::vector<float> pdfs(n);
        for (float& p : pdfs) p = rng.next_float() < 0.2f ? 0.0f : std::exp(20.0f * (rng.next_float() - 0.5f));
        bool any = false;
        for (float p : pdfs) any = any || p > 0.0f;
        for (MisHeuristic h : {MisHeuristic::Balance, MisHeuristic::Power}) {
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                float w = mis_weight(h, pdfs.data(), static_cast<const float*>(nullptr), n, i);
                EXPECT_TRUE(w >= 0.0f && w <= 1.0f);
                sum += w;
            }
            EXPECT_NEAR(sum, any ? 1.0 : 0.0, 1e-5) << "n = " << n;
        }
    }
}

TEST(MisSmis, GuardsAgainstZeroAndNonFiniteDensities) {
    // Own density 0, NaN, negative or infinite: the sample contributes nothing.
    const float own_bad[][3] = {{0.0f, 1.0f, 2.0f}, {kNaN, 1.0f, 2.0f}, {-1.0f, 1.0f, 2.0f}, {kInf, 1.0f, 2.0f}};
    for (const auto& pdfs : own_bad) {
        EXPECT_EQ(balance_weight(pdfs, 3, 0), 0.0f);
        EXPECT_EQ(power_weight(pdfs, 3, 0), 0.0f);
    }
    // Unusable densities of the other techniques are left out of the denominator: finite, never 0/0.
    const float other_bad[] = {2.0f, kNaN, 0.0f, -3.0f, kInf, 2.0f};
    EXPECT_FLOAT_EQ(balance_weight(other_bad, 6, 0), 0.5f);
    EXPECT_FLOAT_EQ(power_weight(other_bad, 6, 5), 0.5f);
    const float all_zero[] = {0.0f, 0.0f};
    EXPECT_EQ(balance_weight(all_zero, 2, 1), 0.0f);
    // Out-of-range index.
    EXPECT_EQ(balance_weight(other_bad, 6, 6), 0.0f);
    EXPECT_EQ(balance_weight(other_bad, 6, -1), 0.0f);

    SmisCombiner<float> c;
    c.add(5.0f, own_bad[0], 3, 0);
    c.add(5.0f, own_bad[1], 3, 0);
    EXPECT_EQ(c.estimate(), 0.0f);
    c.add(4.0f, other_bad, 6, 0);  // w = 1/2, f / p = 2
    EXPECT_FLOAT_EQ(c.estimate(), 1.0f);
    EXPECT_EQ(cmis_estimate(1.0, 3.0, 0.0, 2.0), 0.0);
    EXPECT_EQ(cmis_estimate(1.0, 3.0, 1.0, std::nan("")), 0.0);
}

// Eq. (12): sum_i f(x_i) / sum_j p(x_i|t_j), no 1/n.
TEST(MisSmis, CombinerComputesEquation12) {
    const double f[] = {2.0, 5.0};
    const double pdfs[] = {1.0, 3.0,   // p(x_0|t_0), p(x_0|t_1)
                           0.5, 2.0};  // p(x_1|t_0), p(x_1|t_1)
    SmisCombiner<double, double> c;
    c.add(f[0], pdfs, 2, 0);
    c.add(f[1], pdfs + 2, 2, 1);
    EXPECT_DOUBLE_EQ(c.estimate(), 2.0 / 4.0 + 5.0 / 2.5);
    EXPECT_DOUBLE_EQ(smis_estimate(f, pdfs, 2), c.estimate());
    c.reset();
    EXPECT_EQ(c.estimate(), 0.0);

    // Spectral / RGB values work the same (T = Color).
    SmisCombiner<Color> rgb;
    const float p2[] = {1.0f, 3.0f};
    rgb.add(Color(4.0f, 8.0f, 0.0f), p2, 2, 0);
    EXPECT_FLOAT_EQ(rgb.estimate().x, 1.0f);
    EXPECT_FLOAT_EQ(rgb.estimate().y, 2.0f);
}

// DMIS (Veach): fixed techniques with n_k samples. Counts give the same weights as listing technique k
// n_k times, and the combiner adds w_k f / (n_k p_k) = f / sum_j n_j p_j (eq. 4 with eq. 5).
TEST(MisSmis, DiscreteMisWithSampleCountsIsTheFixedSetSpecialCase) {
    const float pdfs[] = {0.5f, 2.0f};
    const float counts[] = {3.0f, 1.0f};
    const float repeated[] = {0.5f, 0.5f, 0.5f, 2.0f};
    EXPECT_FLOAT_EQ(mis_weight(MisHeuristic::Balance, pdfs, counts, 2, 0), 1.5f / 3.5f);
    EXPECT_FLOAT_EQ(mis_weight(MisHeuristic::Balance, pdfs, counts, 2, 0),
                    3.0f * balance_weight(repeated, 4, 0));
    EXPECT_FLOAT_EQ(mis_weight(MisHeuristic::Power, pdfs, counts, 2, 0), 2.25f / (2.25f + 4.0f));
    SmisCombiner<double> c;
    c.add(7.0, pdfs, counts, 2, 0);
    EXPECT_NEAR(c.estimate(), 7.0 / 3.5, 1e-6);

    // Unbiasedness of the fixed-set estimator: integral of f(x) = 3x^2 on [0,1] with techniques
    // p_0 = 1 (3 samples) and p_1 = 2x (1 sample), combined over 20000 realizations.
    Rng rng(11, 12);
    stats::MeanEstimator mean;
    const int R = 20000;
    for (int r = 0; r < R; ++r) {
        SmisCombiner<double, double> est;
        const double cnt[] = {3.0, 1.0};
        for (int k = 0; k < 2; ++k)
            for (int s = 0; s < static_cast<int>(cnt[k]); ++s) {
                double u = rng.next_double();
                double x = k == 0 ? u : std::sqrt(u);
                const double p[] = {1.0, 2.0 * x};
                est.add(3.0 * x * x, p, cnt, 2, k);
            }
        mean.add(est.estimate());
    }
    EXPECT_GE(stats::z_test_mean(mean, 1.0).p_value, 1e-4) << mean.mean() << " +- " << mean.std_error();
}

TEST(MisSmis, StratifiedAndRotatedPatternsStayInUnitInterval) {
    const float u_max = one_minus_epsilon<float>();
    EXPECT_LT(u_max, 1.0f);
    for (int n : {1, 2, 3, 7, 64}) {
        for (float u : {0.0f, 0.3f, u_max}) {
            for (int j = 0; j < n; ++j) {
                float s = stratified_1d(u, n, j);
                EXPECT_GE(s, static_cast<float>(j) / n - 1e-6f);
                EXPECT_LT(s, 1.0f);
                EXPECT_LE(s, static_cast<float>(j + 1) / n + 1e-6f);
                float r = rotate_1d(static_cast<float>(j) / n, u);
                EXPECT_GE(r, 0.0f);
                EXPECT_LT(r, 1.0f);
            }
        }
    }
    EXPECT_DOUBLE_EQ(stratified_1d(0.5, 4, 2), 0.625);
    EXPECT_DOUBLE_EQ(rotate_1d(0.75, 0.5), 0.25);
}

}  // namespace
