// The World through shader programs (scene/environment_light.h): Cycles' lat-long and mirror-ball
// projections, the importance map's sample() against pdf() (chi-square), sample / pdf / intersect
// agreement, radiance from the program at the exact direction (an unbiased irradiance estimate
// whatever the map's resolution), ray kinds (a camera-only backplate), and white furnaces through
// the path tracer.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

#include "scene/environment_light.h"
#include "scene/scene.h"
#include "shading/node_math.h"
#include "shading/shader_program.h"
#include "program_builder.h"
#include "stats.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::stats;
using smis::testing::add_sphere;
using smis::testing::camera_at;
using smis::testing::channel_mean;
using smis::testing::diffuse;
using smis::testing::render;

namespace {

using Builder = smis::testing::ProgramBuilder;


// A small HDR image: a dim gradient with a bright spot (a "sun") and a coloured patch, so the map
// is far from uniform and sampling must follow it.
std::shared_ptr<const Texture> hdr_image(int w = 32, int h = 16) {
    std::vector<float> px(size_t(w) * h * 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float* p = &px[4 * (size_t(y) * w + x)];
            float g = 0.05f + 0.3f * float(y) / h;
            p[0] = p[1] = p[2] = g;
            if (std::abs(x - 20) <= 1 && std::abs(y - 11) <= 1) p[0] = p[1] = p[2] = 40.0f;
            if (x >= 4 && x < 9 && y >= 3 && y < 6) p[0] = 3.0f, p[1] = 0.2f, p[2] = 0.1f;
            p[3] = 1.0f;
        }
    Texture::Options o;
    return std::make_shared<Texture>(px.data(), w, h, "linear", o);
}

// The World: the HDR image through a Mapping (rotation) node, strength 1.5.
std::shared_ptr<const ShaderProgram> hdr_world() {
    Builder b;
    uint16_t d = b.direction();
    uint16_t mapped = b.alloc(3);
    ShaderOp& m = b.op(ShaderOpCode::Mapping);
    m.in[0] = d, m.in[2] = b.constant3({0.3f, -0.2f, 1.1f}), m.in[3] = b.constant3(Vec3(1.0f));
    m.out[0] = mapped, m.i[0] = 2;  // VECTOR
    b.background(b.environment(mapped, hdr_image()), 1.5f);
    return b.build();
}

// A constant World (value c) that does not fold: a 1 x 1 image looked up per direction.
// (Two equal texels: an image of one texel folds to a constant, which would bypass the sampler.)
std::shared_ptr<const ShaderProgram> constant_world_via_image(float c) {
    const float px[8] = {c, c, c, 1.0f, c, c, c, 1.0f};
    Builder b;
    b.background(b.environment(b.direction(), std::make_shared<Texture>(px, 2, 1, "linear", Texture::Options{})), 1.0f);
    return b.build();
}

}  // namespace

TEST(EnvironmentProjection, MatchesCycles) {
    // Cycles 3.4 direction_to_equirectangular: +x at the centre, +y at u = 0.25, +z at the top.
    auto near = [](Point2 a, Point2 b) { return std::fabs(a.x - b.x) < 1e-5f && std::fabs(a.y - b.y) < 1e-5f; };
    EXPECT_TRUE(near(direction_to_equirectangular({1, 0, 0}), {0.5f, 0.5f}));
    EXPECT_TRUE(near(direction_to_equirectangular({0, 1, 0}), {0.25f, 0.5f}));
    EXPECT_TRUE(near(direction_to_equirectangular({0, -1, 0}), {0.75f, 0.5f}));
    EXPECT_NEAR(direction_to_equirectangular({0, 0, 1}).y, 1.0f, 1e-6f);
    EXPECT_NEAR(direction_to_equirectangular({0, 0, -1}).y, 0.0f, 1e-6f);
    EXPECT_TRUE(near(direction_to_equirectangular({0, 0, 0}), {0.0f, 0.0f}));
    // Mirror ball: -y (towards the camera) at the centre, +x on the right at height 0.5.
    EXPECT_TRUE(near(direction_to_mirrorball({0, -1, 0}), {0.5f, 0.5f}));
    EXPECT_TRUE(near(direction_to_mirrorball({1, 0, 0}), {0.5f + 0.5f * std::sqrt(0.5f), 0.5f}));
    EXPECT_TRUE(near(direction_to_mirrorball({0, 0, 1}), {0.5f, 0.5f + 0.5f * std::sqrt(0.5f)}));
    // Round trip through the map's direction of a (u, v).
    for (float u : {0.01f, 0.3f, 0.5f, 0.77f, 0.99f})
        for (float v : {0.02f, 0.4f, 0.5f, 0.93f}) {
            Vec3 d = equirectangular_to_direction(u, v);
            EXPECT_NEAR(length(d), 1.0f, 1e-5f);
            EXPECT_TRUE(near(direction_to_equirectangular(d), {u, v})) << u << " " << v;
        }
}

TEST(EnvironmentLight, SamplesFollowTheirPdf) {
    auto world = hdr_world();
    // Map resolutions below, at and above the image's: the table only steers the samples.
    const int sizes[][2] = {{64, 32}, {32, 16}, {7, 5}};
    const double alpha = sidak_significance(0.01, 3);
    for (auto& sz : sizes) {
        EnvironmentLight env(world, nullptr, sz[0], sz[1]);
        auto sample = [&](Rng& rng) {
            LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            return s.valid() ? DirSample::valid(s.wi, s.pdf) : DirSample::invalid();
        };
        auto pdf = [&](const Vec3& w) { return env.pdf({0, 0, 0}, w); };
        Chi2Options opt;
        opt.grid = SphereGrid{40, 80};
        Chi2Result r = chi2_test_directions(sample, pdf, 500000, opt);
        EXPECT_TRUE(r.passes(alpha)) << sz[0] << "x" << sz[1] << ": " << r.summary() << "\n" << r.residual_map();
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << sz[0] << "x" << sz[1];
        EXPECT_GT(double(r.n_valid) / r.n_samples, 0.999);
    }
}

TEST(EnvironmentLight, SamplePdfIntersectAndRadianceAgree) {
    auto world = hdr_world();
    EnvironmentLight env(world, nullptr, 48, 24);
    Rng rng(3, 9);
    int valid = 0;
    for (int i = 0; i < 5000; ++i) {
        LightSample s = env.sample({0.3f, -1.0f, 2.0f}, {rng.next_float(), rng.next_float()});
        if (!s.valid()) continue;
        ++valid;
        EXPECT_TRUE(std::isinf(s.dist));
        ASSERT_NEAR(env.pdf({0, 0, 0}, s.wi), s.pdf, 1e-4f * s.pdf);
        LightHit h;
        ASSERT_TRUE(env.intersect(Ray{{1, 2, 3}, s.wi, 0.0f, kInf}, &h));
        ASSERT_NEAR(h.pdf, s.pdf, 1e-4f * s.pdf);
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(h.L[c], s.L[c], 1e-5f * (1.0f + s.L[c]));
        // The radiance is the program at the exact direction, not the map's cell value.
        Color direct = env.radiance(s.wi, EnvironmentLight::light_sample_kind());
        for (int c = 0; c < 3; ++c) ASSERT_EQ(direct[c], s.L[c]);
        // A ray that hits something before infinity does not reach the World.
        ASSERT_FALSE(env.intersect(Ray{{1, 2, 3}, s.wi, 0.0f, 10.0f}, &h));
    }
    EXPECT_GT(valid, 4990);
    // The brightest spot of the image is where the samples go: far more than its solid angle.
    EXPECT_GT(luminance(env.average()), 0.0f);
}

// The NEE estimator of irradiance, mean of L cos / pdf over environment samples, equals the
// integral of the program's radiance (adaptive quadrature), at map resolutions that do not align
// with the image: the returned radiance is exact, so the coarse table costs variance, not bias.
TEST(EnvironmentLight, IrradianceEstimateIsUnbiasedAtAnyMapResolution) {
    auto world = hdr_world();
    const Vec3 n = normalize(Vec3(0.2f, 0.5f, 0.8f));
    EnvironmentLight exact(world, nullptr, 64, 32);
    auto f = [&](const Vec3& w) {
        return double(exact.radiance(w, EnvironmentLight::light_sample_kind()).y) * std::max(0.0, double(dot(w, n)));
    };
    IntegrationOptions io;
    io.subdivisions = 2;
    io.rel_tolerance = 1e-4;
    io.abs_tolerance = 1e-6;
    const double expected = integrate_sphere(f, io, SphereGrid{32, 64});
    for (auto sz : {std::pair<int, int>{64, 32}, {5, 3}, {1, 1}}) {
        EnvironmentLight env(world, nullptr, sz.first, sz.second);
        Rng rng(11, 5);
        MeanEstimator e;
        for (int i = 0; i < 400000; ++i) {
            LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            e.add(s.valid() ? double(s.L.y) * std::max(0.0f, dot(s.wi, n)) / s.pdf : 0.0);
        }
        ZTest z = z_test_mean(e, expected, 1e-4 * expected);
        EXPECT_GT(z.p_value, 1e-3) << sz.first << "x" << sz.second << ": " << e.mean() << " +- " << e.std_error()
                                   << " vs " << expected;
    }
    // And importance sampling pays: the map's estimate is less noisy than the 1 x 1 map's (uniform).
}

TEST(EnvironmentLight, MapFollowsTheImageSoVarianceDrops) {
    auto world = hdr_world();
    const Vec3 n(0, 0, 1);
    auto variance = [&](int w, int h) {
        EnvironmentLight env(world, nullptr, w, h);
        Rng rng(2, 8);
        MeanEstimator e;
        for (int i = 0; i < 100000; ++i) {
            LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            e.add(s.valid() ? double(s.L.y) * std::max(0.0f, dot(s.wi, n)) / s.pdf : 0.0);
        }
        return e.variance();
    };
    EXPECT_LT(variance(128, 64), 0.2 * variance(1, 1));
}

TEST(EnvironmentLight, LightPathTellsCameraRaysApart) {
    // Backplate trick: Mix(Is Camera Ray, lighting colour, backplate colour).
    Builder b;
    uint16_t lp = b.alloc(13);
    ShaderOp& l = b.op(ShaderOpCode::LightPath);
    for (int k = 0; k < 13; ++k) l.out[k] = uint16_t(lp + k);
    uint16_t mixed = b.alloc(3);
    ShaderOp& m = b.op(ShaderOpCode::Mix);
    m.in[0] = lp, m.in[1] = b.constant3({0.2f, 0.4f, 0.6f}), m.in[2] = b.constant3({5.0f, 0.0f, 0.0f});
    m.out[0] = mixed, m.i[0] = 0, m.i[1] = 1;
    b.background(mixed, 1.0f);
    auto program = b.build();
    ASSERT_FALSE(program->is_constant());
    EnvironmentLight env(program, nullptr, 16, 8);
    ShaderRay camera;  // camera = true
    LightHit h;
    ASSERT_TRUE(env.intersect_as(Ray{{0, 0, 0}, {0, 1, 0}, 0.0f, kInf}, camera, &h));
    EXPECT_FLOAT_EQ(h.L.x, 5.0f);
    ASSERT_TRUE(env.intersect(Ray{{0, 0, 0}, {0, 1, 0}, 0.0f, kInf}, &h));
    EXPECT_FLOAT_EQ(h.L.y, 0.4f);
    LightSample s = env.sample({0, 0, 0}, {0.3f, 0.6f});
    ASSERT_TRUE(s.valid());
    EXPECT_FLOAT_EQ(s.L.z, 0.6f);
    // The map sees the lighting colour: uniform in solid angle.
    EXPECT_NEAR(env.average().y, 0.4f, 1e-4f);
}

TEST(EnvironmentLight, BackgroundCoordinatesAsCycles) {
    // Texture Coordinate in the World (Cycles' background shader data): Generated = Object = D,
    // Normal = -D, UV = 0, Reflection = the incoming -D. One program per output: emission = output + 2.
    const Vec3 d = normalize(Vec3(0.3f, -0.5f, 0.7f));
    const Vec3 expected[7] = {d, -d, Vec3(0.0f), d, d, d, -d};
    for (int k : {0, 1, 2, 3, 6}) {
        Builder b;
        uint16_t v = b.alloc(3);
        b.op(ShaderOpCode::TexCoord).out[k] = v;
        uint16_t shifted = b.alloc(3);
        ShaderOp& add = b.op(ShaderOpCode::VectorMath);
        add.in[0] = v, add.in[1] = b.constant3(Vec3(2.0f)), add.out[0] = shifted;
        add.i[0] = int(shading::VectorMathOp::Add);
        b.op(ShaderOpCode::Emission).in[1] = shifted;
        auto program = b.build();
        EnvironmentLight env(program, nullptr, 4, 2);
        ShaderContext ctx = env.context(d, EnvironmentLight::light_sample_kind());
        EXPECT_TRUE(ctx.background);
        Color L = env.radiance(d, EnvironmentLight::light_sample_kind());
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(L[c], expected[k][c] + 2.0f, 1e-6f) << "output " << k;
    }
}

TEST(EnvironmentLight, ConstantWorldProgramFoldsToTheUniformLight) {
    Builder b;
    b.background(b.constant3({0.5f, 0.25f, 1.0f}), 2.0f);
    WorldDesc w;
    w.program = b.build();
    ASSERT_TRUE(w.program->is_constant());
    auto s = std::make_shared<Scene>();
    add_sphere(*s, 1.0f, 8, 16, s->add_material(diffuse(Color(0.5f))));
    s->set_world(w);
    s->set_camera(camera_at({0, 0, 3}, 8, 8));
    s->commit();
    ASSERT_EQ(s->lights().size(), 1u);
    auto* world = dynamic_cast<const WorldLight*>(&s->light(0));
    ASSERT_NE(world, nullptr);
    EXPECT_FLOAT_EQ(world->radiance().x, 1.0f);
    EXPECT_FLOAT_EQ(world->radiance().z, 2.0f);
}

// White furnace: a white diffuse sphere under a constant World that reaches the path tracer through
// the environment sampler (a 1 x 1 image looked up per direction) renders the World's value.
TEST(EnvironmentLight, WhiteFurnaceThroughTheEnvironmentSampler) {
    const float c = 0.7f;
    for (MisHeuristic mis : {MisHeuristic::Balance, MisHeuristic::Power}) {
        auto s = std::make_shared<Scene>();
        add_sphere(*s, 1.0f, 32, 64, s->add_material(diffuse(Color(1.0f))));
        WorldDesc w;
        w.program = constant_world_via_image(c);
        w.map_width = 64, w.map_height = 32;
        ASSERT_FALSE(w.program->is_constant());
        s->set_world(w);
        CameraDesc cam = camera_at({0, 0, 3.0f}, 16, 16);
        cam.lens = 200.0f;  // every pixel sees the sphere
        s->set_camera(cam);
        s->commit();
        ASSERT_EQ(s->infinite_lights().size(), 1u);
        ASSERT_NE(dynamic_cast<const EnvironmentLight*>(&s->light(s->infinite_lights()[0])), nullptr);
        RenderSettings st;
        st.samples = 128;
        st.max_bounces = 4;
        st.mis = mis;
        auto img = render(s, st);
        for (int ch = 0; ch < 3; ++ch) {
            auto m = channel_mean(img, ch);
            EXPECT_NEAR(m.mean(), c, 4.0 * m.std_error() + 1e-4) << "channel " << ch;
        }
    }
}

// A World brighter above than below, L(d) = a + b d.z, lights a diffuse sphere: the radiance leaving
// a point with normal n is rho (a + 2/3 b n.z) (no self-occlusion on a convex body). Light and BSDF
// samples of the varying World meet through MIS.
TEST(EnvironmentLight, GradientWorldLightsASphereExactly) {
    const float a = 1.0f, bz = 0.8f, rho = 0.6f;
    Builder b;
    uint16_t d = b.direction();
    uint16_t dz = b.alloc(1), lum = b.alloc(1), col = b.alloc(3);
    ShaderOp& dot_op = b.op(ShaderOpCode::VectorMath);
    dot_op.in[0] = d, dot_op.in[1] = b.constant3({0, 0, bz}), dot_op.out[1] = dz;
    dot_op.i[0] = int(shading::VectorMathOp::DotProduct);
    ShaderOp& add = b.op(ShaderOpCode::Math);
    add.in[0] = dz, add.in[1] = b.constant(a), add.out[0] = lum, add.i[0] = int(shading::MathOp::Add);
    ShaderOp& conv = b.op(ShaderOpCode::Convert);
    conv.in[0] = lum, conv.out[0] = col, conv.i[0] = 0;
    b.background(col, 1.0f);
    auto s = std::make_shared<Scene>();
    add_sphere(*s, 1.0f, 48, 96, s->add_material(diffuse(Color(rho))));
    WorldDesc w;
    w.program = b.build();
    w.map_width = 32, w.map_height = 16;
    s->set_world(w);
    // Looking down at the sphere's top from x: every pixel sees the sphere.
    CameraDesc cam = camera_at({0, 0, 3.0f}, 12, 12);
    cam.lens = 200.0f;
    s->set_camera(cam);
    s->commit();
    RenderSettings st;
    st.samples = 256;
    st.max_bounces = 3;
    st.filter = PixelFilterKind::Box;
    st.filter_width = 1.0f;
    auto img = render(s, st);
    // Expected per pixel from the normal where the pixel's centre ray meets the unit sphere.
    const Camera& camera = s->camera();
    MeanEstimator diff;
    for (int y = 0; y < 12; ++y)
        for (int x = 0; x < 12; ++x) {
            Ray r = camera.generate_ray(x + 0.5f, y + 0.5f);
            float bq = dot(r.o, r.d), cq = dot(r.o, r.o) - 1.0f;
            float t = -bq - std::sqrt(bq * bq - cq);
            Vec3 nrm = normalize(r.o + r.d * t);
            double expected = rho * (a + 2.0 / 3.0 * bz * nrm.z);
            diff.add(img[4 * (size_t(y) * 12 + x) + 1] - expected);
        }
    EXPECT_NEAR(diff.mean(), 0.0, 4.0 * diff.std_error() + 2e-3) << "mean difference";
}

// The backplate trick through the path tracer: camera rays that miss everything see the plate, the
// sphere is lit by the other colour only (light samples and BSDF rays are not camera rays).
TEST(EnvironmentLight, BackplateSeenByCameraRaysOnly) {
    const Color lighting(0.5f, 1.0f, 0.25f), plate(4.0f, 0.0f, 2.0f);
    const float rho = 0.8f;
    Builder b;
    uint16_t lp = b.alloc(13);
    ShaderOp& l = b.op(ShaderOpCode::LightPath);
    l.out[0] = lp;
    uint16_t mixed = b.alloc(3);
    ShaderOp& m = b.op(ShaderOpCode::Mix);
    m.in[0] = lp, m.in[1] = b.constant3(lighting), m.in[2] = b.constant3(plate);
    m.out[0] = mixed, m.i[0] = 0, m.i[1] = 1;
    b.background(mixed, 1.0f);
    auto s = std::make_shared<Scene>();
    add_sphere(*s, 1.0f, 32, 64, s->add_material(diffuse(Color(rho))));
    WorldDesc w;
    w.program = b.build();
    s->set_world(w);
    CameraDesc cam = camera_at({0, 0, 6.0f}, 16, 16);
    cam.lens = 50.0f;  // the sphere in the middle, the plate in the corners
    s->set_camera(cam);
    s->commit();
    RenderSettings st;
    st.samples = 64;
    st.max_bounces = 2;
    st.filter = PixelFilterKind::Box;
    st.filter_width = 1.0f;
    auto img = render(s, st);
    auto px = [&](int x, int y, int c) { return img[4 * (size_t(y) * 16 + x) + c]; };
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(px(0, 0, c), plate[c]) << c;
        EXPECT_FLOAT_EQ(px(15, 15, c), plate[c]) << c;
    }
    MeanEstimator centre[3];
    for (int y = 6; y < 10; ++y)
        for (int x = 6; x < 10; ++x)
            for (int c = 0; c < 3; ++c) centre[c].add(px(x, y, c));
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(centre[c].mean(), rho * lighting[c], 4.0 * centre[c].std_error() + 1e-3) << c;
}

namespace {

// A Nishita sky (Blender 3.4's default sky) with its sun at 35 degrees, strength 0.5.
std::shared_ptr<const ShaderProgram> nishita_world(float sun_size, bool plain = true) {
    NishitaParams p;
    p.sun_elevation = 0.61f;
    p.sun_rotation = 1.2f;
    p.sun_size = sun_size;
    Builder b;
    b.background(b.nishita_sky(b.direction(), p, plain), 0.5f);
    return b.build();
}

}  // namespace

TEST(NishitaSky, TableIsSymmetricAndTheDiscFollowsTheSun) {
    NishitaParams p;  // Blender's defaults: sun at 15 degrees, 0.545-degree disc, altitude 0 (-> 1 m)
    NishitaSky sky(p);
    // (Its values against Cycles': blender_tests/test_world.py renders the sky with both.)
    // Symmetric about the sun's meridian, brighter towards the sun, dark at the zenith's far side.
    for (int y : {0, 40, 127})
        for (int x : {3, 100, 255}) {
            Vec3 a = sky.cell(x, y), b = sky.cell(NishitaSky::kWidth - 1 - x, y);
            EXPECT_EQ(a.y, b.y);
            EXPECT_GT(a.y, 0.0f);
        }
    EXPECT_GT(sky.cell(NishitaSky::kWidth / 2, 10).y, sky.cell(0, 10).y);  // the sun is at the table's centre
    // The disc's top is brighter than its bottom (less air on the way), and both are very bright.
    EXPECT_GT(sky.sun_top().y, sky.sun_bottom().y);
    EXPECT_GT(sky.sun_bottom().y, 1e4f);
    EXPECT_TRUE(sky.has_sun());
    p.sun_elevation = -0.1f;
    EXPECT_FALSE(NishitaSky(p).has_sun());
    p.sun_elevation = 0.3f;
    p.sun_disc = false;
    EXPECT_FALSE(NishitaSky(p).has_sun());
}

TEST(EnvironmentLight, SunConeAndMapSamplesFollowTheirPdf) {
    // A widened disc (8 degrees: many chi-square cells) and Blender's default 0.545 degrees (the
    // cone's probability lands in one cell, so the mixture weights are what the test sees).
    const double alpha = sidak_significance(0.01, 2);
    for (float size : {0.14f, 0.009512f}) {
        EnvironmentLight env(nishita_world(size), nullptr, 64, 32);
        ASSERT_FLOAT_EQ(env.sun_probability(), 0.8f);
        auto sample = [&](Rng& rng) {
            LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            return s.valid() ? DirSample::valid(s.wi, s.pdf) : DirSample::invalid();
        };
        auto pdf = [&](const Vec3& w) { return env.pdf({0, 0, 0}, w); };
        Chi2Options opt;
        opt.grid = SphereGrid{60, 120};
        Chi2Result r = chi2_test_directions(sample, pdf, 500000, opt);
        EXPECT_TRUE(r.passes(alpha)) << size << ": " << r.summary() << "\n" << r.residual_map();
        EXPECT_GT(double(r.n_valid) / r.n_samples, 0.999);
        // The pdf integrates to 1 over the sphere: the map's part by quadrature, the cone's in closed form.
        EnvironmentLight map_only(nishita_world(size), nullptr, 64, 32, false);
        EXPECT_EQ(map_only.sun_probability(), 0.0f);
        IntegrationOptions io;
        io.subdivisions = 1;
        double map_integral = integrate_sphere([&](const Vec3& w) { return double(map_only.pdf(w)); }, io, SphereGrid{32, 64});
        EXPECT_NEAR(map_integral, 1.0, 2e-3);
    }
}

TEST(EnvironmentLight, SunSamplesAgreeWithPdfIntersectAndRadiance) {
    EnvironmentLight env(nishita_world(0.009512f), nullptr, 64, 32);
    Rng rng(5, 1);
    int in_sun = 0;
    for (int i = 0; i < 4000; ++i) {
        LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.valid());
        ASSERT_NEAR(env.pdf(s.wi), s.pdf, 1e-4f * s.pdf);
        LightHit h;
        ASSERT_TRUE(env.intersect(Ray{{0, 0, 0}, s.wi, 0.0f, kInf}, &h));
        ASSERT_NEAR(h.pdf, s.pdf, 1e-4f * s.pdf);
        in_sun += s.pdf > 1e3f;
    }
    EXPECT_NEAR(in_sun / 4000.0, 0.8, 0.03);  // the cone's share
    // A Nishita sky reading a transformed direction, or two suns, are left to the map (Cycles).
    EXPECT_EQ(EnvironmentLight(nishita_world(0.009512f, false), nullptr, 16, 8).sun_probability(), 0.0f);
}

// Irradiance on a surface facing the sun under the Nishita sky. Reference: the disc by uniform cone
// samples (its radiance is smooth there) plus the rest of the sky by quadrature. Sampling the disc on
// its own (with Cycles' 512 x 256 map) is unbiased and far less noisy than the map alone, even the
// 4096 x 2048 map Cycles uses without it: cells whose centre misses the 0.545-degree disc but which
// overlap it are drawn far too rarely for the light they hold (fireflies).
TEST(EnvironmentLight, SunSamplingIsUnbiasedAndLowersVariance) {
    auto world = nishita_world(0.009512f);
    const NishitaSky* sky = world->sampled_sun();
    ASSERT_NE(sky, nullptr);
    const Vec3 n = normalize(Vec3(0.3f, -0.2f, 1.0f)), axis = normalize(sky->sun_direction());
    const float one_minus_cos = 2.0f * sqr(std::sin(0.5f * sky->sun_half_angle()));
    EnvironmentLight with_sun(world, nullptr, 512, 256);
    auto irradiance = [&](const Vec3& w) {
        return double(luminance(with_sun.radiance(w, EnvironmentLight::light_sample_kind()))) * std::max(0.0f, dot(w, n));
    };
    auto in_disc = [&](const Vec3& w) { return 0.5f * dot(w - axis, w - axis) <= one_minus_cos; };
    MeanEstimator disc;
    Rng cone_rng(23, 1);
    const Frame frame(axis);
    for (int i = 0; i < 20000; ++i) {
        Vec3 w = frame.to_world(sample_uniform_cone({cone_rng.next_float(), cone_rng.next_float()}, one_minus_cos));
        disc.add(irradiance(w) / uniform_cone_pdf(one_minus_cos));
    }
    IntegrationOptions io;
    io.subdivisions = 2;
    io.rel_tolerance = 1e-4;
    const double rest = integrate_sphere([&](const Vec3& w) { return in_disc(w) ? 0.0 : irradiance(w); }, io,
                                         SphereGrid{64, 128});
    const double expected = disc.mean() + rest;

    auto estimate = [&](const EnvironmentLight& env) {
        Rng rng(17, 3);
        MeanEstimator e;
        for (int i = 0; i < 100000; ++i) {
            LightSample s = env.sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
            e.add(s.valid() ? double(luminance(s.L)) * std::max(0.0f, dot(s.wi, n)) / s.pdf : 0.0);
        }
        return e;
    };
    MeanEstimator sun = estimate(with_sun), fine = estimate(EnvironmentLight(world, nullptr, 4096, 2048, false));
    ZTest z = z_test_mean(sun, expected, 2e-3 * expected);
    EXPECT_GT(z.p_value, 1e-3) << sun.mean() << " +- " << sun.std_error() << " vs " << expected;
    std::printf("irradiance under the Nishita sun: expected %.4f (disc %.4f); sun sampled + 512x256 map %.4f "
                "(variance %.4g); 4096x2048 map only %.4f (variance %.4g)\n",
                expected, disc.mean(), sun.mean(), sun.variance(), fine.mean(), fine.variance());
    EXPECT_LT(sun.variance(), 1e-2 * fine.variance());

    // The mean radiance the light reports (light selection by power, the spectral emitter) counts
    // the disc by its own integral: the same two-part reference, without the cosine.
    auto lum = [&](const Vec3& w) { return double(luminance(with_sun.radiance(w, EnvironmentLight::light_sample_kind()))); };
    MeanEstimator disc_lum;
    for (int i = 0; i < 20000; ++i) {
        Vec3 w = frame.to_world(sample_uniform_cone({cone_rng.next_float(), cone_rng.next_float()}, one_minus_cos));
        disc_lum.add(lum(w) / uniform_cone_pdf(one_minus_cos));
    }
    const double mean_radiance =
        (disc_lum.mean() + integrate_sphere([&](const Vec3& w) { return in_disc(w) ? 0.0 : lum(w); }, io,
                                            SphereGrid{64, 128})) / (4.0 * kPi);
    EXPECT_NEAR(luminance(with_sun.average()), mean_radiance, 0.01 * mean_radiance);
}

// A sun-lit diffuse sphere on a floor under the Nishita sky, rendered at equal samples with the sun
// sampled on its own (Cycles' 512 x 256 map) and with the map alone (Cycles' 4096 x 2048 without
// it), each against a converged render: the error of the image, not only of one estimator; the
// render times are printed too (equal time: the sun's cone is cheaper to sample than the big map).
TEST(EnvironmentLight, SunSamplingLowersTheImageErrorAtEqualSamples) {
    auto scene_with = [](bool sample_sun) {
        auto s = std::make_shared<Scene>();
        add_sphere(*s, 0.6f, 24, 48, s->add_material(diffuse(Color(0.7f, 0.5f, 0.3f))));
        smis::testing::add_box(*s, {-3.0f, -3.0f, -0.8f}, {3.0f, 3.0f, -0.6f}, s->add_material(diffuse(Color(0.5f))));
        WorldDesc w;
        w.program = nishita_world(0.009512f);
        w.map_width = sample_sun ? 512 : 4096, w.map_height = sample_sun ? 256 : 2048;
        w.sample_sun = sample_sun;
        s->set_world(w);
        CameraDesc cam = camera_at({0, 0, 4.0f}, 24, 24);
        cam.lens = 40.0f;
        s->set_camera(cam);
        s->commit();
        return s;
    };
    const std::shared_ptr<Scene> scenes[2] = {scene_with(true), scene_with(false)};
    RenderSettings st;
    st.max_bounces = 2;
    st.samples = 1024;
    const std::vector<float> ref = render(scenes[0], st);
    st.samples = 16;
    auto rmse = [&](const std::vector<float>& img) {
        double sum = 0.0;
        for (size_t i = 0; i < img.size(); ++i)
            if (i % 4 != 3) sum += sqr(double(img[i]) - ref[i]);
        return std::sqrt(sum / (img.size() * 3 / 4));
    };
    double with_sun = 0.0, map_only = 0.0, seconds[2] = {0.0, 0.0};
    for (uint32_t seed : {1u, 2u, 3u}) {
        st.seed = seed;
        for (int k : {0, 1}) {
            auto t0 = std::chrono::steady_clock::now();
            double e = rmse(render(scenes[k], st)) / 3.0;
            seconds[k] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            (k == 0 ? with_sun : map_only) += e;
        }
    }
    std::printf("RMSE at 16 spp against 1024 spp (3 seeds): sun sampled %.4f, map only %.4f (ratio %.3f); "
                "render time %.3f s / %.3f s\n", with_sun, map_only, with_sun / map_only, seconds[0], seconds[1]);
    EXPECT_LT(with_sun, 0.8 * map_only);
}
