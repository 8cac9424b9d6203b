// Shadow rays towards mesh lights: a receiver close to a mesh light's plane must see the light.
// The scene: a diffuse ceiling (albedo 0.8) and a 1 x 1 emissive quad (radiance 1, two-sided) a
// small gap below it, the ceiling lit by the quad's top side. The ceiling's radiance is then
// 0.8 / pi x the irradiance of a uniform parallel rectangle, known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "integrators/path_tracing.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// Irradiance at height h below the corner of an A x B rectangle of unit radiance in a parallel
// plane: pi x the point-to-rectangle form factor.
double corner_irradiance(double a, double b, double h) {
    double x = a / h, y = b / h;
    return 0.5 * (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
                  y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y)));
}
// ... at (x, y) from the square [-s, s]^2, by signed corner rectangles.
double square_irradiance(double x, double y, double s, double h) {
    double e = 0.0;
    for (double dx : {s - x, s + x})
        for (double dy : {s - y, s + y})
            e += (dx < 0 ? -1 : 1) * (dy < 0 ? -1 : 1) * corner_irradiance(std::fabs(dx), std::fabs(dy), h);
    return e;
}

struct GapScene {
    std::shared_ptr<Scene> scene = std::make_shared<Scene>();
    Vec3 offset;
    float gap;
    GapScene(const Vec3& at, float gap_) : offset(at), gap(gap_) {
        uint32_t white = scene->add_material(diffuse(Color(0.8f)));
        uint32_t light = scene->add_material(diffuse(Color(0.0f), Color(1.0f)));
        const float z = 2.0f, zl = 2.0f - gap;
        float v[] = {-3, -3, z, 3, -3, z, 3, 3, z, -3, 3, z,  // ceiling, facing down
                     -0.5f, -0.5f, zl, 0.5f, -0.5f, zl, 0.5f, 0.5f, zl, -0.5f, 0.5f, zl};  // light, facing up
        for (int i = 0; i < 8; ++i) v[3 * i] += at.x, v[3 * i + 1] += at.y, v[3 * i + 2] += at.z;
        int32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7};
        int32_t slot[] = {0, 0, 1, 1};
        scene->add_instance(scene->add_mesh(v, 8, t, 4, nullptr, slot, {white, light}), Transform());
        scene->set_camera(camera_at(at, 8, 8));
        scene->commit();
    }
    // The ceiling's shading point above (x, y), found by a ray from just below it.
    ShadingPoint ceiling(float x, float y, Ray* ray) const {
        *ray = Ray{offset + Vec3(x, y, 2.0f - 0.5f * gap), Vec3(0, 0, 1), 0.0f, kInf};
        SurfaceHit hit;
        EXPECT_TRUE(scene->intersect(*ray, &hit));
        return make_shading_point(*scene, hit, ray->d);
    }
    double expected(float x, float y) const { return 0.8 / kPi * square_irradiance(x, y, 0.5, gap); }
};

// Light samples alone (no BSDF samples: the MIS weight is 1): the ceiling point sees the light.
void expect_light_samples_match(const GapScene& g, float x, float y) {
    Ray ray;
    ShadingPoint sp = g.ceiling(x, y, &ray);
    RenderSettings settings;
    Rng rng(3, 0);
    LocalCounters counters;
    stats::MeanEstimator est;
    for (int i = 0; i < 40000; ++i) {
        DirectSample ds = sample_direct(*g.scene, settings, sp, rng, counters, -1, 1, 0);
        est.add(ds.valid ? double(sp.bsdf.eval(sp.wo, ds.wi).y * ds.weighted.y) : 0.0);
    }
    double ref = g.expected(x, y);
    EXPECT_NEAR(est.mean(), ref, 0.02 * ref + 4.0 * est.std_error()) << "at (" << x << ", " << y << ")";
}

// The path tracer at Cycles' bounce limit 0 (light samples and BSDF samples combined by MIS).
void expect_direct_lighting_matches(const GapScene& g, float x, float y) {
    Ray ray;
    g.ceiling(x, y, &ray);
    RenderSettings settings;
    settings.max_bounces = 0;
    Rng rng(5, 0);
    LocalCounters counters;
    stats::MeanEstimator est;
    for (int i = 0; i < 40000; ++i) est.add(trace_path(*g.scene, settings, ray, PathState{}, rng, counters).y);
    double ref = g.expected(x, y);
    EXPECT_NEAR(est.mean(), ref, 0.02 * ref + 4.0 * est.std_error()) << "at (" << x << ", " << y << ")";
}

}  // namespace

// 20 cm gap at coordinates near 2: the origin's offset used to bring every light sample's shadow ray
// onto the light's own triangle before its end (all of them counted as occluded).
TEST(ShadowRays, MeshLightCloseBelowACeilingLightsIt) {
    GapScene g(Vec3(0.0f), 0.2f);
    for (float x : {0.0f, 0.3f, -0.8f}) {
        expect_light_samples_match(g, x, 0.1f);
        expect_direct_lighting_matches(g, x, 0.1f);
    }
}

// The same far from the origin (offsets of 256 ulps grow with the coordinates) and a 5 cm gap, as in
// the Cornell box whose light hangs 5 cm below the ceiling.
TEST(ShadowRays, MeshLightCloseBelowACeilingFarFromTheOrigin) {
    GapScene near_gap(Vec3(0.0f), 0.05f);
    expect_light_samples_match(near_gap, 0.2f, 0.0f);
    GapScene far(Vec3(60.0f, -40.0f, 30.0f), 0.2f);
    for (float x : {0.0f, -0.8f}) {
        expect_light_samples_match(far, x, 0.1f);
        expect_direct_lighting_matches(far, x, 0.1f);
    }
}

// A mesh light behind a wall that meets it at an edge (the emissive end of a lamp's housing): from
// the far side of the wall nothing of the light is visible. A shadow ray stopping 1e-4 short of the
// light point missed the wall for light points within that stretch of it (here those within 1 mm of
// the shared edge, 1e-3 of the light), and they lit the far side through the wall (the slit lamp
// of rendererer/prism.blend lit the ground around its housing).
TEST(ShadowRays, MeshLightDoesNotLeakThroughAWallAtItsEdge) {
    auto scene = std::make_shared<Scene>();
    uint32_t white = scene->add_material(diffuse(Color(0.8f)));
    uint32_t light = scene->add_material(diffuse(Color(0.0f), Color(1.0f)));
    float v[] = {0, -0.5f, 0, 1, -0.5f, 0, 1, 0.5f, 0, 0, 0.5f, 0,          // light, z = 0, x in [0, 1]
                 0, -0.5f, -1, 0, 0.5f, -1, 0, 0.5f, 1, 0, -0.5f, 1,          // wall x = 0 through its edge
                 -10, -1, -1, -10, 1, -1, -10, 1, 1, -10, -1, 1};             // receiver x = -10, facing +x
    int32_t t[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11};
    int32_t slot[] = {1, 1, 0, 0, 0, 0};
    scene->add_instance(scene->add_mesh(v, 12, t, 6, nullptr, slot, {white, light}), Transform());
    scene->set_camera(camera_at(Vec3(-5, 0, 0), 8, 8));
    scene->commit();
    Ray ray{Vec3(-9.0f, 0.0f, 0.05f), Vec3(-1, 0, 0), 0.0f, kInf};
    SurfaceHit hit;
    ASSERT_TRUE(scene->intersect(ray, &hit));
    ShadingPoint sp = make_shading_point(*scene, hit, ray.d);
    RenderSettings settings;
    Rng rng(9, 0);
    LocalCounters counters;
    int lit = 0;
    for (int i = 0; i < 100000; ++i) lit += sample_direct(*scene, settings, sp, rng, counters, -1, 1, 0).valid;
    // Without the test of the last stretch 101 of these samples lit the receiver; what remains is
    // the sliver of the light within float precision of the wall (1 sample here).
    EXPECT_LE(lit, 3);
}

// A mesh light's samples carry their distance to the triangle's nearest edge (which decides whether
// reaches_mesh_light tests the shadow ray's last stretch): checked against point-segment distances.
TEST(ShadowRays, TriangleLightSampleEdgeDistance) {
    const Vec3 a(0, 0, 1), b(2, 0, 1), c(0.5f, 1, 1);
    TriangleLight t(a, b, c, Color(1.0f));
    auto segment_distance = [](const Vec3& p, const Vec3& s0, const Vec3& s1) {
        const Vec3 e = s1 - s0;
        const float f = clampf(dot(p - s0, e) / dot(e, e), 0.0f, 1.0f);
        return length(p - (s0 + e * f));
    };
    Rng rng(3, 0);
    for (int i = 0; i < 1000; ++i) {
        LightSample ls = t.sample(Vec3(0.3f, 0.2f, 0.0f), Point2{rng.next_float(), rng.next_float()});
        ASSERT_TRUE(ls.valid());
        const Vec3 p = Vec3(0.3f, 0.2f, 0.0f) + ls.wi * ls.dist;
        const float expected =
            std::min({segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
        EXPECT_NEAR(ls.edge_distance, expected, 2e-5f) << i;
    }
    // Lamps sample no edge.
    EXPECT_FALSE(LightSample{}.edge_distance < kInf);
}
