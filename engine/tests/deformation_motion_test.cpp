// Deformation motion blur: a mesh's vertices and corner normals at steps over the shutter, seen by
// rays at their time as the steps interpolated linearly (Cycles' motion triangles), whether the mesh
// is flattened into world space, a moving instance or shared by several instances; and the light
// samples of a moving emitter, taken where rays at the path's time see it.
#include <gtest/gtest.h>

#include <cmath>

#include "core/rng.h"
#include "test_scenes.h"

namespace smis {
namespace {

// A unit square in the plane z = h(step) whose corner normals tilt towards +x by tilt(step).
constexpr int kSteps = 3;
const float kHeight[kSteps] = {0.0f, 0.2f, 1.0f};  // not linear over the three steps
const float kTilt[kSteps] = {0.0f, 0.5f, 0.5f};

const float kSquare[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
const int32_t kTriangles[] = {0, 1, 2, 0, 2, 3};

std::vector<float> step_positions() {
    std::vector<float> out;
    for (int k = 0; k < kSteps; ++k)
        for (int i = 0; i < 4; ++i) out.insert(out.end(), {kSquare[3 * i], kSquare[3 * i + 1], kHeight[k]});
    return out;
}

std::vector<float> step_normals() {
    std::vector<float> out;
    for (int k = 0; k < kSteps; ++k)
        for (int c = 0; c < 6; ++c) out.insert(out.end(), {kTilt[k], 0.0f, 1.0f});
    return out;
}

// Piecewise linear between the steps, as the engine must interpolate.
float at_time(const float* values, float time) {
    float x = time * (kSteps - 1);
    int k = std::min(static_cast<int>(x), kSteps - 2);
    float f = x - k;
    return values[k] * (1.0f - f) + values[k + 1] * f;
}

uint32_t add_deforming_square(Scene& s, uint32_t material) {
    const float flat_normals[18] = {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1};
    uint32_t mesh = s.add_mesh(kSquare, 4, kTriangles, 2, flat_normals, nullptr, {material});
    std::vector<float> p = step_positions(), n = step_normals();
    s.set_mesh_motion(mesh, p.data(), kSteps, 4, n.data(), 2);
    return mesh;
}

Transform translation(const Vec3& t) {
    Transform m;
    m.m[0][3] = t.x, m.m[1][3] = t.y, m.m[2][3] = t.z;
    return m;
}

// Straight down at (x, y) at `time`: the square at its interpolated height, normal, offset by `shift`.
void expect_square_at(const Scene& s, float time, const Vec3& shift, const char* what) {
    const float x = 0.3f + shift.x, y = -0.4f + shift.y;
    Ray ray{Vec3(x, y, 5.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInf, time};
    SurfaceHit hit;
    ASSERT_TRUE(s.intersect(ray, &hit)) << what << " time " << time;
    const float h = at_time(kHeight, time) + shift.z, tilt = at_time(kTilt, time);
    EXPECT_NEAR(hit.p.z, h, 1e-4f) << what << " time " << time;
    EXPECT_NEAR(hit.t, 5.0f - h, 1e-4f) << what << " time " << time;
    EXPECT_NEAR(hit.ng.z, 1.0f, 1e-5f) << what << " time " << time;
    const Vec3 ns = normalize(Vec3(tilt, 0.0f, 1.0f));
    EXPECT_NEAR(hit.ns.x, ns.x, 1e-4f) << what << " time " << time;
    EXPECT_NEAR(hit.ns.z, ns.z, 1e-4f) << what << " time " << time;
    // Occlusion at the same time agrees: just above the surface is free, just below is not.
    EXPECT_FALSE(s.occluded(ray.o, ray.d, 5.0f - h - 1e-3f, time)) << what << " time " << time;
    EXPECT_TRUE(s.occluded(ray.o, ray.d, 5.0f - h + 1e-3f, time)) << what << " time " << time;
}

const float kTimes[] = {0.0f, 0.2f, 0.5f, 0.6f, 0.85f, 1.0f};

TEST(DeformationMotion, FlattenedMeshFollowsItsSteps) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    uint32_t mesh = add_deforming_square(s, grey);
    const Vec3 shift(2.0f, 1.0f, 0.5f);
    s.add_instance(mesh, translation(shift));  // used once, not moving: flattened into world space
    s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
    s.commit();
    ASSERT_TRUE(s.has_motion());
    EXPECT_EQ(s.stats().embree_instances, 0u);
    for (float time : kTimes) expect_square_at(s, time, shift, "flattened");
    EXPECT_GT(s.radius(), 0.5f * std::sqrt(8.0f + 1.0f) - 1e-4f);  // bounds cover the highest step
}

TEST(DeformationMotion, MovingAndSharedInstancesDeformToo) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    uint32_t mesh = add_deforming_square(s, grey);
    // One instance still at x = -5, one moving from x = 4 to x = 6 (both deform).
    s.add_instance(mesh, translation(Vec3(-5.0f, 0.0f, 0.0f)));
    s.add_instance(mesh, translation(Vec3(5.0f, 0.0f, 0.0f)), Color(1.0f), 0, 0, 1, false, kRayAllVisibility,
                   {translation(Vec3(4.0f, 0.0f, 0.0f)), translation(Vec3(6.0f, 0.0f, 0.0f))});
    s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
    s.commit();
    for (float time : kTimes) {
        expect_square_at(s, time, Vec3(-5.0f, 0.0f, 0.0f), "shared");
        expect_square_at(s, time, Vec3(4.0f + 2.0f * time, 0.0f, 0.0f), "moving");
    }
}

TEST(DeformationMotion, StillStepsAreNoMotionAndBadStepsAreRefused) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    uint32_t mesh = s.add_mesh(kSquare, 4, kTriangles, 2, nullptr, nullptr, {grey});
    std::vector<float> still(kSquare, kSquare + 12);
    still.insert(still.end(), kSquare, kSquare + 12);
    s.set_mesh_motion(mesh, still.data(), 2, 4);
    std::vector<float> p = step_positions(), n = step_normals();
    EXPECT_THROW(s.set_mesh_motion(mesh, p.data(), kSteps, 3), std::invalid_argument);  // topology changed
    EXPECT_THROW(s.set_mesh_motion(mesh, p.data(), 1, 4), std::invalid_argument);
    EXPECT_THROW(s.set_mesh_motion(mesh, p.data(), kSteps, 4, n.data(), 3), std::invalid_argument);
    std::vector<float> broken = p;
    broken[7] = std::nanf("");
    EXPECT_THROW(s.set_mesh_motion(mesh, broken.data(), kSteps, 4), std::invalid_argument);
    s.add_instance(mesh, Transform());
    s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
    s.commit();
    EXPECT_FALSE(s.has_motion());
}

// Moving emitters: a light sample at a path's time lands on the triangle where a ray at that time
// finds it, with the density the BSDF-hit side computes there (so MIS pairs the two techniques),
// for a deforming flattened emitter and a deforming emitter that also moves as an instance.
TEST(DeformationMotion, MovingEmittersAreSampledWhereRaysSeeThem) {
    for (bool moving_instance : {false, true}) {
        Scene s;
        uint32_t lamp = s.add_material(testing::diffuse(Color(0.0f), Color(2.0f)));
        uint32_t mesh = add_deforming_square(s, lamp);
        std::vector<Transform> motion;
        if (moving_instance) motion = {translation(Vec3(-1.0f, 0.0f, 0.0f)), translation(Vec3(1.0f, 0.5f, 0.0f))};
        s.add_instance(mesh, Transform(), Color(1.0f), 0, 0, 1, false, kRayAllVisibility, motion);
        s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
        s.commit();
        ASSERT_EQ(s.lights().size(), 2u);
        const Vec3 ref(0.2f, -0.1f, -3.0f);  // below the square: it faces away, two-sided emission
        Rng rng(7, 0);
        int checked = 0;
        for (float time : kTimes)
            for (uint32_t li = 0; li < 2; ++li)
                for (int i = 0; i < 8; ++i) {
                    const TriangleLight& tri = static_cast<const TriangleLight&>(s.light(li));
                    LightSample ls = tri.sample_at(ref, {rng.next_float(), rng.next_float()}, time);
                    ASSERT_TRUE(ls.valid()) << "time " << time;
                    EXPECT_NEAR(ref.z + ls.wi.z * ls.dist, at_time(kHeight, time), 1e-4f) << "time " << time;
                    if (ls.edge_distance < 1e-3f) continue;  // an edge: the ray may take the other triangle
                    SurfaceHit hit;
                    ASSERT_TRUE(s.intersect(Ray{ref, ls.wi, 0.0f, kInf, time}, &hit)) << "time " << time;
                    EXPECT_EQ(hit.light, int32_t(li)) << "time " << time;
                    EXPECT_NEAR(hit.t, ls.dist, 1e-4f * ls.dist) << "time " << time;
                    EXPECT_NEAR(tri.pdf_at(ref, hit.p, time), ls.pdf, 1e-4f * ls.pdf) << "time " << time;
                    ++checked;
                }
        EXPECT_GT(checked, 60) << (moving_instance ? "moving instance" : "flattened");
    }
}

}  // namespace
}  // namespace smis
