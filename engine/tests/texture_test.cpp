// Image textures: texel placement, bilinear weights, wrapping and sRGB decoding as Blender's Image
// Texture node; a textured material scales its lobe by the texture at the hit's UV; alpha cut-outs
// are hit with frequency alpha. The Cycles tables were measured with Blender 3.4.1 (CPU, 1 sample
// per pixel so that each pixel's colour and its rendered texture coordinate come from the same
// point): an emission plane / UV sphere / oblique cube showing a 5 x 3 image (an 8-bit sRGB PNG, a
// float EXR), every interpolation x extension, alpha modes and projections. Over all rendered pixels
// the engine differed from Cycles by at most 6e-7.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "core/rng.h"
#include "scene/material.h"
#include "scene/scene.h"
#include "scene/texture.h"
#include "shading/image_projection.h"

using namespace smis;

namespace {

// 2 x 2 RGBA, bottom row first: (0,0) black, (1,0) red, (0,1) green, (1,1) white; alpha 0.25 .. 1.
const float kPixels[] = {0, 0, 0, 0.25f, 1, 0, 0, 0.5f, 0, 1, 0, 0.75f, 1, 1, 1, 1};

}  // namespace

TEST(Texture, TexelCentresAndBilinearWeights) {
    Texture t(kPixels, 2, 2, "linear", false, Texture::Wrap::Extend);
    TextureSample red = t.lookup({0.75f, 0.25f});  // texel (1, 0)'s centre
    EXPECT_FLOAT_EQ(red.rgb.x, 1.0f);
    EXPECT_FLOAT_EQ(red.rgb.y, 0.0f);
    EXPECT_FLOAT_EQ(red.alpha, 0.5f);
    TextureSample mid = t.lookup({0.5f, 0.5f});  // equal weights of all four
    EXPECT_FLOAT_EQ(mid.rgb.x, 0.5f);
    EXPECT_FLOAT_EQ(mid.rgb.y, 0.5f);
    EXPECT_FLOAT_EQ(mid.rgb.z, 0.25f);
    EXPECT_FLOAT_EQ(mid.alpha, 0.625f);
    TextureSample edge = t.lookup({0.6f, 0.25f});  // 0.7 of the way from black to red
    EXPECT_NEAR(edge.rgb.x, 0.7f, 1e-6f);
}

TEST(Texture, WrapModes) {
    Texture repeat(kPixels, 2, 2, "linear", true, Texture::Wrap::Repeat);
    Texture clip(kPixels, 2, 2, "linear", true, Texture::Wrap::Clip);
    Texture extend(kPixels, 2, 2, "linear", true, Texture::Wrap::Extend);
    EXPECT_FLOAT_EQ(repeat.lookup({1.75f, -0.75f}).rgb.x, 1.0f);  // = (0.75, 0.25): red
    EXPECT_FLOAT_EQ(clip.lookup({1.75f, 0.25f}).alpha, 0.0f);
    EXPECT_FLOAT_EQ(extend.lookup({5.0f, 0.25f}).rgb.x, 1.0f);
    EXPECT_FLOAT_EQ(repeat.lookup({NAN, 0.5f}).alpha, 0.0f);
}

// Linear Repeat blends the last texel of a row (column) with the first across the seam: at u = 0 and
// u = 1 (and every whole number) a 4 x 3 image gives the mean of its last and first columns, and
// likewise in v. Red counts the column, green the row, so a wrong neighbour shows in one channel.
TEST(Texture, LinearRepeatBlendsAcrossTheSeam) {
    const int w = 4, h = 3;
    std::vector<float> px;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) px.insert(px.end(), {float(x), float(y), 0.0f, 1.0f});
    Texture t(px.data(), w, h, "linear", Texture::Interp::Linear, Texture::Wrap::Repeat);
    const float row1 = 1.5f / h;  // the centre of row 1
    for (float u : {0.0f, 1.0f, -1.0f, 3.0f}) {
        TextureSample s = t.lookup({u, row1});
        EXPECT_NEAR(s.rgb.x, 0.5f * (float(w - 1) + 0.0f), 1e-5f) << "u = " << u;
        EXPECT_NEAR(s.rgb.y, 1.0f, 1e-5f) << "u = " << u;
    }
    const float col2 = 2.5f / w;  // the centre of column 2
    for (float v : {0.0f, 1.0f, 2.0f, -2.0f}) {
        TextureSample s = t.lookup({col2, v});
        EXPECT_NEAR(s.rgb.x, 2.0f, 1e-5f) << "v = " << v;
        EXPECT_NEAR(s.rgb.y, 0.5f * (float(h - 1) + 0.0f), 1e-5f) << "v = " << v;
    }
    // Just inside the seam: a quarter texel left of u = 1 is 3/4 of the last column, 1/4 of the first.
    EXPECT_NEAR(t.lookup({1.0f - 0.25f / w, row1}).rgb.x, 0.75f * float(w - 1), 1e-5f);
}

TEST(Texture, SrgbIsDecodedOnceAlphaIsNot) {
    const float grey[] = {0.5f, 0.5f, 0.5f, 0.5f};
    Texture t(grey, 1, 1, "sRGB", false, Texture::Wrap::Repeat);
    EXPECT_NEAR(t.lookup({0.3f, 0.3f}).rgb.x, 0.21404f, 1e-5f);
    EXPECT_FLOAT_EQ(t.lookup({0.3f, 0.3f}).alpha, 0.5f);
    EXPECT_THROW(Texture(grey, 1, 1, "Filmic", false, Texture::Wrap::Repeat), std::invalid_argument);
}

// The decode's power segment uses a Newton-refined x^2.4 (as Cycles' fastpow24) instead of powf:
// it must stay within 1e-6 relative of the exact power (measured max 5.3e-7; powf's own 2.8e-7)
// on a dense grid of [0.04045, 1] and on every 8-bit value, and be exact pow above 1.
TEST(Texture, FastSrgbDecodeMatchesPow) {
    auto exact = [](float v) { return std::pow((double(v) + 0.055) / 1.055, 2.4); };
    double worst = 0.0;
    auto check = [&](float v) {
        double ref = exact(v);
        worst = std::max(worst, std::abs(double(srgb_to_linear(v)) - ref) / ref);
    };
    const int n = 200000;
    for (int i = 0; i <= n; ++i) check(0.04045f + (1.0f - 0.04045f) * float(i) / float(n));
    for (int k = 11; k <= 255; ++k) check(float(k) / 255.0f);
    EXPECT_LT(worst, 1e-6);
    EXPECT_FLOAT_EQ(srgb_to_linear(1.0f), 1.0f);
    EXPECT_FLOAT_EQ(srgb_to_linear(1.5f), std::pow((1.5f + 0.055f) / 1.055f, 2.4f));
    EXPECT_TRUE(std::isnan(srgb_to_linear(std::nanf(""))));
}

// Lookups decode the three channels at once: bit for bit the channel-by-channel decode, whether all
// three lie in the power segment (the vector path) or some lie in the linear segment, below 0 or
// above 1 (channel by channel). Closest textures decode their texels at load, through the same code.
TEST(Texture, SrgbDecodeOfThreeChannelsIsTheScalarDecodeBitForBit) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> power(0.04045f, 1.0f), wide(-0.1f, 1.3f);
    std::vector<float> texels;
    auto add = [&](float r, float g, float b) { texels.insert(texels.end(), {r, g, b, 1.0f}); };
    for (int k = 0; k <= 255; ++k) add(k / 255.0f, ((k * 7) % 256) / 255.0f, ((k * 101) % 256) / 255.0f);
    for (int i = 0; i < 60000; ++i) add(power(rng), power(rng), power(rng));
    for (int i = 0; i < 20000; ++i) add(wide(rng), power(rng), wide(rng));
    add(0.04045f, 1.0f, std::nextafter(0.04045f, 0.0f));
    const int n = static_cast<int>(texels.size() / 4);
    Texture t(texels.data(), n, 1, "sRGB", true, Texture::Wrap::Repeat);
    int differing = 0;
    for (int i = 0; i < n; ++i) {
        const Color rgb = t.lookup({(i + 0.5f) / n, 0.5f}).rgb;
        const float got[3] = {rgb.x, rgb.y, rgb.z};
        const float want[3] = {srgb_to_linear(texels[4 * i]), srgb_to_linear(texels[4 * i + 1]),
                               srgb_to_linear(texels[4 * i + 2])};
        differing += std::memcmp(got, want, sizeof got) != 0;
    }
    EXPECT_EQ(differing, 0);
}

// Byte images with straight alpha are premultiplied in 8 bits at load, each channel rounded as
// std::lround rounds (halves up): checked on every value whose 255 multiple is a half, its float
// neighbours and a dense sweep, through Closest lookups of a linear image (texels returned as stored).
TEST(Texture, BytePremultiplyRoundsAsLround) {
    std::vector<float> values;
    for (int k = 0; k < 255; ++k) {
        const float half = (float(k) + 0.5f) / 255.0f;
        values.insert(values.end(), {half, std::nextafter(half, 0.0f), std::nextafter(half, 1.0f)});
    }
    for (int i = 0; i <= 4000; ++i) values.push_back(float(i) / 4000.0f);
    const float alphas[] = {1.0f, 0.5f, 101.5f / 255.0f, 0.2f};
    auto byte = [](float v) { return static_cast<uint32_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
    for (float alpha : alphas) {
        std::vector<float> rgba;
        for (float v : values) rgba.insert(rgba.end(), {v, v, v, alpha});
        Texture::Options o{Texture::Interp::Closest, Texture::Wrap::Repeat, Texture::AlphaMode::Straight, true, false};
        const int n = static_cast<int>(values.size());
        Texture t(rgba.data(), n, 1, "linear", o);
        const uint32_t a = byte(alpha);
        for (int i = 0; i < n; ++i) {
            const float expected = static_cast<float>(byte(values[i]) * a / 255u) * (1.0f / 255.0f);
            ASSERT_EQ(t.lookup({(float(i) + 0.5f) / float(n), 0.5f}).rgb.x, expected) << values[i] << " alpha " << alpha;
        }
        ASSERT_EQ(t.lookup({0.5f / float(n), 0.5f}).alpha, static_cast<float>(a) * (1.0f / 255.0f));
    }
}

// The mean light selection weighs textured emitters by is the average of the decoded texels (node
// outputs, negatives counted as 0), computed on first use and the same on every call.
TEST(Texture, MeanIsTheAverageOfDecodedTexels) {
    const float texels[] = {0.5f, 0.0f, 1.0f, 1.0f, 0.25f, 0.75f, 0.02f, 1.0f, -0.5f, 0.9f, 0.1f, 1.0f};
    Texture t(texels, 3, 1, "sRGB", false, Texture::Wrap::Repeat);
    for (int c = 0; c < 3; ++c) {
        double sum = 0.0;
        for (int i = 0; i < 3; ++i) sum += std::max(srgb_to_linear(texels[4 * i + c]), 0.0f);
        EXPECT_FLOAT_EQ(t.mean()[c], float(sum / 3.0)) << c;
    }
    EXPECT_EQ(t.mean().x, t.mean().x);
    const float dark[] = {0.0f, 0.0f, 0.0f, 1.0f};
    EXPECT_GT(Texture(dark, 1, 1, "linear", false, Texture::Wrap::Repeat).mean().x, 0.0f);
}

TEST(Texture, MaterialLobeTakesTheTextureAndObjectColour) {
    Material m;
    Lobe diffuse;
    diffuse.weight = Color(0.5f);
    m.lobes.push_back(diffuse);
    LobeInput in;
    in.texture = std::make_shared<Texture>(kPixels, 2, 2, "linear", true, Texture::Wrap::Repeat);
    in.object_color = true;
    m.inputs.push_back(in);
    SurfaceAttribs attr;
    attr.uv = {0.75f, 0.25f};  // red
    attr.object_color = Color(0.5f, 1.0f, 1.0f);
    Bsdf b = m.make_bsdf(Frame(Vec3(0, 0, 1)), Vec3(0, 0, 1), false, attr);
    EXPECT_FLOAT_EQ(b.lobe(0).weight.x, 0.25f);
    EXPECT_FLOAT_EQ(b.lobe(0).weight.y, 0.0f);
    EXPECT_TRUE(m.needs_uv());
}

TEST(Cutout, SurfaceOfAlphaAIsHitWithFrequencyA) {
    Scene s;
    Material m;
    m.lobes.push_back(Lobe{});
    m.alpha = 0.3f;
    uint32_t mat = s.add_material(m);
    const float quad[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const int32_t tris[] = {0, 1, 2, 0, 2, 3};
    s.add_instance(s.add_mesh(quad, 4, tris, 2, nullptr, nullptr, {mat}), Transform());
    s.set_camera(CameraDesc{});
    s.commit();
    Rng rng(5, 0);
    const int n = 20000;
    int hits = 0, blocked = 0;
    for (int i = 0; i < n; ++i) {
        Vec3 o(rng.next_float() - 0.5f, rng.next_float() - 0.5f, 1.0f);
        SurfaceHit h;
        hits += s.intersect(Ray{o, Vec3(0, 0, -1), 0.0f, kInf}, &h);
        blocked += s.occluded(o, Vec3(0, 0, -1), 2.0f);
        // The same ray decides the same way every time (deterministic images).
        EXPECT_EQ(s.intersect(Ray{o, Vec3(0, 0, -1), 0.0f, kInf}, &h), s.intersect(Ray{o, Vec3(0, 0, -1), 0.0f, kInf}, &h));
    }
    const double sigma = std::sqrt(0.3 * 0.7 / n);
    EXPECT_NEAR(hits / double(n), 0.3, 4 * sigma);
    EXPECT_NEAR(blocked / double(n), 0.3, 4 * sigma);
}

// ---- Cycles 3.4 reference values ----

namespace {

using I = Texture::Interp;
using X = Texture::Wrap;
using A = Texture::AlphaMode;

// The 5 x 3 PNG's bytes (RGBA, bottom row first, straight alpha; Image.pixels = byte / 255).
const int kPngBytes[] = {
    112, 154, 114, 0, 140, 173, 244, 38, 143, 112, 91, 61, 13, 103, 211, 24, 103, 247, 243, 55,
    1, 171, 3, 76, 127, 223, 23, 169, 136, 33, 216, 255, 123, 241, 155, 231, 245, 145, 71, 37,
    144, 49, 192, 237, 62, 141, 12, 1, 96, 226, 248, 164, 149, 145, 15, 96, 251, 105, 54, 255,
};
// The 5 x 3 EXR's floats (premultiplied linear, as Cycles and Image.pixels with alpha_mode PREMUL hold them).
const float kExr[] = {
    0.972073317f, 1.13898015f, 1.0687238f, 0.793416739f,
    0.616222322f, 0.701585412f, 1.12575853f, 0.273196489f,
    0.0853255838f, 1.09575748f, 1.08152902f, 0.63291508f,
    0.855334699f, 0.704587162f, 0.678250968f, 0.606217802f,
    0.651734591f, 0.8365345f, 0.884362638f, 0.897071481f,
    0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f,
    0.970074117f, 1.18841183f, 0.603768468f, 0.678547263f,
    0.527434051f, 0.96342659f, 0.284747273f, 0.247401312f,
    0.256506622f, 0.892336786f, 0.853931725f, 0.510105431f,
    1.14997351f, 0.974895895f, 0.891745329f, 0.458429068f,
    0.878382266f, 0.643164396f, 0.141397312f, 0.320159793f,
    0.573605061f, 1.01654339f, 0.584638238f, 0.853070498f,
    0.770051301f, 0.0665952861f, 1.10089076f, 0.503556967f,
    0.518629909f, 0.66623354f, 1.12956774f, 0.982998312f,
    0.888417244f, 1.11075521f, 0.982016027f, 0.671993375f,
};
constexpr int kW = 5, kH = 3;

std::vector<float> png_pixels() {
    std::vector<float> p;
    for (int b : kPngBytes) p.push_back(b / 255.0f);
    return p;
}

// Cycles' float arithmetic differs from ours by rounding only.
constexpr float kTol = 2e-6f;

}  // namespace

TEST(TextureCycles, EightBitSrgbEveryInterpolationAndExtension) {
    struct Row {
        I interp;
        X wrap;
        float u, v, r, g, b;
    };
    // Straight alpha, colour output unlinked alpha: Cycles premultiplies the bytes (in 8 bits),
    // interpolates the sRGB-encoded values and decodes after interpolation.
    const Row rows[] = {
    {I::Linear, X::Repeat, 1.40500498f, -0.444995195f, 0.122714818f, 0.0915676504f, 0.169584811f},
    {I::Linear, X::Repeat, -0.12499512f, 0.505004883f, 0.0286869947f, 0.0277776141f, 0.0106874183f},
    {I::Linear, X::Repeat, 0.735004723f, 0.105004825f, 0.00723624416f, 0.00987257157f, 0.00840465445f},
    {I::Linear, X::Repeat, -0.544995189f, 1.45500481f, 0.161064416f, 0.0371633545f, 0.309546709f},
    {I::Linear, X::Extend, 1.40500498f, -0.444995195f, 0.00802319311f, 0.0356013328f, 0.0343398228f},
    {I::Linear, X::Extend, -0.12499512f, 0.505004883f, 0.000606127724f, 0.0318063684f, 0.000811208505f},
    {I::Linear, X::Extend, 0.735004723f, 0.105004825f, 0.00141913886f, 0.00547663076f, 0.00958770886f},
    {I::Linear, X::Extend, -0.544995189f, 1.45500481f, 0.23455061f, 0.0262412261f, 0.445201337f},
    {I::Linear, X::Clip, 1.40500498f, -0.444995195f, 0.0f, 0.0f, 0.0f},
    {I::Linear, X::Clip, -0.12499512f, 0.505004883f, 0.0f, 0.0f, 0.0f},
    {I::Linear, X::Clip, 0.735004723f, 0.105004825f, 0.0011566187f, 0.00424678531f, 0.00709083257f},
    {I::Linear, X::Clip, -0.544995189f, 1.45500481f, 0.0f, 0.0f, 0.0f},
    {I::Closest, X::Repeat, 1.40500498f, -0.444995195f, 0.246201441f, 0.0152085181f, 0.686685443f},
    {I::Closest, X::Repeat, -0.12499512f, 0.505004883f, 0.0168073773f, 0.00749903405f, 0.00303526991f},
    {I::Closest, X::Repeat, 0.735004723f, 0.105004825f, 0.000303526991f, 0.00273174304f, 0.00651209243f},
    {I::Closest, X::Repeat, -0.544995189f, 1.45500481f, 0.246201441f, 0.0152085181f, 0.686685443f},
    {I::Closest, X::Extend, 1.40500498f, -0.444995195f, 0.00802319311f, 0.0356013328f, 0.0343398228f},
    {I::Closest, X::Extend, -0.12499512f, 0.505004883f, 0.0f, 0.0318960473f, 0.0f},
    {I::Closest, X::Extend, 0.735004723f, 0.105004825f, 0.000303526991f, 0.00273174304f, 0.00651209243f},
    {I::Closest, X::Extend, -0.544995189f, 1.45500481f, 0.23455061f, 0.0262412261f, 0.445201248f},
    {I::Closest, X::Clip, 1.40500498f, -0.444995195f, 0.0f, 0.0f, 0.0f},
    {I::Closest, X::Clip, -0.12499512f, 0.505004883f, 0.0f, 0.0f, 0.0f},
    {I::Closest, X::Clip, 0.735004723f, 0.105004825f, 0.000303526991f, 0.00273174304f, 0.00651209243f},
    {I::Closest, X::Clip, -0.544995189f, 1.45500481f, 0.0f, 0.0f, 0.0f},
    {I::Cubic, X::Repeat, 1.40500498f, -0.444995195f, 0.0827964246f, 0.0797654539f, 0.125378489f},
    {I::Cubic, X::Repeat, -0.12499512f, 0.505004883f, 0.0585485436f, 0.057838019f, 0.0234929807f},
    {I::Cubic, X::Repeat, 0.735004723f, 0.105004825f, 0.025495179f, 0.0301129706f, 0.0184537172f},
    {I::Cubic, X::Repeat, -0.544995189f, 1.45500481f, 0.0976355821f, 0.0595592409f, 0.168653712f},
    {I::Cubic, X::Extend, 1.40500498f, -0.444995195f, 0.00802319311f, 0.0356013328f, 0.0343398228f},
    {I::Cubic, X::Extend, -0.12499512f, 0.505004883f, 0.00866842829f, 0.0223337989f, 0.0137187671f},
    {I::Cubic, X::Extend, 0.735004723f, 0.105004825f, 0.00570324063f, 0.0157582071f, 0.0173276961f},
    {I::Cubic, X::Extend, -0.544995189f, 1.45500481f, 0.23455067f, 0.0262412336f, 0.445201337f},
    {I::Cubic, X::Clip, 1.40500498f, -0.444995195f, 0.0f, 0.0f, 0.0f},
    {I::Cubic, X::Clip, -0.12499512f, 0.505004883f, 0.000785630196f, 0.00139519305f, 0.00105144491f},
    {I::Cubic, X::Clip, 0.735004723f, 0.105004825f, 0.00460002525f, 0.0113070011f, 0.0115553355f},
    {I::Cubic, X::Clip, -0.544995189f, 1.45500481f, 0.0f, 0.0f, 0.0f},
    };
    std::vector<float> px = png_pixels();
    for (const Row& r : rows) {
        Texture::Options o;
        o.interp = r.interp, o.wrap = r.wrap, o.alpha_mode = A::Straight, o.byte_image = true;
        Texture t(px.data(), kW, kH, "sRGB", o);
        TextureSample s = t.lookup({r.u, r.v});
        SCOPED_TRACE(testing::Message() << int(r.interp) << " " << int(r.wrap) << " at " << r.u << ", " << r.v);
        EXPECT_NEAR(s.rgb.x, r.r, kTol);
        EXPECT_NEAR(s.rgb.y, r.g, kTol);
        EXPECT_NEAR(s.rgb.z, r.b, kTol);
    }
}

TEST(TextureCycles, AlphaModesColourSpacesAndTheLinkedAlphaOutput) {
    struct Row {
        A mode;
        const char* colorspace;
        bool alpha_linked;
        float u, v, r, g, b, a;
    };
    // Linear, Repeat. STRAIGHT and PREMUL (a PNG is read as straight either way) premultiply a colour
    // image, and un-premultiply the Color output when Alpha is linked; CHANNEL_PACKED and data
    // images keep RGB; NONE makes alpha 1.
    const Row rows[] = {
    {A::Straight, "sRGB", false, 0.0150048453f, 0.435004771f, 0.00431545544f, 0.0165789612f, 0.00234627957f, 0.205475584f},
    {A::Straight, "sRGB", false, 0.68500483f, 0.905004859f, 0.0262417309f, 0.0318413228f, 0.00565151917f, 0.333794475f},
    {A::Straight, "sRGB", true, 0.0150048453f, 0.435004771f, 0.0563719869f, 0.396651804f, 0.0190445967f, 0.205475584f},
    {A::Straight, "sRGB", true, 0.68500483f, 0.905004859f, 0.24155955f, 0.30345282f, 0.0334079526f, 0.333794475f},
    {A::Straight, "data", false, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::Straight, "data", false, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::Straight, "data", true, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::Straight, "data", true, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::Premul, "sRGB", false, 0.0150048453f, 0.435004771f, 0.00431545544f, 0.0165789612f, 0.00234627957f, 0.205475584f},
    {A::Premul, "sRGB", false, 0.68500483f, 0.905004859f, 0.0262417309f, 0.0318413228f, 0.00565151917f, 0.333794475f},
    {A::Premul, "sRGB", true, 0.0150048453f, 0.435004771f, 0.0563719869f, 0.396651804f, 0.0190445967f, 0.205475584f},
    {A::Premul, "sRGB", true, 0.68500483f, 0.905004859f, 0.24155955f, 0.30345282f, 0.0334079526f, 0.333794475f},
    {A::Premul, "data", false, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::Premul, "data", false, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::Premul, "data", true, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::Premul, "data", true, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::ChannelPacked, "sRGB", false, 0.0150048453f, 0.435004771f, 0.142327741f, 0.383856148f, 0.0431572534f, 0.205475584f},
    {A::ChannelPacked, "sRGB", false, 0.68500483f, 0.905004859f, 0.183592409f, 0.265868187f, 0.0593763851f, 0.333794475f},
    {A::ChannelPacked, "sRGB", true, 0.0150048453f, 0.435004771f, 0.142327741f, 0.383856148f, 0.0431572534f, 0.205475584f},
    {A::ChannelPacked, "sRGB", true, 0.68500483f, 0.905004859f, 0.183592409f, 0.265868187f, 0.0593763851f, 0.333794475f},
    {A::ChannelPacked, "data", false, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::ChannelPacked, "data", false, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::ChannelPacked, "data", true, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 0.205475584f},
    {A::ChannelPacked, "data", true, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 0.333794475f},
    {A::None, "sRGB", false, 0.0150048453f, 0.435004771f, 0.142327741f, 0.383856148f, 0.0431572534f, 1.0f},
    {A::None, "sRGB", false, 0.68500483f, 0.905004859f, 0.183592409f, 0.265868187f, 0.0593763851f, 1.0f},
    {A::None, "sRGB", true, 0.0150048453f, 0.435004771f, 0.142327741f, 0.383856148f, 0.0431572534f, 1.0f},
    {A::None, "sRGB", true, 0.68500483f, 0.905004859f, 0.183592409f, 0.265868187f, 0.0593763851f, 1.0f},
    {A::None, "data", false, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 1.0f},
    {A::None, "data", false, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 1.0f},
    {A::None, "data", true, 0.0150048453f, 0.435004771f, 0.413226932f, 0.652928293f, 0.229790077f, 1.0f},
    {A::None, "data", true, 0.68500483f, 0.905004859f, 0.465625256f, 0.552477419f, 0.2702806f, 1.0f},
    };
    std::vector<float> px = png_pixels();
    for (const Row& r : rows) {
        Texture::Options o;
        o.alpha_mode = r.mode, o.byte_image = true, o.alpha_linked = r.alpha_linked;
        Texture t(px.data(), kW, kH, r.colorspace, o);
        TextureSample s = t.lookup({r.u, r.v});
        SCOPED_TRACE(testing::Message() << int(r.mode) << " " << r.colorspace << " linked " << r.alpha_linked);
        EXPECT_NEAR(s.rgb.x, r.r, kTol);
        EXPECT_NEAR(s.rgb.y, r.g, kTol);
        EXPECT_NEAR(s.rgb.z, r.b, kTol);
        EXPECT_NEAR(s.alpha, r.a, kTol);
    }
}

TEST(TextureCycles, ClosestAtTexelBoundaries) {
    struct Row {
        X wrap;
        float u, r, g, b, a;
    };
    // Constant vectors (u, 0.5) into a Closest EXR texture. u = -1 lands on the last texel with
    // Repeat (Cycles' frac() puts a negative whole number into the texel below), and u = 1 is
    // outside the image for Clip.
    const Row rows[] = {
    {X::Repeat, -1.0f, 1.14997351f, 0.974895895f, 0.891745329f, 0.458429068f},
    {X::Repeat, -0.2f, 0.256506622f, 0.892336786f, 0.853931725f, 0.510105431f},
    {X::Repeat, 0.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Repeat, 0.2f, 0.970074117f, 1.18841183f, 0.603768468f, 0.678547263f},
    {X::Repeat, 1.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Repeat, 2.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Extend, -1.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Extend, -0.2f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Extend, 0.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Extend, 0.2f, 0.970074117f, 1.18841183f, 0.603768468f, 0.678547263f},
    {X::Extend, 1.0f, 1.14997351f, 0.974895895f, 0.891745329f, 0.458429068f},
    {X::Extend, 2.0f, 1.14997351f, 0.974895895f, 0.891745329f, 0.458429068f},
    {X::Clip, -1.0f, 0.0f, 0.0f, 0.0f, 0.0f},
    {X::Clip, -0.2f, 0.0f, 0.0f, 0.0f, 0.0f},
    {X::Clip, 0.0f, 0.921311915f, 1.19183147f, 1.07890618f, 0.489011258f},
    {X::Clip, 0.2f, 0.970074117f, 1.18841183f, 0.603768468f, 0.678547263f},
    {X::Clip, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f},
    {X::Clip, 2.0f, 0.0f, 0.0f, 0.0f, 0.0f},
    };
    for (const Row& r : rows) {
        Texture t(kExr, kW, kH, "linear", I::Closest, r.wrap);
        TextureSample s = t.lookup({r.u, 0.5f});
        SCOPED_TRACE(testing::Message() << int(r.wrap) << " u " << r.u);
        EXPECT_FLOAT_EQ(s.rgb.x, r.r);
        EXPECT_FLOAT_EQ(s.rgb.y, r.g);
        EXPECT_FLOAT_EQ(s.rgb.z, r.b);
        EXPECT_FLOAT_EQ(s.alpha, r.a);
    }
}

TEST(TextureCycles, SphereTubeAndBoxProjections) {
    enum class P { Sphere, Tube, Box };
    struct Row {
        P proj;
        float blend;
        Vec3 co, n;
        float r, g, b;
    };
    // Object coordinates + 0.5 of a smooth UV sphere (radius 0.5) and of an oblique cube, their
    // object-space normals, Linear / Repeat.
    const Row rows[] = {
    {P::Sphere, 0.0f, {0.735987723f, 0.0656541288f, 0.429932117f}, {0.472693801f, -0.870013535f, -0.140132323f}, 0.944232345f, 1.16098046f, 1.05812192f},
    {P::Sphere, 0.0f, {0.853845716f, 0.221089035f, 0.71467948f}, {0.709210694f, -0.559021175f, 0.429552734f}, 0.880906403f, 0.993118703f, 0.662188649f},
    {P::Sphere, 0.0f, {0.671442091f, 0.283771336f, 0.916722655f}, {0.343677551f, -0.433459908f, 0.833065629f}, 0.87138617f, 0.687038898f, 0.209309161f},
    {P::Sphere, 0.0f, {0.98791939f, 0.530033529f, 0.601528347f}, {0.977319181f, 0.0601578057f, 0.203047425f}, 0.896640956f, 1.14067435f, 0.659455895f},
    {P::Tube, 0.0f, {0.735987723f, 0.0656541288f, 0.429932117f}, {0.472693801f, -0.870013535f, -0.140132323f}, 0.943754852f, 1.15630436f, 1.05737269f},
    {P::Tube, 0.0f, {0.853845716f, 0.221089035f, 0.71467948f}, {0.709210694f, -0.559021175f, 0.429552734f}, 0.85451293f, 0.890818238f, 0.500568569f},
    {P::Tube, 0.0f, {0.671442091f, 0.283771336f, 0.916722655f}, {0.343677551f, -0.433459908f, 0.833065629f}, 0.891191542f, 0.772910178f, 0.384986848f},
    {P::Tube, 0.0f, {0.98791939f, 0.530033529f, 0.601528347f}, {0.977319181f, 0.0601578057f, 0.203047425f}, 0.861163259f, 1.11367369f, 0.637235045f},
    {P::Box, 0.0f, {0.735987723f, 0.0656541288f, 0.429932117f}, {0.472693801f, -0.870013535f, -0.140132323f}, 0.501656413f, 0.869594812f, 0.830172718f},
    {P::Box, 0.0f, {0.853845716f, 0.221089035f, 0.71467948f}, {0.709210694f, -0.559021175f, 0.429552734f}, 0.785330772f, 0.983323455f, 0.545547962f},
    {P::Box, 0.0f, {0.671442091f, 0.283771336f, 0.916722655f}, {0.343677551f, -0.433459908f, 0.833065629f}, 0.44196713f, 0.797851264f, 0.991030872f},
    {P::Box, 0.0f, {0.98791939f, 0.530033529f, 0.601528347f}, {0.977319181f, 0.0601578057f, 0.203047425f}, 0.561539233f, 0.710268199f, 0.594083309f},
    {P::Box, 0.25f, {0.735987723f, 0.0656541288f, 0.429932117f}, {0.472693801f, -0.870013535f, -0.140132323f}, 0.501656413f, 0.869594812f, 0.830172718f},
    {P::Box, 0.25f, {0.853845716f, 0.221089035f, 0.71467948f}, {0.709210694f, -0.559021175f, 0.429552734f}, 0.803181887f, 0.984960735f, 0.65690279f},
    {P::Box, 0.25f, {0.671442091f, 0.283771336f, 0.916722655f}, {0.343677551f, -0.433459908f, 0.833065629f}, 0.44196713f, 0.797851264f, 0.991030872f},
    {P::Box, 0.25f, {0.98791939f, 0.530033529f, 0.601528347f}, {0.977319181f, 0.0601578057f, 0.203047425f}, 0.561539233f, 0.710268199f, 0.594083309f},
    {P::Box, 1.0f, {0.735987723f, 0.0656541288f, 0.429932117f}, {0.472693801f, -0.870013535f, -0.140132323f}, 0.683019578f, 0.954003155f, 0.868120849f},
    {P::Box, 1.0f, {0.853845716f, 0.221089035f, 0.71467948f}, {0.709210694f, -0.559021175f, 0.429552734f}, 0.778823555f, 0.948197424f, 0.813057303f},
    {P::Box, 1.0f, {0.671442091f, 0.283771336f, 0.916722655f}, {0.343677551f, -0.433459908f, 0.833065629f}, 0.520993352f, 0.778387904f, 0.937132895f},
    {P::Box, 1.0f, {0.98791939f, 0.530033529f, 0.601528347f}, {0.977319181f, 0.0601578057f, 0.203047425f}, 0.567422509f, 0.706130087f, 0.681613982f},
    {P::Sphere, 0.0f, {0.926810622f, 0.162717134f, 0.471336931f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.930054545f, 1.18367803f, 0.980728328f},
    {P::Sphere, 0.0f, {0.770329595f, 0.287902951f, 0.664569974f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.880492449f, 0.992503583f, 0.660622835f},
    {P::Sphere, 0.0f, {0.562175393f, 0.204703629f, 0.828108549f}, {0.658901513f, -0.263772726f, 0.704466283f}, 0.906142712f, 0.866855621f, 0.547545254f},
    {P::Tube, 0.0f, {0.926810622f, 0.162717134f, 0.471336931f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.928719699f, 1.17841363f, 0.984505177f},
    {P::Tube, 0.0f, {0.770329595f, 0.287902951f, 0.664569974f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.872370064f, 0.961231649f, 0.611256361f},
    {P::Tube, 0.0f, {0.562175393f, 0.204703629f, 0.828108549f}, {0.658901513f, -0.263772726f, 0.704466283f}, 0.883563042f, 0.804748833f, 0.432186961f},
    {P::Box, 0.0f, {0.926810622f, 0.162717134f, 0.471336931f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.756507277f, 0.921947122f, 0.969800115f},
    {P::Box, 0.0f, {0.770329595f, 0.287902951f, 0.664569974f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.497439325f, 0.73171854f, 1.07066393f},
    {P::Box, 0.0f, {0.562175393f, 0.204703629f, 0.828108549f}, {0.658901513f, -0.263772726f, 0.704466283f}, 0.684577525f, 0.921670437f, 0.906887949f},
    {P::Box, 0.25f, {0.926810622f, 0.162717134f, 0.471336931f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.831682026f, 1.03134787f, 0.958357871f},
    {P::Box, 0.25f, {0.770329595f, 0.287902951f, 0.664569974f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.620673835f, 0.887999952f, 0.864902318f},
    {P::Box, 0.25f, {0.562175393f, 0.204703629f, 0.828108549f}, {0.658901513f, -0.263772726f, 0.704466283f}, 0.700960577f, 0.888088822f, 0.678922176f},
    {P::Box, 1.0f, {0.926810622f, 0.162717134f, 0.471336931f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.87968117f, 1.03575075f, 0.950408936f},
    {P::Box, 1.0f, {0.770329595f, 0.287902951f, 0.664569974f}, {0.658901453f, -0.263772726f, 0.704466343f}, 0.630762339f, 0.900655329f, 0.862169683f},
    {P::Box, 1.0f, {0.562175393f, 0.204703629f, 0.828108549f}, {0.658901513f, -0.263772726f, 0.704466283f}, 0.700447023f, 0.783629715f, 0.72501868f},
    };
    Texture t(kExr, kW, kH, "linear", I::Linear, X::Repeat);
    for (const Row& r : rows) {
        TextureSample s;
        if (r.proj == P::Box) {
            shading::BoxWeights bw = shading::project_box(r.co, r.n, r.blend);
            float sum = 0.0f;
            for (int i = 0; i < 3; ++i) {
                if (bw.w[i] > 0.0f) s.rgb += t.lookup(bw.uv[i]).rgb * bw.w[i];
                sum += bw.w[i];
            }
            EXPECT_NEAR(sum, 1.0f, 1e-6f);
        } else {
            s = t.lookup(r.proj == P::Sphere ? shading::project_sphere(r.co) : shading::project_tube(r.co));
        }
        SCOPED_TRACE(testing::Message() << int(r.proj) << " blend " << r.blend << " co " << r.co.x << " " << r.co.y
                                        << " " << r.co.z);
        EXPECT_NEAR(s.rgb.x, r.r, kTol);
        EXPECT_NEAR(s.rgb.y, r.g, kTol);
        EXPECT_NEAR(s.rgb.z, r.b, kTol);
    }
}

TEST(TextureCycles, ProjectionGeometry) {
    // Sphere and tube wrap around z through the centre 0.5: u = 0 towards -y, 0.25 towards +x, 0.5
    // towards +y (counter-clockwise from above), v from the bottom (0) to the top (1); the tube's v
    // is height.
    Point2 s = shading::project_sphere(Vec3(0.5f, 1.0f, 0.5f));
    EXPECT_NEAR(s.x, 0.5f, 1e-6f);
    EXPECT_NEAR(s.y, 0.5f, 1e-6f);
    EXPECT_NEAR(shading::project_sphere(Vec3(1.0f, 0.5f, 0.5f)).x, 0.25f, 1e-6f);
    EXPECT_NEAR(shading::project_sphere(Vec3(0.0f, 0.5f, 0.5f)).x, 0.75f, 1e-6f);
    EXPECT_NEAR(shading::project_sphere(Vec3(0.5f, 0.5f, 1.0f)).y, 1.0f, 1e-6f);
    EXPECT_EQ(shading::project_sphere(Vec3(0.5f, 0.5f, 0.9f)).x, 0.0f);  // on the axis
    EXPECT_EQ(shading::project_sphere(Vec3(0.5f)).y, 0.0f);               // the centre itself
    Point2 tb = shading::project_tube(Vec3(0.5f, 1.0f, 0.25f));
    EXPECT_NEAR(tb.x, 0.5f, 1e-6f);
    EXPECT_NEAR(tb.y, 0.25f, 1e-6f);
    // A point scaled away from the centre keeps its sphere UV.
    Point2 a = shading::project_sphere(Vec3(0.6f, 0.3f, 0.7f)), b = shading::project_sphere(Vec3(0.7f, 0.1f, 0.9f));
    EXPECT_NEAR(a.x, b.x, 1e-6f);
    EXPECT_NEAR(a.y, b.y, 1e-6f);
    EXPECT_EQ(shading::project_flat(Vec3(0.3f, 0.7f, 5.0f)).x, 0.3f);

    // Box: an axis normal takes its face alone whatever the blend; each face's UV flips with the
    // normal's side; the blend's middle mixes all three; no blend falls back to X on ties.
    Vec3 co(0.2f, 0.3f, 0.4f);
    for (float blend : {0.0f, 0.5f, 1.0f}) {
        shading::BoxWeights bz = shading::project_box(co, Vec3(0, 0, -2), blend);
        EXPECT_EQ(bz.w[2], 1.0f);
        EXPECT_EQ(bz.w[0] + bz.w[1], 0.0f);
    }
    shading::BoxWeights px = shading::project_box(co, Vec3(1, 0, 0), 0.0f), nx = shading::project_box(co, Vec3(-1, 0, 0), 0.0f);
    EXPECT_FLOAT_EQ(px.uv[0].x, 0.3f);
    EXPECT_FLOAT_EQ(nx.uv[0].x, 0.7f);
    EXPECT_FLOAT_EQ(px.uv[0].y, 0.4f);
    shading::BoxWeights py = shading::project_box(co, Vec3(0, 1, 0), 0.0f), pz = shading::project_box(co, Vec3(0, 0, 1), 0.0f);
    EXPECT_FLOAT_EQ(py.uv[1].x, 0.8f);
    EXPECT_FLOAT_EQ(pz.uv[2].x, 0.7f);
    EXPECT_FLOAT_EQ(pz.uv[2].y, 0.2f);
    shading::BoxWeights mid = shading::project_box(co, Vec3(1, 1, 1), 1.0f);
    for (float w : mid.w) EXPECT_NEAR(w, 1.0f / 3.0f, 1e-6f);
    shading::BoxWeights tie = shading::project_box(co, Vec3(1, 1, 0), 0.0f);
    EXPECT_EQ(tie.w[0], 1.0f);
    shading::BoxWeights edge = shading::project_box(co, Vec3(1, 1, 0), 0.5f);  // X and Y half each
    EXPECT_NEAR(edge.w[0], 0.5f, 1e-6f);
    EXPECT_NEAR(edge.w[1], 0.5f, 1e-6f);
    EXPECT_EQ(edge.w[2], 0.0f);
    shading::BoxWeights zero = shading::project_box(co, Vec3(0.0f), 0.5f);  // Cycles: black
    EXPECT_EQ(zero.w[0] + zero.w[1] + zero.w[2], 0.0f);
}

TEST(TextureCycles, CubicIsTheUniformBSpline) {
    // A single bright texel in a 5-wide row: the B-spline's weights 1/6, 2/3, 1/6 at texel centres,
    // 1/48, 23/48, 23/48, 1/48 half-way; the kernel is not negative (but for rounding).
    float row[5 * 4] = {};
    row[2 * 4 + 0] = 1.0f;
    for (int i = 0; i < 5; ++i) row[i * 4 + 3] = 1.0f;
    Texture t(row, 5, 1, "linear", I::Cubic, X::Repeat);
    EXPECT_NEAR(t.lookup({2.5f / 5, 0.5f}).rgb.x, 2.0f / 3.0f, 1e-6f);
    EXPECT_NEAR(t.lookup({1.5f / 5, 0.5f}).rgb.x, 1.0f / 6.0f, 1e-6f);
    EXPECT_NEAR(t.lookup({0.5f / 5, 0.5f}).rgb.x, 0.0f, 1e-6f);
    EXPECT_NEAR(t.lookup({2.0f / 5, 0.5f}).rgb.x, 23.0f / 48.0f, 1e-6f);
    EXPECT_NEAR(t.lookup({1.0f / 5, 0.5f}).rgb.x, 1.0f / 48.0f, 1e-6f);
    for (float u = -0.3f; u < 1.3f; u += 0.01f) EXPECT_GE(t.lookup({u, 0.5f}).rgb.x, -1e-7f);
    // Clip: the one row blends with transparent black above and below (weights 1/6 each).
    Texture clip(row, 5, 1, "linear", I::Cubic, X::Clip);
    EXPECT_NEAR(clip.lookup({2.5f / 5, 0.5f}).alpha, 2.0f / 3.0f, 1e-6f);
    EXPECT_NEAR(clip.lookup({2.5f / 5, 0.5f}).rgb.x, 4.0f / 9.0f, 1e-6f);
}

TEST(TextureCycles, MirrorReflectsAtTheEdges) {
    // Blender 3.4 has no Mirror extension; this is Cycles' later one: the image, then flipped copies.
    for (I interp : {I::Closest, I::Linear, I::Cubic}) {
        Texture m(kExr, kW, kH, "linear", interp, X::Mirror);
        Texture e(kExr, kW, kH, "linear", interp, X::Extend);
        for (float u : {0.05f, 0.13f, 0.37f, 0.5f, 0.71f, 0.93f}) {
            for (float v : {0.1f, 0.45f, 0.8f}) {
                float mu = m.lookup({u, v}).rgb.y;
                EXPECT_NEAR(m.lookup({-u, v}).rgb.y, mu, 1e-5f);
                EXPECT_NEAR(m.lookup({2.0f - u, v}).rgb.y, mu, 1e-5f);
                EXPECT_NEAR(m.lookup({u + 2.0f, v}).rgb.y, mu, 1e-5f);
                EXPECT_NEAR(m.lookup({u, -v}).rgb.y, mu, 1e-5f);
                if (interp == I::Closest) {
                    EXPECT_EQ(mu, e.lookup({u, v}).rgb.y);
                }
            }
        }
        // Within half a texel of the edges Linear mirrors exactly like Extend (Cubic reaches further).
        if (interp == I::Linear) {
            EXPECT_NEAR(m.lookup({0.02f, 0.5f}).rgb.x, e.lookup({0.02f, 0.5f}).rgb.x, 1e-6f);
            EXPECT_NEAR(m.lookup({0.98f, 0.3f}).rgb.x, e.lookup({0.98f, 0.3f}).rgb.x, 1e-6f);
        }
    }
}

TEST(TextureCycles, MissingImageIsOpaqueMagenta) {
    auto t = Texture::missing();
    for (Point2 uv : {Point2{0.3f, 0.2f}, Point2{-7.0f, 12.5f}}) {
        TextureSample s = t->lookup(uv);
        EXPECT_EQ(s.rgb, Color(1.0f, 0.0f, 1.0f));
        EXPECT_EQ(s.alpha, 1.0f);
    }
}

TEST(TextureCycles, UnpremultiplyLeavesAlphaZeroAndOneAlone) {
    // Cycles divides by alpha only strictly between 0 and 1; a fully transparent texel stays black.
    const float px[] = {0.25f, 0.5f, 0.125f, 0.5f, 0.0f, 0.0f, 0.0f, 0.0f, 0.3f, 0.6f, 0.9f, 1.0f, 0.2f, 0.2f, 0.2f, 0.0f};
    Texture::Options o;
    o.interp = I::Closest, o.alpha_mode = A::Premul, o.alpha_linked = true;
    Texture t(px, 4, 1, "linear", o);
    EXPECT_FLOAT_EQ(t.lookup({0.1f, 0.5f}).rgb.y, 1.0f);
    EXPECT_EQ(t.lookup({0.3f, 0.5f}).rgb, Color(0.0f));
    EXPECT_FLOAT_EQ(t.lookup({0.6f, 0.5f}).rgb.z, 0.9f);
    EXPECT_FLOAT_EQ(t.lookup({0.9f, 0.5f}).rgb.x, 0.2f);  // alpha 0: kept as stored
    // Float images are used as stored (no association at load): unlinked, Color is the stored RGB.
    o.alpha_linked = false;
    EXPECT_FLOAT_EQ(Texture(px, 4, 1, "linear", o).lookup({0.1f, 0.5f}).rgb.y, 0.5f);
    // A NaN channel zeroes the whole texel, as Cycles' loader does.
    const float bad[] = {NAN, 0.5f, 0.5f, 1.0f};
    EXPECT_EQ(Texture(bad, 1, 1, "linear", o).lookup({0.5f, 0.5f}).alpha, 0.0f);
}
