// Image textures: texel placement, bilinear weights, wrapping and sRGB decoding as Blender's Image
// Texture node; a textured material scales its lobe by the texture at the hit's UV; alpha cut-outs
// are hit with frequency alpha.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "scene/material.h"
#include "scene/scene.h"
#include "scene/texture.h"

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

TEST(Texture, SrgbIsDecodedOnceAlphaIsNot) {
    const float grey[] = {0.5f, 0.5f, 0.5f, 0.5f};
    Texture t(grey, 1, 1, "sRGB", false, Texture::Wrap::Repeat);
    EXPECT_NEAR(t.lookup({0.3f, 0.3f}).rgb.x, 0.21404f, 1e-5f);
    EXPECT_FLOAT_EQ(t.lookup({0.3f, 0.3f}).alpha, 0.5f);
    EXPECT_THROW(Texture(grey, 1, 1, "Filmic", false, Texture::Wrap::Repeat), std::invalid_argument);
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
