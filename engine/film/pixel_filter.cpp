#include "film/pixel_filter.h"

#include <cmath>

namespace smis {

PixelFilter::PixelFilter(PixelFilterKind kind, float width) : width_(width) {
    if (!(width > 0.0f) || !std::isfinite(width)) width_ = 1.0f;
    if (kind == PixelFilterKind::Box) return;
    const int n = 1024;
    float support = kind == PixelFilterKind::BlackmanHarris ? 2.0f * width_ : width_;
    auto f = [&](float x) {  // x in [-support/2, support/2]
        if (kind == PixelFilterKind::Gaussian) return std::exp(-2.0f * sqr(x / (0.5f * width_)));
        float t = 2.0f * kPi * (x / support + 0.5f);
        return 0.35875f - 0.48829f * std::cos(t) + 0.14128f * std::cos(2 * t) - 0.01168f * std::cos(3 * t);
    };
    std::vector<double> cdf(n + 1, 0.0);
    for (int i = 0; i < n; ++i) cdf[i + 1] = cdf[i] + std::max(0.0f, f(support * ((i + 0.5f) / n - 0.5f)));
    inverse_cdf_.resize(n + 1);
    // Invert the tabulated CDF onto a uniform grid of u.
    int j = 0;
    for (int k = 0; k <= n; ++k) {
        double target = cdf[n] * k / n;
        while (j < n - 1 && cdf[j + 1] < target) ++j;
        double span = cdf[j + 1] - cdf[j];
        double frac = span > 0 ? (target - cdf[j]) / span : 0.0;
        inverse_cdf_[k] = support * static_cast<float>((j + frac) / n - 0.5);
    }
    width_ = support;
}

float PixelFilter::warp(float u) const {
    if (inverse_cdf_.empty()) return (u - 0.5f) * width_;
    float x = u * (inverse_cdf_.size() - 1);
    int i = std::min(static_cast<int>(x), static_cast<int>(inverse_cdf_.size()) - 2);
    float t = x - i;
    return inverse_cdf_[i] * (1 - t) + inverse_cdf_[i + 1] * t;
}

}  // namespace smis
