// Scene building and camera framing: dropped geometry is counted, instances hit the right place,
// the camera frames the image the way Blender does.
#include <gtest/gtest.h>

#include <memory>

#include "core/rng.h"
#include "scene/light_selection.h"
#include "scene/scene.h"
#include "stats.h"
#include "test_scenes.h"

using namespace smis;

namespace {

Transform translation(float x, float y, float z) {
    Transform t;
    t.m[0][3] = x, t.m[1][3] = y, t.m[2][3] = z;
    return t;
}

CameraDesc looking_down_minus_z(int w, int h) {
    CameraDesc c;
    c.width = w;
    c.height = h;
    return c;  // identity matrix: at the origin, looking down -Z
}

// A unit quad in the z = 0 plane, two triangles, facing +Z.
const float kQuad[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const int32_t kQuadTris[] = {0, 1, 2, 0, 2, 3};

}  // namespace

TEST(Camera, PerspectiveFramingMatchesBlender) {
    CameraDesc c = looking_down_minus_z(200, 100);
    c.lens = 50.0f;
    c.sensor_width = 36.0f;
    Camera cam(c);
    // Sensor fit AUTO on a landscape image: the 36 mm sensor spans the width.
    Ray r = cam.generate_ray(200.0f, 50.0f);  // right edge, middle row
    EXPECT_NEAR(r.d.x / -r.d.z, 0.5f * 36.0f / 50.0f, 1e-5f);
    Ray top = cam.generate_ray(100.0f, 100.0f);
    EXPECT_NEAR(top.d.y / -top.d.z, 0.5f * 36.0f / 50.0f * 0.5f, 1e-5f);
    // Portrait: AUTO puts the sensor width on the larger (vertical) axis.
    Camera portrait(looking_down_minus_z(100, 200));
    Ray up = portrait.generate_ray(50.0f, 200.0f);
    EXPECT_NEAR(up.d.y / -up.d.z, 0.5f * 36.0f / 50.0f, 1e-5f);
}

TEST(Camera, ShiftIsInUnitsOfTheFittedDimension) {
    CameraDesc c = looking_down_minus_z(200, 100);
    c.shift_x = 0.25f;
    c.shift_y = 0.1f;
    Camera cam(c);
    Ray center = cam.generate_ray(100.0f, 50.0f);
    float full_width = 36.0f / 50.0f;
    EXPECT_NEAR(center.d.x / -center.d.z, 0.25f * full_width, 1e-5f);
    EXPECT_NEAR(center.d.y / -center.d.z, 0.1f * full_width, 1e-5f);
}

TEST(Camera, OrthographicScaleSpansTheFittedAxis) {
    CameraDesc c = looking_down_minus_z(100, 50);
    c.orthographic = true;
    c.ortho_scale = 4.0f;
    Camera cam(c);
    EXPECT_NEAR(cam.generate_ray(100.0f, 25.0f).o.x, 2.0f, 1e-5f);
    EXPECT_NEAR(cam.generate_ray(50.0f, 50.0f).o.y, 1.0f, 1e-5f);
}

TEST(Camera, BorderWindowIsClamped) {
    CameraDesc c = looking_down_minus_z(100, 80);
    int b[4] = {10, 20, 60, 200};
    std::copy(b, b + 4, c.border);
    Camera cam(c);
    EXPECT_EQ(cam.window_width(), 50);
    EXPECT_EQ(cam.window_height(), 60);
}

TEST(Scene, DropsDegenerateAndNonFiniteTriangles) {
    Scene s;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, nan, 0, 0};
    const int32_t t[] = {0, 1, 2,   // fine
                         0, 1, 3,   // collinear: zero area
                         0, 1, 4,   // NaN vertex
                         0, 1, 7,   // index out of range
                         0, 0, 2};  // repeated vertex
    uint32_t mesh = s.add_mesh(v, 5, t, 5, nullptr, nullptr, {});
    EXPECT_EQ(s.mesh_dropped(mesh), 4u);
    EXPECT_EQ(s.stats().dropped_triangles, 4u);
}

TEST(Scene, InstancesShareOnePrototypeAndHitWhereTheyAre) {
    Scene s;
    uint32_t mesh = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {});
    s.add_instance(mesh, translation(-3, 0, -5));
    s.add_instance(mesh, translation(3, 0, -10));
    s.set_camera(looking_down_minus_z(16, 16));
    s.commit();
    EXPECT_EQ(s.stats().embree_instances, 2u);
    SurfaceHit hit;
    ASSERT_TRUE(s.intersect({{-3, 0, 0}, {0, 0, -1}}, &hit));
    EXPECT_NEAR(hit.t, 5.0f, 1e-5f);
    EXPECT_NEAR(hit.ng.z, 1.0f, 1e-6f);
    ASSERT_TRUE(s.intersect({{3, 0.5f, 0}, {0, 0, -1}}, &hit));
    EXPECT_NEAR(hit.t, 10.0f, 1e-5f);
    EXPECT_NEAR(hit.p.y, 0.5f, 1e-5f);
    EXPECT_FALSE(s.intersect({{0, 0, 0}, {0, 0, -1}}, &hit));
    EXPECT_TRUE(s.occluded({3, 0, 0}, {0, 0, -1}, 11.0f));
    EXPECT_FALSE(s.occluded({3, 0, 0}, {0, 0, -1}, 9.0f));
}

TEST(Scene, MirroredSingleUserMeshKeepsOutwardNormal) {
    Scene s;
    uint32_t mesh = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {});
    Transform mirror = translation(0, 0, -5);
    mirror.m[0][0] = -1.0f;  // mirror in x: winding flips, the outward side must not
    s.add_instance(mesh, mirror);
    s.set_camera(looking_down_minus_z(16, 16));
    s.commit();
    SurfaceHit hit;
    ASSERT_TRUE(s.intersect({{0.2f, 0.1f, 0}, {0, 0, -1}}, &hit));
    EXPECT_NEAR(hit.ng.z, 1.0f, 1e-6f);
}

TEST(Scene, EmissiveTrianglesBecomeLightsPerInstance) {
    Scene s;
    Material glow;
    glow.emission = Color(2.0f);
    uint32_t mat = s.add_material(glow);
    uint32_t mesh = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {mat});
    s.add_instance(mesh, translation(0, 0, -5));
    s.add_instance(mesh, translation(0, 0, -6));
    s.set_camera(looking_down_minus_z(16, 16));
    s.commit();
    EXPECT_EQ(s.stats().emissive_triangles, 4u);
    SurfaceHit hit;
    ASSERT_TRUE(s.intersect({{0.1f, 0.2f, 0}, {0, 0, -1}}, &hit));
    ASSERT_GE(hit.light, 0);
    EXPECT_GT(s.light_pmf(hit.light), 0.0f);
}

TEST(Scene, RejectsUnusableLights) {
    Scene s;
    LightDesc neg;
    neg.type = "POINT";
    neg.power = -10.0f;
    EXPECT_THROW(s.add_light(neg), std::invalid_argument);
    LightDesc flat;
    flat.type = "AREA";
    flat.power = 10.0f;
    flat.size = 0.0f;
    EXPECT_THROW(s.add_light(flat), std::invalid_argument);
    EXPECT_THROW((void)s.commit(), std::invalid_argument);  // no camera
}

TEST(Scene, CameraRaysSkipTheBvhOnlyWhenTheyMissTheSceneBox) {
    // Camera rays that surely miss the scene's bounding box are answered without Embree
    // (scene_bounds.h). Rays aimed within 1e-7 to 1e-2 of the box's edges and corners, from a camera
    // near a small object and from one 1e4 away from it, must find exactly what the same ray finds
    // through the BVH (a ray seen by every object takes no shortcut).
    struct Case {
        float cam_z, scale;
    };
    for (const Case c : {Case{0.0f, 0.5f}, Case{1e4f, 0.01f}}) {
        Scene s;
        uint32_t mesh = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {});
        Transform t = translation(0.3f * c.scale, 0.2f * c.scale, -40.0f * c.scale);
        t.m[0][0] = t.m[1][1] = c.scale;
        t.m[2][1] = c.scale;  // tilted: the box has depth, its corners are no quad corners
        s.add_instance(mesh, t);
        CameraDesc cam = looking_down_minus_z(64, 64);
        cam.to_world = translation(0, 0, c.cam_z);
        s.set_camera(cam);
        s.commit();
        EXPECT_TRUE(s.tests_camera_rays_against_bounds()) << c.cam_z;
        const Vec3 o(0, 0, c.cam_z);
        Rng rng(7, 0);
        int hits = 0, misses = 0;
        // The quad's bounding box (y tilted into z): its edges and corners are where rays graze.
        const Vec3 centre = t.point(Vec3(0.0f)), half(c.scale);
        for (int i = 0; i < 20000; ++i) {
            // A point on an edge of the box (two coordinates on a face), then moved off it.
            Vec3 u(rng.next_float() * 2 - 1, rng.next_float() * 2 - 1, rng.next_float() * 2 - 1);
            u[int(rng.next_float() * 3)] = rng.next_float() < 0.5f ? -1.0f : 1.0f;
            u[int(rng.next_float() * 3)] = rng.next_float() < 0.5f ? -1.0f : 1.0f;
            const float off = c.scale * std::pow(10.0f, -7.0f + 5.0f * rng.next_float());
            Vec3 target = centre + half * u + normalize(Vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f,
                                                             rng.next_float() - 0.5f)) * off;
            Ray camera_ray{o, normalize(target - o), 1e-3f, 1e6f, kShutterCentre, kRayCamera};
            Ray any_ray = camera_ray;
            any_ray.visibility = kRayAllVisibility;
            SurfaceHit h1, h2;
            const bool f1 = s.intersect(camera_ray, &h1), f2 = s.intersect(any_ray, &h2);
            ASSERT_EQ(f1, f2) << "case " << c.cam_z << " ray " << i;
            if (f1) {
                EXPECT_EQ(h1.t, h2.t);
            }
            (f1 ? hits : misses)++;
        }
        EXPECT_GT(hits, 2000) << c.cam_z;
        EXPECT_GT(misses, 2000) << c.cam_z;
    }
    // Every camera ray meets the box (an object filling the view): no test, it would only cost.
    Scene wall;
    uint32_t quad = wall.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {});
    Transform big = translation(0, 0, -1);
    big.m[0][0] = big.m[1][1] = 100.0f;
    wall.add_instance(quad, big);
    wall.set_camera(looking_down_minus_z(64, 64));
    wall.commit();
    EXPECT_FALSE(wall.tests_camera_rays_against_bounds());
}

TEST(SceneBounds, SaysMissOnlyForRaysThatSurelyMissTheBox) {
    SceneBounds b;  // unpadded: rays exactly on its faces
    b.lo = Vec3(0.0f), b.hi = Vec3(1.0f);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    EXPECT_TRUE(b.may_meet({{0.5f, 0.5f, -1}, {0, 0, 1}}));
    EXPECT_FALSE(b.may_meet({{2, 0.5f, -1}, normalize(Vec3(0.1f, 0, 1))}));
    EXPECT_FALSE(b.may_meet({{0.5f, 0.5f, -1}, normalize(Vec3(1, 0, 0.1f))}));
    EXPECT_FALSE(b.may_meet({{0.5f, 0.5f, -1}, {0, 0, 1}, 0.0f, 0.5f}));  // stops before the box
    EXPECT_FALSE(b.may_meet({{0.5f, 0.5f, 3}, {0, 0, 1}}));               // points away
    // In a face's plane (direction component +-0, origin on the plane: 0 x inf = NaN): may meet.
    for (float zero : {0.0f, -0.0f}) {
        EXPECT_TRUE(b.may_meet({{1, 0.5f, -1}, {zero, 0, 1}}));
        EXPECT_TRUE(b.may_meet({{0, 0.5f, -1}, {zero, 0, 1}}));
    }
    EXPECT_TRUE(b.may_meet({{0.5f, 0.5f, -1}, {nan, 0, 1}}));
    EXPECT_TRUE(b.may_meet({{0.5f, 0.5f, -1}, {0, 0, 1}, nan, kInf}));
}

TEST(Scene, InPlaceViewportUpdatesEqualAFreshScene) {
    // A fast-build (viewport) scene moved and edited in place answers rays exactly like a scene
    // built from scratch in the final state.
    const float tri[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0};
    const int32_t one[] = {0, 1, 2};
    auto build = [&](const float* verts, const Transform& a, const Transform& b, bool fast) {
        auto s = std::make_unique<Scene>();
        s->set_fast_build(fast);
        uint32_t quad = s->add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {});
        uint32_t other = s->add_mesh(verts, 3, one, 1, nullptr, nullptr, {});
        s->add_instance(quad, a);
        s->add_instance(other, b);
        s->set_camera(looking_down_minus_z(8, 8));
        s->commit();
        return s;
    };
    const float moved_tri[] = {-1, -1, 0, 1, -1, 0, 0, 1, 0.5f};
    Transform a0 = translation(0, 0, -3), a1 = translation(0.5f, 0, -2), b = translation(3, 0, -4);
    auto updated = build(tri, a0, b, true);
    float rows[24];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) rows[4 * r + c] = a1.m[r][c], rows[12 + 4 * r + c] = b.m[r][c];
    ASSERT_TRUE(updated->set_instance_transforms(rows, 2));
    ASSERT_TRUE(updated->replace_mesh(1, moved_tri, 3, one, 1, nullptr, nullptr, {}));
    EXPECT_FALSE(updated->set_instance_transforms(rows, 1));  // instance count differs: rebuild
    auto fresh = build(moved_tri, a1, b, false);
    Rng rng(2, 0);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        Ray r{Vec3(0, 0, 0), normalize(Vec3(rng.next_float() * 8 - 4, rng.next_float() * 2 - 1, -1)), 0, kInf};
        SurfaceHit h1, h2;
        bool f1 = updated->intersect(r, &h1), f2 = fresh->intersect(r, &h2);
        ASSERT_EQ(f1, f2) << i;
        if (!f1) continue;
        ++hits;
        EXPECT_NEAR(h1.t, h2.t, 1e-4f);
        EXPECT_NEAR(length(h1.ng - h2.ng), 0.0f, 1e-4f);
    }
    EXPECT_GT(hits, 100);
}

TEST(Scene, InPlaceMaterialAndLightEditsEqualAFreshScene) {
    // Viewport material, lamp and world edits replace what changed in the committed scene; its
    // materials and light table must then be those of a scene built from scratch in the final state.
    using smis::testing::diffuse;
    auto lamp = [](float power, float x) {
        LightDesc d;
        d.type = "POINT";
        d.power = power;
        d.to_world = translation(x, 0, -1);
        return d;
    };
    uint32_t m0 = 0, m1 = 0;  // the scene has its own default material first
    auto build = [&](Color albedo, Color emission, const std::vector<LightDesc>& lamps, Color world, bool fast) {
        auto s = std::make_unique<Scene>();
        s->set_fast_build(fast);
        m0 = s->add_material(diffuse(albedo));
        m1 = s->add_material(diffuse(Color(0.5f), emission));
        uint32_t quad = s->add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {m0});
        uint32_t glow = s->add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {m1});
        s->add_instance(quad, translation(0, 0, -3));
        s->add_instance(glow, translation(3, 0, -4));
        for (const LightDesc& d : lamps) s->add_light(d);
        s->set_world(world);
        s->set_camera(looking_down_minus_z(8, 8));
        s->commit();
        return s;
    };
    auto updated = build(Color(0.8f), Color(2.0f), {lamp(100, 0)}, Color(0.1f), true);
    EXPECT_FALSE(build(Color(0.8f), Color(2.0f), {}, Color(0.0f), false)->replace_material(m0, diffuse(Color(0.1f), Color(0.0f))))
        << "only viewport (fast-build) scenes are edited in place";
    ASSERT_TRUE(updated->replace_material(m0, diffuse(Color(0.2f, 0.4f, 0.6f), Color(0.0f))));
    ASSERT_TRUE(updated->replace_material(m1, diffuse(Color(0.5f), Color(5.0f, 1.0f, 0.5f))));
    EXPECT_FALSE(updated->replace_material(m0, diffuse(Color(0.1f), Color(1.0f))))  // would become emissive
        << "emissive triangles are found at commit";
    std::vector<LightDesc> lamps = {lamp(50, 1), lamp(300, -1)};
    ASSERT_TRUE(updated->replace_lights(lamps, Color(0.0f)));
    LightDesc bad = lamp(-1, 0);
    EXPECT_THROW(updated->replace_lights({bad}, Color(0.0f)), std::invalid_argument);
    auto fresh = build(Color(0.2f, 0.4f, 0.6f), Color(5.0f, 1.0f, 0.5f), lamps, Color(0.0f), false);

    EXPECT_EQ(updated->material(m0).lobes[0].weight.z, 0.6f);
    EXPECT_EQ(updated->material(m1).emission.x, 5.0f);
    ASSERT_EQ(updated->lights().size(), fresh->lights().size());  // 2 lamps + 2 emissive triangles, no world
    for (uint32_t i = 0; i < fresh->lights().size(); ++i) {
        EXPECT_NEAR(updated->light_pmf(i), fresh->light_pmf(i), 1e-6f) << i;
        EXPECT_NEAR(updated->light(i).power(1.0f), fresh->light(i).power(1.0f), 1e-3f) << i;
    }
    EXPECT_TRUE(updated->infinite_lights().empty());
    // A hit on the emitter names a triangle light carrying the new emission.
    SurfaceHit h;
    ASSERT_TRUE(updated->intersect(Ray{Vec3(3, 0, 0), Vec3(0, 0, -1), 0, kInf}, &h));
    ASSERT_GE(h.light, 0);
    EXPECT_EQ(static_cast<const TriangleLight&>(updated->light(h.light)).radiance().x, 5.0f);
}

// scene/light_selection.h: NEE chooses a light half by power and half uniformly among emitters
// (a lamp, or one instance's emissive triangles), so a dim emitter beside a bright one keeps a
// share; lights without power are never chosen.
TEST(Scene, LightSelectionGivesEveryEmitterAShareWhateverItsPower) {
    const std::vector<float> power = {300.0f, 20.0f, 0.0f, 1.0f, 3.0f};
    const std::vector<uint32_t> emitter = {0, 1, 2, 3, 3};  // lights 3 and 4: one mesh's triangles
    std::vector<float> w = defensive_light_weights(power, emitter);
    const double total = 324.0, a = kUniformEmitterShare;
    EXPECT_NEAR(w[0], (1 - a) * 300 / total + a / 3, 1e-6);
    EXPECT_NEAR(w[1], (1 - a) * 20 / total + a / 3, 1e-6);
    EXPECT_EQ(w[2], 0.0f);
    EXPECT_NEAR(w[3], (1 - a) * 1 / total + a / 3 * 0.25, 1e-6);
    EXPECT_NEAR(w[4], (1 - a) * 3 / total + a / 3 * 0.75, 1e-6);
    EXPECT_NEAR(w[0] + w[1] + w[3] + w[4], 1.0, 1e-6);
    std::vector<float> by_power = defensive_light_weights(power, emitter, 0.0f);
    for (size_t i = 0; i < power.size(); ++i) EXPECT_NEAR(by_power[i], power[i] / total, 1e-6) << i;

    // In a scene: a one-triangle emitter ten times brighter than a two-triangle one. Each object
    // is one emitter (half of the uniform share), its triangles split it by power.
    Scene s;
    Material bright, dim;
    bright.emission = Color(20.0f);
    dim.emission = Color(2.0f);
    const uint32_t mesh_bright = s.add_mesh(kQuad, 4, kQuadTris, 1, nullptr, nullptr, {s.add_material(bright)});
    const uint32_t mesh_dim = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {s.add_material(dim)});
    s.add_instance(mesh_bright, translation(0, 0, -5));
    s.add_instance(mesh_dim, translation(0, 3, -5));
    s.set_camera(looking_down_minus_z(16, 16));
    s.commit();
    ASSERT_EQ(s.lights().size(), 3u);
    double sum = 0.0;
    int bright_lights = 0;
    for (uint32_t i = 0; i < 3; ++i) {
        const bool is_bright = s.light_power_pmf(i) > 0.5f;
        bright_lights += is_bright;
        EXPECT_NEAR(s.light_power_pmf(i), is_bright ? 10.0 / 12.0 : 1.0 / 12.0, 1e-5) << i;
        EXPECT_NEAR(s.light_pmf(i), (1 - a) * s.light_power_pmf(i) + a / 2 * (is_bright ? 1.0 : 0.5), 1e-5) << i;
        sum += s.light_pmf(i);
    }
    EXPECT_EQ(bright_lights, 1);
    EXPECT_NEAR(sum, 1.0, 1e-5);
}

// A 100 W point lamp, a sun of strength 3 and a grey World (0.5), as the light-selection tests use them.
static void add_lamp_sun_and_world(Scene* s) {
    LightDesc lamp;
    lamp.type = "POINT";
    lamp.power = 100.0f;
    lamp.to_world = translation(0, 0, -1);
    LightDesc sun;
    sun.type = "SUN";
    sun.strength = 3.0f;
    s->add_light(lamp);
    s->add_light(sun);
    s->set_world(Color(0.5f));
}

// scene/light_selection.h, cycles_light_weights: Cycles 3.4's distribution (scene/light.cpp,
// device_update_distribution): every lamp 1 / L, every emissive triangle its share of the triangles'
// area, half each when the scene has both; a World without variation is not chosen.
TEST(Scene, CyclesLightWeightsSplitLampsUniformlyAndTrianglesByArea) {
    using R = CyclesLightRole;
    const std::vector<R> role = {R::Lamp, R::Triangle, R::NotSampled, R::Triangle, R::Lamp, R::Triangle};
    const std::vector<float> area = {0.0f, 1.0f, 0.0f, 2.0f, 0.0f, 3.0f};
    std::vector<float> w = cycles_light_weights(role, area);
    const double expected[] = {0.25, 0.5 / 6, 0.0, 1.0 / 6, 0.25, 1.5 / 6};
    double sum = 0.0;
    for (size_t i = 0; i < w.size(); ++i) {
        EXPECT_NEAR(w[i], expected[i], 1e-6) << i;
        sum += w[i];
    }
    EXPECT_NEAR(sum, 1.0, 1e-6);
    // Lamps alone share all of it, triangles alone too; nothing sampled: all zero.
    EXPECT_EQ(cycles_light_weights({R::Lamp, R::NotSampled, R::Lamp}, {0, 0, 0}),
              (std::vector<float>{0.5f, 0.0f, 0.5f}));
    std::vector<float> tri = cycles_light_weights({R::Triangle, R::Triangle}, {1.0f, 3.0f});
    EXPECT_NEAR(tri[0], 0.25, 1e-6);
    EXPECT_NEAR(tri[1], 0.75, 1e-6);
    EXPECT_EQ(cycles_light_weights({R::NotSampled}, {0.0f}), (std::vector<float>{0.0f}));
}

// The scene's table for LightSelection::Cycles34 (the setting multiscatter_cycles_walk): a point lamp,
// a sun, two emissive triangles of areas 0.5 and 1.5 and a grey World. Cycles samples the lamps 1/4
// each, the triangles 1/2 by area, never the World; NEE draws lights with exactly these frequencies
// (chi-square against the formula, not against the table's own pmf); back to Defensive after commit
// restores the default table.
TEST(Scene, CyclesLightSelectionIsCyclesDistributionAndSamplesIt) {
    auto build = [](LightSelection mode) {
        auto s = std::make_unique<Scene>();
        s->set_light_selection(mode);
        add_lamp_sun_and_world(s.get());
        // Triangles (0,0)-(1,0)-(1,1) (area 0.5) and (0,0)-(1,1)-(-2,1) (area 1.5).
        const float v[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, -2, 1, 0};
        const int32_t t[] = {0, 1, 2, 0, 2, 3};
        Material glow;
        glow.emission = Color(4.0f);
        s->add_instance(s->add_mesh(v, 4, t, 2, nullptr, nullptr, {s->add_material(glow)}), translation(0, 0, -5));
        s->set_camera(looking_down_minus_z(8, 8));
        s->commit();
        return s;
    };
    std::unique_ptr<Scene> s = build(LightSelection::Cycles34);
    ASSERT_EQ(s->lights().size(), 5u);
    std::vector<double> expected(5);
    double sum = 0.0;
    int worlds = 0;
    for (uint32_t i = 0; i < 5; ++i) {
        const Light& l = s->light(i);
        if (auto* tri = dynamic_cast<const TriangleLight*>(&l)) expected[i] = 0.5 * tri->area() / 2.0;
        else if (l.is_background()) expected[i] = 0.0, ++worlds;
        else expected[i] = 0.25;
        EXPECT_NEAR(s->light_pmf(i), expected[i], 1e-6) << i;
        sum += s->light_pmf(i);
    }
    EXPECT_EQ(worlds, 1);
    EXPECT_NEAR(sum, 1.0, 1e-6);
    // The triangles' areas as built, so the area split is really tested.
    std::vector<double> tri_pmfs;
    for (uint32_t i = 0; i < 5; ++i)
        if (dynamic_cast<const TriangleLight*>(&s->light(i))) tri_pmfs.push_back(expected[i]);
    ASSERT_EQ(tri_pmfs.size(), 2u);
    EXPECT_NEAR(std::min(tri_pmfs[0], tri_pmfs[1]), 0.125, 1e-6);
    EXPECT_NEAR(std::max(tri_pmfs[0], tri_pmfs[1]), 0.375, 1e-6);

    // NEE's draws (Scene::light_selection, as sample_direct uses it) against the formula.
    Rng rng(7, 3);
    const int n = 200000;
    std::vector<int> counts(5, 0);
    for (int k = 0; k < n; ++k) ++counts[s->light_selection().sample(rng.next_float())];
    double chi2 = 0.0;
    int dof = -1;
    for (uint32_t i = 0; i < 5; ++i) {
        if (expected[i] == 0.0) {
            EXPECT_EQ(counts[i], 0) << i;
            continue;
        }
        const double e = n * expected[i];
        chi2 += (counts[i] - e) * (counts[i] - e) / e;
        ++dof;
    }
    EXPECT_GT(stats::chi2_survival(chi2, dof), 1e-3) << "chi2 " << chi2;

    // Back to the default after commit: the table a fresh default scene builds.
    std::unique_ptr<Scene> fresh = build(LightSelection::Defensive);
    s->set_light_selection(LightSelection::Defensive);
    for (uint32_t i = 0; i < 5; ++i) EXPECT_EQ(s->light_pmf(i), fresh->light_pmf(i)) << i;
    EXPECT_GT(fresh->light_pmf(4) + fresh->light_pmf(3) + fresh->light_pmf(2), 0.0f);
}

// Lights at infinity (a sun, the world) take only their power share, no uniform one: with an equal
// share clamped sun and world images moved (scene.cpp, where the emitter ids are set).
TEST(Scene, LightSelectionGivesSunAndWorldOnlyTheirPowerShare) {
    Scene s;
    add_lamp_sun_and_world(&s);
    const uint32_t quad = s.add_mesh(kQuad, 4, kQuadTris, 2, nullptr, nullptr, {s.add_material(Material{})});
    s.add_instance(quad, translation(0, 0, -3));
    s.set_camera(looking_down_minus_z(8, 8));
    s.commit();
    const double a = kUniformEmitterShare;
    int at_infinity = 0;
    double sum = 0.0;
    for (uint32_t i = 0; i < s.lights().size(); ++i) {
        const bool infinite = s.light(i).at_infinity();
        at_infinity += infinite;
        // The only local emitter (the lamp) gets the whole uniform share.
        EXPECT_NEAR(s.light_pmf(i), (1 - a) * s.light_power_pmf(i) + (infinite ? 0.0 : a), 1e-5) << i;
        sum += s.light_pmf(i);
    }
    EXPECT_EQ(at_infinity, 2);
    EXPECT_NEAR(sum, 1.0, 1e-5);
}
