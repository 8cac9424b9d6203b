#include "scene/texture.h"

#include <emmintrin.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace smis {

namespace {

// Cycles' split of a coordinate into texel index and fraction: truncation, one less for negatives, so
// a negative whole number x gives (x - 1, 1) rather than (x, 0); that decides Closest's texel there.
inline float split(float x, int* i) {
    int k = static_cast<int>(x) - (x < 0.0f ? 1 : 0);
    *i = k;
    return x - static_cast<float>(k);
}

// Uniform cubic B-spline weights of the 4 texels around t in [0, 1] (Cycles' bicubic filter; they
// are positive and sum to 1, so the result stays within the texels' range).
inline void bspline_weights(float t, float w[4]) {
    w[0] = (((-1.0f / 6.0f) * t + 0.5f) * t - 0.5f) * t + (1.0f / 6.0f);
    w[1] = ((0.5f * t - 1.0f) * t) * t + (2.0f / 3.0f);
    w[2] = ((-0.5f * t + 0.5f) * t + 0.5f) * t + (1.0f / 6.0f);
    w[3] = (1.0f / 6.0f) * t * t * t;
}

// Keeps huge coordinates in int range (Repeat is periodic, Extend/Clip saturate, and at this size a
// float has no fraction left).
constexpr float kCoordLimit = 1e7f;

// x^2.4 for x in [0.09, 1] (the power segment of the decode), computed as Cycles 3.4 does for byte
// sRGB images (util/color.h, fastpow24): y = (x^4)^(1/5) from a first guess made on the float's bit
// pattern (read as a scaled log2), refined by three Newton steps on y^5 = x^4, then y^3. The guess is
// within ~7 %, Newton squares the relative error (times 2) per step, so the result is at float
// rounding level (Texture.FastSrgbDecodeMatchesPow bounds it); a third of glibc powf's instructions.
inline float pow24_unit(float x) {
    int32_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    constexpr int32_t kOne = 0x3F800000;  // the bit pattern of 1.0f
    const int32_t guess_bits = kOne + static_cast<int32_t>(0.8f * static_cast<float>(bits - kOne));
    float y;
    std::memcpy(&y, &guess_bits, sizeof y);
    const float x2 = x * x, x4 = x2 * x2;
    for (int step = 0; step < 3; ++step) {
        const float y2 = y * y;
        y = 0.8f * y + 0.2f * x4 / (y2 * y2);
    }
    return y * y * y;
}

// pow24_unit on four lanes: per lane the same IEEE operations in the same order (cvtdq2ps and
// cvttps2dq round as the scalar casts do), so each lane is bit for bit pow24_unit of its value, with
// one division per Newton step for all lanes instead of one per channel.
inline __m128 pow24_unit4(__m128 x) {
    const __m128i one = _mm_set1_epi32(0x3F800000);
    const __m128 scaled = _mm_mul_ps(_mm_set1_ps(0.8f), _mm_cvtepi32_ps(_mm_sub_epi32(_mm_castps_si128(x), one)));
    __m128 y = _mm_castsi128_ps(_mm_add_epi32(one, _mm_cvttps_epi32(scaled)));
    const __m128 x2 = _mm_mul_ps(x, x), x4 = _mm_mul_ps(x2, x2);
    const __m128 tail = _mm_mul_ps(_mm_set1_ps(0.2f), x4);
    for (int step = 0; step < 3; ++step) {
        const __m128 y2 = _mm_mul_ps(y, y);
        y = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(0.8f), y), _mm_div_ps(tail, _mm_mul_ps(y2, y2)));
    }
    return _mm_mul_ps(_mm_mul_ps(y, y), y);
}

// std::lround of x in [0, 2^24) without the library call (texture loads round four values a texel):
// x - trunc(x) is exact there, so comparing the fraction with 0.5 rounds halves up as lround does.
inline uint32_t round_half_up(float x) {
    const auto k = static_cast<uint32_t>(x);
    return k + (x - static_cast<float>(k) >= 0.5f ? 1u : 0u);
}

}  // namespace

float srgb_to_linear(float v) {
    if (v < 0.04045f) return v < 0.0f ? 0.0f : v * (1.0f / 12.92f);
    // Above 1 (float images) or NaN: the exact power; the fast one is only checked on [0.04045, 1].
    if (!(v <= 1.0f)) return std::pow((v + 0.055f) * (1.0f / 1.055f), 2.4f);
    return pow24_unit((v + 0.055f) * (1.0f / 1.055f));
}

namespace {

// srgb_to_linear of the three colour channels, bit for bit: the power segment of all three at once
// when each lies in it (nearly every lookup of an 8-bit colour texture), else channel by channel.
void srgb_to_linear3(float v[3]) {
    const auto power_segment = [](float c) { return c >= 0.04045f && c <= 1.0f; };
    if (!(power_segment(v[0]) && power_segment(v[1]) && power_segment(v[2]))) {
        for (int c = 0; c < 3; ++c) v[c] = srgb_to_linear(v[c]);
        return;
    }
    const __m128 x = _mm_mul_ps(_mm_add_ps(_mm_setr_ps(v[0], v[1], v[2], 1.0f), _mm_set1_ps(0.055f)),
                                _mm_set1_ps(1.0f / 1.055f));
    float out[4];
    _mm_storeu_ps(out, pow24_unit4(x));
    v[0] = out[0], v[1] = out[1], v[2] = out[2];
}

}  // namespace

Texture::Texture(const float* rgba, int width, int height, const std::string& colorspace, bool closest, Wrap wrap)
    : Texture(rgba, width, height, colorspace, closest ? Interp::Closest : Interp::Linear, wrap) {}

Texture::Texture(const float* rgba, int width, int height, const std::string& colorspace, Interp interp, Wrap wrap)
    : Texture(rgba, width, height, colorspace, Options{interp, wrap}) {}

Texture::Texture(const float* rgba, int width, int height, const std::string& colorspace, const Options& options)
    : width_(width), height_(height), options_(options) {
    if (width <= 0 || height <= 0) throw std::invalid_argument("texture size must be positive");
    srgb_ = colorspace == "sRGB";
    bool data = colorspace == "data";
    if (!srgb_ && !data && colorspace != "linear")
        throw std::invalid_argument("texture colour space must be sRGB, linear or data");
    const AlphaMode mode = options.alpha_mode;
    // Cycles associates alpha of colour (not data) images unless told to ignore or keep it packed;
    // of the files only straight ones get multiplied (byte images: Blender's byte buffers are straight,
    // and a PNG is read as straight whatever its alpha_mode), float files are premultiplied already.
    const bool associated = !data && (mode == AlphaMode::Straight || mode == AlphaMode::Premul);
    const bool premultiply = associated && options.byte_image;
    unpremultiply_ = associated && options.alpha_linked;

    rgba_.assign(rgba, rgba + size_t(4) * width * height);
    for (size_t i = 0; i < rgba_.size(); i += 4) {
        float* t = &rgba_[i];
        // Cycles zeroes a whole texel with any non-finite channel.
        if (!std::isfinite(t[0]) || !std::isfinite(t[1]) || !std::isfinite(t[2]) || !std::isfinite(t[3]))
            t[0] = t[1] = t[2] = t[3] = 0.0f;
        if (mode == AlphaMode::None) t[3] = 1.0f;
        if (premultiply) {
            // In 8 bits, truncating, as Cycles' loader does; then read back as k / 255.
            auto byte = [](float v) { return round_half_up(clampf(v, 0.0f, 1.0f) * 255.0f); };
            uint32_t a = byte(t[3]);
            for (int c = 0; c < 3; ++c) t[c] = static_cast<float>(byte(t[c]) * a / 255u) * (1.0f / 255.0f);
            t[3] = static_cast<float>(a) * (1.0f / 255.0f);
        }
    }
    // Closest returns one texel as it is, so its node output can be computed once here.
    finished_ = options.interp == Interp::Closest;
    if (finished_)
        for (size_t i = 0; i < rgba_.size(); i += 4) finish(&rgba_[i]);
}

Color Texture::mean() const {
    std::call_once(mean_once_, [this] {
        double sum[3] = {0.0, 0.0, 0.0};
        for (size_t i = 0; i < rgba_.size(); i += 4) {
            float v[4] = {rgba_[i], rgba_[i + 1], rgba_[i + 2], rgba_[i + 3]};
            if (!finished_) finish(v);
            for (int c = 0; c < 3; ++c) sum[c] += std::max(v[c], 0.0f);
        }
        double n = double(width_) * height_;
        mean_ = vmax(Color(float(sum[0] / n), float(sum[1] / n), float(sum[2] / n)), Color(1e-6f));
    });
    return mean_;
}

bool Texture::non_negative() const {
    std::call_once(non_negative_once_, [this] {
        bool all = true;
        for (size_t i = 0; i < rgba_.size() && all; i += 4)
            all = rgba_[i] >= 0.0f && rgba_[i + 1] >= 0.0f && rgba_[i + 2] >= 0.0f && rgba_[i + 3] >= 0.0f;
        non_negative_ = all;
    });
    return non_negative_;
}

std::shared_ptr<Texture> Texture::missing() {
    static const float magenta[4] = {1.0f, 0.0f, 1.0f, 1.0f};
    return std::make_shared<Texture>(magenta, 1, 1, "linear", Options{Interp::Closest, Wrap::Repeat});
}

void Texture::finish(float v[4]) const {
    float a = v[3];
    if (unpremultiply_ && a != 1.0f && a != 0.0f)
        for (int c = 0; c < 3; ++c) v[c] /= a;
    if (srgb_) srgb_to_linear3(v);
}

inline int Texture::wrap_index(int i, int n) const {
    switch (options_.wrap) {
        case Wrap::Repeat:
            i %= n;
            return i < 0 ? i + n : i;
        case Wrap::Extend:
            return std::min(std::max(i, 0), n - 1);
        case Wrap::Clip:
            return i < 0 || i >= n ? -1 : i;
        case Wrap::Mirror: {
            // Reflect about the image's edges: ..., 1, 0 | 0, 1, ..., n-1 | n-1, n-2, ...
            int m = std::abs(i + (i < 0 ? 1 : 0)) % (2 * n);
            return m >= n ? 2 * n - m - 1 : m;
        }
    }
    return -1;
}

TextureSample Texture::lookup(Point2 uv) const {
    if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) return {};
    float u = clampf(uv.x, -kCoordLimit, kCoordLimit), v = clampf(uv.y, -kCoordLimit, kCoordLimit);
    float acc[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    if (options_.interp == Interp::Closest) {
        int ix, iy;
        split(u * static_cast<float>(width_), &ix);
        split(v * static_cast<float>(height_), &iy);
        ix = wrap_index(ix, width_), iy = wrap_index(iy, height_);
        if (ix < 0 || iy < 0) return {};
        const float* t = texel(ix, iy);
        return {Color(t[0], t[1], t[2]), t[3]};
    }
    // Linear and Cubic: texel centres at (i + 0.5) / size.
    int ix, iy;
    float tx = split(u * static_cast<float>(width_) - 0.5f, &ix);
    float ty = split(v * static_cast<float>(height_) - 0.5f, &iy);
    auto add = [&](int x, int y, float w) {
        if (x < 0 || y < 0) return;  // outside a clipped image: transparent black
        const float* t = texel(x, y);
        for (int c = 0; c < 4; ++c) acc[c] += w * t[c];
    };
    if (options_.interp == Interp::Linear) {
        int x0, x1, y0, y1;
        if (options_.wrap == Wrap::Repeat) {
            // (i + 1) mod n from i mod n: one division per axis instead of two.
            x0 = wrap_index(ix, width_), y0 = wrap_index(iy, height_);
            x1 = x0 + 1 == width_ ? 0 : x0 + 1;
            y1 = y0 + 1 == height_ ? 0 : y0 + 1;
        } else {
            x0 = wrap_index(ix, width_), x1 = wrap_index(ix + 1, width_);
            y0 = wrap_index(iy, height_), y1 = wrap_index(iy + 1, height_);
        }
        add(x0, y0, (1.0f - ty) * (1.0f - tx));
        add(x1, y0, (1.0f - ty) * tx);
        add(x0, y1, ty * (1.0f - tx));
        add(x1, y1, ty * tx);
    } else {
        float wx[4], wy[4];
        bspline_weights(tx, wx);
        bspline_weights(ty, wy);
        int xs[4], ys[4];
        for (int k = 0; k < 4; ++k) xs[k] = wrap_index(ix - 1 + k, width_), ys[k] = wrap_index(iy - 1 + k, height_);
        for (int j = 0; j < 4; ++j) {
            // Cycles sums each row with its x weights, then weights the rows.
            float row[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            for (int k = 0; k < 4; ++k) {
                if (xs[k] < 0 || ys[j] < 0) continue;
                const float* t = texel(xs[k], ys[j]);
                for (int c = 0; c < 4; ++c) row[c] += wx[k] * t[c];
            }
            for (int c = 0; c < 4; ++c) acc[c] += wy[j] * row[c];
        }
    }
    finish(acc);
    return {Color(acc[0], acc[1], acc[2]), acc[3]};
}

}  // namespace smis
