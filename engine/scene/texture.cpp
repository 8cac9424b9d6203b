#include "scene/texture.h"

#include <cmath>
#include <stdexcept>

namespace smis {

float srgb_to_linear(float v) {
    return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}

Texture::Texture(const float* rgba, int width, int height, const std::string& colorspace, bool closest, Wrap wrap)
    : width_(width), height_(height), closest_(closest), wrap_(wrap) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("texture size must be positive");
    bool srgb = colorspace == "sRGB";
    if (!srgb && colorspace != "linear") throw std::invalid_argument("texture colour space must be sRGB or linear");
    rgba_.assign(rgba, rgba + size_t(4) * width * height);
    for (size_t i = 0; i < rgba_.size(); ++i) {
        float& v = rgba_[i];
        if (!std::isfinite(v)) v = 0.0f;  // a NaN texel would reach the film through every path
        if (srgb && i % 4 != 3) v = srgb_to_linear(std::max(v, 0.0f));
    }
    double sum[3] = {0.0, 0.0, 0.0};
    for (size_t i = 0; i < rgba_.size(); i += 4)
        for (int c = 0; c < 3; ++c) sum[c] += std::max(rgba_[i + c], 0.0f);
    double n = double(width) * height;
    mean_ = vmax(Color(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)), Color(1e-6f));
}

const float* Texture::texel(int x, int y) const {
    switch (wrap_) {
        case Wrap::Repeat:
            x %= width_, y %= height_;
            x += x < 0 ? width_ : 0, y += y < 0 ? height_ : 0;
            break;
        case Wrap::Extend:
            x = std::min(std::max(x, 0), width_ - 1), y = std::min(std::max(y, 0), height_ - 1);
            break;
        case Wrap::Clip:
            if (x < 0 || y < 0 || x >= width_ || y >= height_) return nullptr;
            break;
    }
    return &rgba_[4 * (size_t(y) * width_ + x)];
}

TextureSample Texture::lookup(Point2 uv) const {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return {};
    // Texel centres at (i + 0.5) / width, as Blender and Cycles place them.
    float fx = uv.x * width_ - 0.5f, fy = uv.y * height_ - 0.5f;
    // Keep huge coordinates in int range (Repeat is periodic, Extend/Clip saturate anyway).
    const float limit = 1e7f;
    fx = std::min(std::max(fx, -limit), limit), fy = std::min(std::max(fy, -limit), limit);
    float x0f = std::floor(fx), y0f = std::floor(fy);
    int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    float tx = fx - x0f, ty = fy - y0f;
    float acc[4] = {0, 0, 0, 0};
    auto add = [&](int x, int y, float w) {
        const float* t = texel(x, y);
        if (!t || w == 0.0f) return;
        for (int c = 0; c < 4; ++c) acc[c] += w * t[c];
    };
    if (closest_) {
        add(tx < 0.5f ? x0 : x0 + 1, ty < 0.5f ? y0 : y0 + 1, 1.0f);
    } else {
        add(x0, y0, (1 - tx) * (1 - ty));
        add(x0 + 1, y0, tx * (1 - ty));
        add(x0, y0 + 1, (1 - tx) * ty);
        add(x0 + 1, y0 + 1, tx * ty);
    }
    return {Color(acc[0], acc[1], acc[2]), acc[3]};
}

}  // namespace smis
