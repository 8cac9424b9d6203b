// Image textures as Cycles 3.4's Image Texture node reads them (kernel/device/cpu/image.h and
// svm/image.h): RGBA looked up at a UV with Linear (bilinear), Closest or Cubic (uniform cubic
// B-spline; Blender's "Smart" is Cubic on the CPU) interpolation and Repeat / Extend / Clip / Mirror
// extension, with Cycles' alpha association and sRGB decoding.
//
// What the Python side must pass (all measured against Blender 3.4.1's Cycles, see texture_test.cpp):
//  * rgba: Image.pixels (row 0 the bottom), with two exceptions where Blender's copy differs from the
//    file Cycles reads itself (colour images only; Blender leaves data images' pixels alone): a float
//    image (Image.is_float) with alpha_mode STRAIGHT holds RGB that Blender premultiplied, while Cycles
//    uses the file as stored: divide RGB by alpha where alpha > 0; a byte image with alpha_mode PREMUL
//    holds RGB that Blender un-premultiplied (and clamped at 1): multiply back,
//    RGB = round(255 * RGB * alpha) / 255 (exact for valid premultiplied bytes, RGB <= alpha).
//  * colorspace: "sRGB" for a byte image in sRGB (Cycles keeps its bytes encoded and decodes after
//    interpolation); "data" for Non-Color / Raw (alpha never touches the RGB); "linear" for everything
//    else (float images, which Blender already converted to scene linear, and byte Linear images).
//  * Options::alpha_mode = Image.alpha_mode, Options::byte_image = not Image.is_float,
//    Options::alpha_linked = the node's Alpha output is linked to something that reaches an output
//    (Cycles then un-premultiplies the Color output, otherwise Color is premultiplied).
// In short, Cycles 3.4 does:
//  * load: alpha = 1 for alpha_mode NONE; RGB *= alpha (in 8 bits, truncating) for a byte image whose
//    colour space is not data and alpha_mode is STRAIGHT or PREMUL (PNG files are read as straight
//    even when marked PREMUL); float files (EXR) are taken as premultiplied as they are.
//  * lookup: interpolate the stored values; if alpha_linked (and not data, STRAIGHT or PREMUL) and
//    0 < alpha < 1: RGB /= alpha; then decode sRGB (byte sRGB images). Alpha is the interpolated alpha.
//  * a missing or unreadable image, or no image at all: magenta (1, 0, 1), alpha 1 (Texture::missing()).
// Not reproduced (from Cycles' source, not measured): images Cycles reads at another depth than
// Blender (a 16-bit PNG is float in Blender but 16-bit sRGB in Cycles, interpolated before decoding),
// byte images in colour spaces other than sRGB / linear / data (Cycles converts those at load).
#pragma once
#include <memory>
#include <mutex>
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
    // Repeat: periodic; Extend: edge texels continue; Clip: transparent black outside the image
    // (and texels outside blend in as transparent black at the border); Mirror: periodic with every
    // other copy flipped (Cycles after 3.4; Blender 3.4 has no MIRROR extension, so unverified here).
    enum class Wrap { Repeat, Extend, Clip, Mirror };
    enum class Interp { Linear, Closest, Cubic };
    // Blender's Image.alpha_mode.
    enum class AlphaMode { Straight, Premul, ChannelPacked, None };
    struct Options {
        Interp interp = Interp::Linear;
        Wrap wrap = Wrap::Repeat;
        // The default uses the pixels as given: no association at load, none undone at lookup.
        AlphaMode alpha_mode = AlphaMode::ChannelPacked;
        bool byte_image = false;    // pixels are 8-bit values k / 255 (Image.is_float is False)
        bool alpha_linked = false;  // the node's Alpha output is used: Color is un-premultiplied
    };

    // rgba: width x height x 4 floats, row 0 the bottom (Blender's Image.pixels order); colorspace
    // "sRGB", "linear" or "data" (see above). Non-finite texels become 0.
    Texture(const float* rgba, int width, int height, const std::string& colorspace, const Options& options);
    Texture(const float* rgba, int width, int height, const std::string& colorspace, Interp interp, Wrap wrap);
    Texture(const float* rgba, int width, int height, const std::string& colorspace, bool closest, Wrap wrap);

    // Cycles' stand-in for an image it cannot load: 1 x 1 magenta, alpha 1.
    static std::shared_ptr<Texture> missing();

    // The node's Color and Alpha at uv (flat projection: uv = the Vector input's x, y).
    TextureSample lookup(Point2 uv) const;
    int width() const { return width_; }
    int height() const { return height_; }
    // One texel that every lookup returns whatever the coordinate (not clipped): Cycles' magenta
    // stand-in for a missing image, a 1 x 1 colour image.
    bool constant() const { return width_ == 1 && height_ == 1 && options_.wrap != Wrap::Clip; }
    // Mean RGB over the texels (for light selection by power); at least a tiny positive value so
    // that a dark texture's emitters can still be chosen. Computed on the first call: only emission
    // textures need it, and decoding every texel at load costs more than the rest of loading.
    Color mean() const;
    // Whether every lookup's Color is >= 0 in each channel: it is when every stored texel's four
    // channels are (non-finite ones are 0 already), as neither the interpolation (non-negative
    // weights, the B-spline's too), the un-premultiplication (by the interpolated alpha, then >= 0)
    // nor the sRGB decoding turns them negative. Computed on the first call, as mean() is.
    bool non_negative() const;

private:
    int wrap_index(int i, int n) const;  // -1: outside (Clip)
    const float* texel(int x, int y) const { return &rgba_[4 * (size_t(y) * width_ + x)]; }
    void finish(float v[4]) const;  // stored (interpolated) value -> node output
    int width_, height_;
    Options options_;
    bool srgb_;          // stored values are sRGB-encoded, decoded after interpolation
    bool unpremultiply_; // lookups divide RGB by alpha
    bool finished_;      // texels already hold node outputs (Closest: no interpolation in between)
    std::vector<float> rgba_;
    mutable std::once_flag mean_once_;
    mutable Color mean_{0.0f};
    mutable std::once_flag non_negative_once_;
    mutable bool non_negative_ = false;
};

// The sRGB transfer function's inverse (IEC 61966-2-1), as Cycles decodes sRGB (0 for negatives).
float srgb_to_linear(float v);

}  // namespace smis
