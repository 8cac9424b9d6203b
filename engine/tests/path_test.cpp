// End-to-end checks of the path tracer on analytic scenes.
#include <gtest/gtest.h>

#include <array>

#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// Inside a closed sphere whose wall has albedo rho and emits Le everywhere, the radiance seen along
// any ray after k bounces is Le * sum_{i <= k} rho^i: a furnace that tests emission, NEE, MIS and
// the bounce limit at once. Flat shading: interpolated normals make a Lambertian wall lose a little
// energy (about 4e-4 here), which is a property of shading normals, not of the estimator.
std::shared_ptr<Scene> furnace_scene(float rho, float le) {
    auto s = std::make_shared<Scene>();
    uint32_t mat = s->add_material(diffuse(Color(rho), Color(le)));
    add_sphere(*s, 1.0f, 24, 48, mat, /*smooth=*/false);
    s->set_camera(camera_at({0.1f, 0.2f, 0.05f}, 24, 24));
    s->commit();
    return s;
}

double expected_furnace(float rho, float le, int max_bounces) {
    double sum = 0, p = 1;
    for (int i = 0; i <= max_bounces + 1; ++i, p *= rho) sum += le * p;
    return sum;
}

}  // namespace

TEST(PathTracer, FurnaceMatchesGeometricSeriesAtEveryBounceLimit) {
    const float rho = 0.5f, le = 1.0f;
    auto scene = furnace_scene(rho, le);
    for (int bounces : {0, 1, 3, 64}) {
        for (MisHeuristic mis : {MisHeuristic::Balance, MisHeuristic::Power}) {
            RenderSettings st;
            st.samples = 64;
            st.max_bounces = bounces;
            st.mis = mis;
            auto img = render(scene, st);
            auto m = channel_mean(img, 1);
            double expect = expected_furnace(rho, le, bounces);
            // A tessellated sphere is an exact enclosure, so only Monte Carlo noise separates them.
            EXPECT_NEAR(m.mean(), expect, 4.0 * m.std_error() + 1e-4) << "bounces " << bounces;
        }
    }
}

TEST(PathTracer, DiffuseSphereUnderUniformSkyReflectsItsAlbedo) {
    // A convex white-ish sphere under a uniform sky: every shading point sees the sky over its whole
    // hemisphere, so the reflected radiance is albedo x sky radiance, exactly, after one bounce.
    auto s = std::make_shared<Scene>();
    uint32_t mat = s->add_material(diffuse(Color(0.7f, 0.5f, 0.3f)));
    add_sphere(*s, 1.0f, 32, 64, mat);
    s->set_world(Color(2.0f));
    // Camera close enough that every pixel sees the sphere.
    CameraDesc c = camera_at({0, 0, 3.0f}, 16, 16);
    c.lens = 200.0f;
    s->set_camera(c);
    s->commit();
    RenderSettings st;
    st.samples = 128;
    st.max_bounces = 4;
    auto img = render(s, st);
    for (int ch = 0; ch < 3; ++ch) {
        auto m = channel_mean(img, ch);
        double expect = 2.0 * std::array<double, 3>{0.7, 0.5, 0.3}[ch];
        EXPECT_NEAR(m.mean(), expect, 4.0 * m.std_error() + 1e-4) << "channel " << ch;
    }
}

TEST(PathTracer, SameSeedSameImageWhateverTheThreadCount) {
    auto scene = furnace_scene(0.6f, 1.0f);
    RenderSettings st;
    st.samples = 8;
    st.seed = 7;
    expect_same_image_whatever_the_thread_count(scene, st, 2, "PATH");
}

TEST(PathTracer, TimeLimitAndCancelStopTheSession) {
    auto scene = furnace_scene(0.9f, 1.0f);
    RenderSettings st;
    st.samples = 1000000;
    st.max_bounces = 64;
    RenderSession session(scene, st);
    session.start();
    EXPECT_FALSE(session.wait(0.2));
    session.cancel();
    EXPECT_TRUE(session.wait(5.0));  // generous bound: the assertion is that it stops, not how fast
    RenderProgress p = session.progress();
    EXPECT_TRUE(p.cancelled);
    EXPECT_LT(p.samples_done, st.samples);
}

TEST(PathTracer, ATimeLimitShorterThanOneSampleStillGivesThatSample) {
    // The first pass ignores the time limit: a limit shorter than a sample (or an iteration of a
    // multi-stage integrator) must not leave the film empty. (Checked red: with the limit applied to
    // the first pass, no sample is done and the image is black.)
    auto scene = furnace_scene(0.6f, 1.0f);
    RenderSettings st;
    st.samples = 1000000;
    st.max_bounces = 4;
    st.time_limit = 1e-9;
    RenderSession session(scene, st);
    session.start();
    EXPECT_TRUE(session.wait(10.0));
    RenderProgress p = session.progress();
    EXPECT_FALSE(p.cancelled);
    EXPECT_GE(p.samples_done, 1u);
    EXPECT_LT(p.samples_done, st.samples);
    std::vector<float> img = session.pixels();
    double sum = 0.0;
    for (size_t i = 0; i < img.size(); i += 4) sum += img[i];
    EXPECT_GT(sum, 0.0);
}
