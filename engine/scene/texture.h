// Image textures as Blender's Image Texture node reads them: RGBA in scene-linear, looked up at a UV
// with bilinear (Linear) or nearest (Closest) filtering and Repeat / Extend / Clip wrapping.
#pragma once
#include <string>
#include <vector>

#include "core/math.h"
#include "core/sampling.h"

namespace smis {

struct TextureSample {
    Color rgb{0.0f};
    float alpha = 0.0f;
};

class Texture {
public:
    enum class Wrap { Repeat, Extend, Clip };
    // rgba: width x height x 4 floats, row 0 the bottom (Blender's Image.pixels order). Colour
    // channels of an "sRGB" image are linearised here, once; "linear" data is kept as is.
    Texture(const float* rgba, int width, int height, const std::string& colorspace, bool closest, Wrap wrap);
    TextureSample lookup(Point2 uv) const;
    int width() const { return width_; }
    // Mean RGB over the texels (for light selection by power); at least a tiny positive value so
    // that a dark texture's emitters can still be chosen.
    Color mean() const { return mean_; }
    int height() const { return height_; }

private:
    const float* texel(int x, int y) const;  // null outside the image for Clip
    int width_, height_;
    bool closest_;
    Wrap wrap_;
    std::vector<float> rgba_;
    Color mean_{0.0f};
};

// The sRGB transfer function's inverse (IEC 61966-2-1), what Blender's "sRGB" colour space applies.
float srgb_to_linear(float v);

}  // namespace smis
