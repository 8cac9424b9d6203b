// Pixel reconstruction by filter importance sampling, as Cycles does it: each camera sample is offset
// from the pixel centre by a draw from the (separable) filter, and all samples weigh the same.
#pragma once
#include <vector>

#include "core/sampling.h"

namespace smis {

// The filter shapes (the render setting `filter`, addon/smis_render/settings_schema.py).
enum class PixelFilterKind { BlackmanHarris, Gaussian, Box };

class PixelFilter {
public:
    // Blackman-Harris is Cycles' default (width 1.5 px; Cycles doubles the width of Blackman-Harris
    // internally so its support matches a Gaussian of the same nominal width).
    explicit PixelFilter(PixelFilterKind kind = PixelFilterKind::Box, float width = 1.0f);
    // Offset from the pixel centre, in pixels.
    Point2 sample(Point2 u) const { return {warp(u.x), warp(u.y)}; }

private:
    float warp(float u) const;
    std::vector<float> inverse_cdf_;  // empty for the box filter
    float width_;
};

}  // namespace smis
