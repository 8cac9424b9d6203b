// Transform motion blur: the decomposition and interpolation of motion steps (Cycles'), Embree's
// motion instances following them, the camera's motion, the shutter curve's time distribution, and
// a render of a box crossing the view whose pixels must see it for the time it covers them.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/motion.h"
#include "test_scenes.h"

namespace smis {
namespace {

Transform rotation_z(float degrees, const Vec3& translation = Vec3(0.0f)) {
    float a = degrees * kPi / 180.0f;
    Transform t;
    t.m[0][0] = std::cos(a), t.m[0][1] = -std::sin(a);
    t.m[1][0] = std::sin(a), t.m[1][1] = std::cos(a);
    t.m[0][3] = translation.x, t.m[1][3] = translation.y, t.m[2][3] = translation.z;
    return t;
}

Transform product(const Transform& a, const Transform& b) {
    Transform r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) {
            float v = j == 3 ? a.m[i][3] : 0.0f;
            for (int k = 0; k < 3; ++k) v += a.m[i][k] * b.m[k][j];
            r.m[i][j] = v;
        }
    return r;
}

void expect_transform_near(const Transform& a, const Transform& b, float tol) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(a.m[i][j], b.m[i][j], tol) << "entry " << i << "," << j;
}

TEST(Motion, DecompositionComposesBackToTheMatrix) {
    // Rotation, non-uniform scale, shear, translation; and the same mirrored.
    Transform shear;
    shear.m[0][0] = 2.0f, shear.m[0][1] = 0.3f, shear.m[1][1] = 0.5f, shear.m[1][2] = -0.2f, shear.m[2][2] = 1.5f;
    Transform tilt;  // 30 degrees about x
    tilt.m[1][1] = std::cos(0.5236f), tilt.m[1][2] = -std::sin(0.5236f);
    tilt.m[2][1] = std::sin(0.5236f), tilt.m[2][2] = std::cos(0.5236f);
    Transform m = product(product(rotation_z(70.0f, Vec3(1.0f, -2.0f, 3.0f)), tilt), shear);
    expect_transform_near(compose(decompose(m)), m, 1e-5f);
    Transform mirror;
    mirror.m[0][0] = -1.0f;
    Transform mirrored = product(m, mirror);
    DecomposedTransform d = decompose(mirrored);
    expect_transform_near(compose(d), mirrored, 1e-5f);
    const float* q = d.quat;
    EXPECT_NEAR(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3], 1.0f, 1e-5f);  // a proper rotation
}

TEST(Motion, InterpolationSlerpsRotationAndLerpsTranslation) {
    std::vector<DecomposedTransform> steps =
        decompose_motion({rotation_z(0.0f, Vec3(0.0f)), rotation_z(90.0f, Vec3(2.0f, 0.0f, 0.0f))});
    expect_transform_near(interpolate_motion(steps, 0.0f), rotation_z(0.0f), 1e-6f);
    expect_transform_near(interpolate_motion(steps, 1.0f), rotation_z(90.0f, Vec3(2.0f, 0.0f, 0.0f)), 1e-6f);
    // Halfway: 45 degrees with unit scale (a linear blend of the matrices would shrink it to 0.71).
    expect_transform_near(interpolate_motion(steps, 0.5f), rotation_z(45.0f, Vec3(1.0f, 0.0f, 0.0f)), 1e-5f);
    // Three steps: the time is split between the two segments.
    steps = decompose_motion({rotation_z(0.0f), rotation_z(0.0f, Vec3(1.0f, 0.0f, 0.0f)),
                              rotation_z(0.0f, Vec3(1.0f, 4.0f, 0.0f))});
    expect_transform_near(interpolate_motion(steps, 0.25f), rotation_z(0.0f, Vec3(0.5f, 0.0f, 0.0f)), 1e-6f);
    expect_transform_near(interpolate_motion(steps, 0.75f), rotation_z(0.0f, Vec3(1.0f, 2.0f, 0.0f)), 1e-6f);
    // A rotation past 180 degrees between steps goes the short way once the quaternions are chained.
    steps = decompose_motion({rotation_z(170.0f), rotation_z(-170.0f)});
    expect_transform_near(interpolate_motion(steps, 0.5f), rotation_z(180.0f), 1e-5f);
}

// A unit cube [-0.5, 0.5]^3 instanced with the given motion.
void add_moving_cube(Scene& s, uint32_t material, const std::vector<Transform>& motion, float y_half = 0.5f) {
    const Vec3 lo(-0.5f, -y_half, -0.5f), hi(0.5f, y_half, 0.5f);
    const float v[] = {lo.x, lo.y, lo.z, hi.x, lo.y, lo.z, hi.x, hi.y, lo.z, lo.x, hi.y, lo.z,
                       lo.x, lo.y, hi.z, hi.x, lo.y, hi.z, hi.x, hi.y, hi.z, lo.x, hi.y, hi.z};
    const int32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                         2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 3, 0, 4, 3, 4, 7};
    uint32_t mesh = s.add_mesh(v, 8, t, 12, nullptr, nullptr, {material});
    s.add_instance(mesh, motion[motion.size() / 2], Color(1.0f), 0.0f, 0.0f, 1.0f, false, kRayAllVisibility, motion);
}

TEST(Motion, EmbreeInstancesMoveAsTheInterpolationSays) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    // Moves 4 units along x while turning 90 degrees about z (three steps, as Cycles' default).
    std::vector<Transform> motion = {rotation_z(0.0f, Vec3(-2.0f, 0.0f, 0.0f)), rotation_z(30.0f, Vec3(0.0f)),
                                     rotation_z(90.0f, Vec3(2.0f, 0.0f, 0.0f))};
    add_moving_cube(s, grey, motion);
    s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
    s.commit();
    ASSERT_TRUE(s.has_motion());
    std::vector<DecomposedTransform> steps = decompose_motion(motion);
    for (float time : {0.0f, 0.1f, 0.3f, 0.5f, 0.62f, 0.9f, 1.0f}) {
        Transform at = interpolate_motion(steps, time);
        // Straight down onto a point of the top face (z = 0.5 in the cube's space).
        Vec3 target = at.point(Vec3(0.3f, -0.2f, 0.5f));
        Ray ray{Vec3(target.x, target.y, 5.0f), Vec3(0.0f, 0.0f, -1.0f), 0.0f, kInf, time};
        SurfaceHit hit;
        ASSERT_TRUE(s.intersect(ray, &hit)) << "time " << time;
        EXPECT_NEAR(hit.p.x, target.x, 1e-4f) << "time " << time;
        EXPECT_NEAR(hit.p.y, target.y, 1e-4f) << "time " << time;
        EXPECT_NEAR(hit.p.z, 0.5f, 1e-4f) << "time " << time;
        EXPECT_NEAR(hit.t, 4.5f, 1e-4f) << "time " << time;
        EXPECT_NEAR(hit.ng.z, 1.0f, 1e-4f) << "time " << time;
        EXPECT_EQ(hit.time, time);
        // The same ray a quarter of the shutter away finds the cube gone (it moved >= 1 unit).
        Ray other = ray;
        other.time = time < 0.5f ? time + 0.45f : time - 0.45f;
        EXPECT_FALSE(s.occluded(ray.o, ray.d, kInf, other.time)) << "time " << time;
        EXPECT_TRUE(s.occluded(ray.o, ray.d, kInf, time)) << "time " << time;
    }
}

TEST(Motion, StillInstancesAndMatchingStepsAreNoMotion) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    add_moving_cube(s, grey, {rotation_z(10.0f), rotation_z(10.0f), rotation_z(10.0f)});
    s.set_camera(testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8));
    s.commit();
    EXPECT_FALSE(s.has_motion());
    EXPECT_EQ(s.stats().embree_instances, 0u);  // flattened as any mesh used once
}

TEST(Motion, BadStepsAreRefused) {
    Scene s;
    uint32_t grey = s.add_material(testing::diffuse(Color(0.5f)));
    const float v[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int32_t t[] = {0, 1, 2};
    uint32_t plain = s.add_mesh(v, 3, t, 1, nullptr, nullptr, {grey});
    Transform zero;
    zero.m[0][0] = 0.0f;
    EXPECT_THROW(s.add_instance(plain, Transform(), Color(1.0f), 0, 0, 1, false, kRayAllVisibility, {Transform(), zero}),
                 std::invalid_argument);
    EXPECT_THROW(s.add_instance(plain, Transform(), Color(1.0f), 0, 0, 1, false, kRayAllVisibility, {Transform()}), std::invalid_argument);
    CameraDesc c = testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 8, 8);
    c.motion = {c.to_world, zero};
    EXPECT_THROW(Camera{c}, std::invalid_argument);
}

TEST(Motion, CameraFollowsItsSteps) {
    CameraDesc c = testing::camera_at(Vec3(0.0f, 0.0f, 10.0f), 16, 16);
    Transform open = c.to_world, close = c.to_world;
    close.m[0][3] = 4.0f;
    c.motion = {open, close};
    Camera cam(c);
    ASSERT_TRUE(cam.has_motion());
    for (float time : {0.0f, 0.25f, 1.0f}) {
        Ray r = cam.generate_ray(8.0f, 8.0f, {0.5f, 0.5f}, time);
        EXPECT_NEAR(r.o.x, 4.0f * time, 1e-5f);
        EXPECT_NEAR(r.d.z, -1.0f, 1e-5f);
        EXPECT_EQ(r.time, time);
    }
    c.motion = {open, open};
    EXPECT_FALSE(Camera(c).has_motion());
}

TEST(Motion, ShutterCurveDistributesTimesByItsShape) {
    // A ramp 0 -> 1 over the shutter: density 2t, so P(time < x) = x^2 and the mean is 2/3.
    ShutterCurve ramp({0.0f, 1.0f});
    EXPECT_FALSE(ramp.uniform());
    const int n = 10000;
    double mean = 0.0;
    for (int i = 0; i < n; ++i) {
        float t = ramp.sample((i + 0.5f) / n);
        EXPECT_NEAR(t * t, (i + 0.5f) / n, 1e-3f);  // the CDF at the sampled time is the fraction
        mean += t / n;
    }
    EXPECT_NEAR(mean, 2.0 / 3.0, 1e-3);
    // A trapezoid with a step: its inverse CDF at the fractions of each piece.
    ShutterCurve steps({1.0f, 1.0f, 3.0f, 3.0f});  // areas 1, 2, 3 over thirds (of 6)
    EXPECT_NEAR(steps.sample(1.0f / 6.0f), 1.0f / 3.0f, 2e-3f);
    EXPECT_NEAR(steps.sample(0.5f), 2.0f / 3.0f, 2e-3f);
    EXPECT_TRUE(ShutterCurve({2.0f, 2.0f, 2.0f}).uniform());
    EXPECT_EQ(ShutterCurve({2.0f, 2.0f}).sample(0.3f), 0.3f);
    EXPECT_THROW(ShutterCurve({0.0f, 0.0f}), std::invalid_argument);
    EXPECT_THROW(ShutterCurve({1.0f, -1.0f}), std::invalid_argument);
}

// A black box 1 wide (3 deep) moving from x = -1 to x = 1 over the shutter, under a white world,
// seen from above by a 16 x 4 orthographic camera spanning x in [-2, 2] (0.25 per pixel).
std::shared_ptr<Scene> crossing_box_scene() {
    auto scene = std::make_shared<Scene>();
    uint32_t black = scene->add_material(testing::diffuse(Color(0.0f)));
    Transform from, to;
    from.m[0][3] = -1.0f, to.m[0][3] = 1.0f;
    add_moving_cube(*scene, black, {from, to}, 3.0f);
    scene->set_world(Color(1.0f));
    CameraDesc c = testing::camera_at(Vec3(0.0f, 0.0f, 5.0f), 16, 4);
    c.orthographic = true;
    c.ortho_scale = 4.0f;
    scene->set_camera(c);
    scene->commit();
    return scene;
}

// The box crossing an orthographic view of a white world, from x = -1 to x = 1 over
// the shutter: a pixel is dark for the fraction of the shutter the box covers it (the mean over the
// pixel's footprint), which each column's mean must match.
TEST(Motion, RenderedPixelsSeeTheBoxForTheTimeItCoversThem) {
    auto scene = crossing_box_scene();
    RenderSettings st;
    st.samples = 64;
    st.max_bounces = 0;
    st.filter = PixelFilterKind::Box;
    st.filter_width = 1.0f;
    testing::expect_same_image_whatever_the_thread_count(scene, st, 2, "moving box");
    for (bool stratified : {true, false}) {
        st.sampling_pattern = stratified ? SamplingPattern::Stratified : SamplingPattern::Random;
        std::vector<float> img = testing::render(scene, st);
        // Covered at x while the box centre -1 + 2t is within 0.5 of it.
        auto covered = [](double x) { return std::max(0.0, std::min(x + 0.5, 1.0) - std::max(x - 0.5, -1.0)) / 2.0; };
        const double alpha = stats::sidak_significance(0.01, 16);
        for (int col = 0; col < 16; ++col) {
            stats::MeanEstimator m;
            for (int row = 0; row < 4; ++row) m.add(img[4 * (row * 16 + col) + 1]);
            double expected = 0.0;
            for (int k = 0; k < 1000; ++k) expected += (1.0 - covered(-2.0 + 0.25 * (col + (k + 0.5) / 1000.0))) / 1000.0;
            // Four pixels of 64 samples: the standard error from the samples' binomial spread.
            double se = std::sqrt(std::max(expected * (1.0 - expected), 1e-4) / (4.0 * st.samples));
            EXPECT_GE(stats::z_test(m.mean(), expected, se, 1e-6).p_value, alpha)
                << "column " << col << ": " << m.mean() << " vs " << expected << (stratified ? " stratified" : "");
        }
    }
}

// Every integrator renders a moving scene: finite pixels whose image mean is the fraction of the
// view the box leaves uncovered over the shutter (the path tracer's rays carry the sample's time; the
// others trace what they trace at their rays' times or the shutter's centre).
TEST(Motion, EveryIntegratorRendersAMovingScene) {
    auto scene = crossing_box_scene();
    for (const std::string& name : testing::all_integrators()) {
        RenderSettings st;
        testing::select_integrator(st, name);
        st.samples = 16;
        st.max_bounces = 1;
        std::vector<float> img = testing::render(scene, st);
        double mean = 0.0;
        for (size_t i = 0; i < img.size(); i += 4) {
            ASSERT_TRUE(std::isfinite(img[i]) && std::isfinite(img[i + 1]) && std::isfinite(img[i + 2])) << name;
            mean += img[i + 1] / (img.size() / 4);
        }
        // The box (1 wide) covers a quarter of the 4-wide view at any time it is inside it.
        EXPECT_NEAR(mean, 0.75, 0.05) << name;
    }
}

}  // namespace
}  // namespace smis
