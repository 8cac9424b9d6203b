// Wavelength sampling: a sampled wavelength stays in the bin its CDF value selected, and the density
// the estimators weight it with is that bin's.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "spectral/wavelength_sampling.h"

using namespace smis;
using namespace smis::spectral;

namespace {

// Density 1 on the first 200 bins, 3 on the rest: bins 199 and 200 (559 and 560 nm) differ.
constexpr int kStep = 200;
std::vector<double> step_weights() {
    std::vector<double> w(WavelengthPdf::kBins, 1.0);
    for (int b = kStep; b < WavelengthPdf::kBins; ++b) w[b] = 3.0;
    return w;
}
constexpr double kTotal = kStep + 3.0 * (WavelengthPdf::kBins - kStep);

// The largest float below the CDF at the step: its CDF interval is bin 199's, 2e-5 of a bin below
// the edge, so 559 + f (f = 0.99998) rounded to 560 nm in float before the fix, in bin 200.
float u_just_below_step() {
    double edge = kStep / kTotal;
    float u = float(edge);
    while (!(double(u) < edge)) u = std::nextafter(u, 0.0f);
    return u;
}

}  // namespace

TEST(WavelengthPdf, SampleJustBelowABinEdgeStaysInItsBin) {
    WavelengthPdf pdf(step_weights());
    float u = u_just_below_step();
    float lambda = pdf.sample(u);
    EXPECT_LT(lambda, kLambdaMin + kStep) << "u = " << u;
    EXPECT_GE(lambda, kLambdaMin + kStep - 1);
    EXPECT_FLOAT_EQ(pdf.pdf(lambda), float(1.0 / kTotal)) << "lambda = " << lambda;
}

TEST(WavelengthPdf, SampleReturnsTheSampledBinsDensity) {
    WavelengthPdf pdf(step_weights());
    float density = -1.0f;
    float lambda = pdf.sample(u_just_below_step(), &density);
    EXPECT_FLOAT_EQ(density, float(1.0 / kTotal));
    EXPECT_EQ(density, pdf.pdf(lambda));
}

// Every bin edge of an uneven density, approached from below and from above by a few floats: the
// wavelength's bin is the one whose CDF interval holds u, and the returned density is its density.
TEST(WavelengthPdf, EveryBinEdgeFromBothSides) {
    std::vector<double> w(WavelengthPdf::kBins);
    for (int b = 0; b < WavelengthPdf::kBins; ++b) w[b] = 1.0 + 0.9 * std::sin(0.37 * b) + (b % 7 == 3 ? 5.0 : 0.0);
    WavelengthPdf pdf(w);
    std::vector<double> cdf(WavelengthPdf::kBins + 1, 0.0);
    for (int b = 0; b < WavelengthPdf::kBins; ++b) cdf[b + 1] = cdf[b] + w[b];
    for (double& c : cdf) c /= cdf.back();
    int checked = 0, failures = 0;
    for (int b = 1; b < WavelengthPdf::kBins; ++b) {
        float u = float(cdf[b]);
        for (int k = 0; k < 4; ++k) u = std::nextafter(u, 0.0f);
        for (int k = 0; k < 8; ++k, u = std::nextafter(u, 1.0f)) {
            int expected = double(u) < cdf[b] ? b - 1 : b;
            float density = -1.0f;
            float lambda = pdf.sample(u, &density);
            bool ok = int(std::floor(lambda - kLambdaMin)) == expected && density == pdf.pdf(lambda) &&
                      std::fabs(double(density) - (cdf[expected + 1] - cdf[expected])) < 1e-7;
            failures += !ok;
            ++checked;
            if (!ok && failures <= 5)
                ADD_FAILURE() << "u = " << u << " (bin " << expected << "): lambda " << lambda << ", density "
                              << density << ", pdf(lambda) " << pdf.pdf(lambda);
        }
    }
    EXPECT_EQ(failures, 0) << "of " << checked;
}

// The sampler's weights use the sampled bin's density: SPECTRAL_IS's q and HERO's hero density.
TEST(WavelengthSampler, WeightsUseTheSampledBinsDensity) {
    WavelengthPdf pdf(step_weights());
    float u = u_just_below_step();
    Rng rng(1, 0);
    WavelengthSet ws;
    WavelengthSampler(SpectralMode::SpectralIs, 1, pdf).sample(u, 0.0f, rng, &ws);
    EXPECT_LT(ws.lambda[0], kLambdaMin + kStep);
    EXPECT_FLOAT_EQ(ws.q[0], float(1.0 / kTotal));
    WavelengthSampler(SpectralMode::Hero, 4, pdf).sample(u, 0.0f, rng, &ws);
    EXPECT_LT(ws.lambda[0], kLambdaMin + kStep);
    EXPECT_FLOAT_EQ(ws.a[0], float(1.0 / kTotal));
    WavelengthSampler(SpectralMode::Smis, 1, pdf).sample(u, 0.0f, rng, &ws);
    EXPECT_LT(ws.lambda[0], kLambdaMin + kStep);
    EXPECT_FLOAT_EQ(ws.q[0], float(1.0 / kTotal));
}
