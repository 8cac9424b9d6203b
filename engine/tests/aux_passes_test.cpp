// The auxiliary passes a camera path records at its first hit (FirstHitPasses, path_loop.h) are
// those of the passes' own camera ray, bit for bit, and the path leaves them to that ray exactly
// where the two rays' first hits differ (a medium boundary the path passes) or the path ends
// before shading its hit (a holdout object's hole).
#include <gtest/gtest.h>

#include <cstring>

#include "integrators/aux_passes.h"
#include "integrators/path_tracing.h"
#include "integrators/tiles.h"
#include "integrators/volume.h"
#include "test_scenes.h"

namespace smis::testing {
namespace {

// A closed room with a mirror box, a smooth glass box (the albedo's Dirac bounces) and a holdout box.
std::shared_ptr<Scene> room_with_mirror_glass_and_holdout(int w, int h) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    uint32_t red = s->add_material(diffuse(Color(0.7f, 0.15f, 0.1f)));
    add_room(*s, white, white, red);
    add_box(*s, {-0.8f, 0.2f, 0.0f}, {-0.2f, 0.3f, 1.2f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    add_box(*s, {0.1f, -0.6f, 0.0f}, {0.7f, 0.0f, 0.6f}, s->add_material(smooth_glass(1.5f)));
    const float v[] = {0.3f, 0.5f, 0.8f, 0.8f, 0.5f, 0.8f, 0.8f, 0.5f, 1.4f, 0.3f, 0.5f, 1.4f};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    s->add_instance(s->add_mesh(v, 4, t, 2, nullptr, nullptr, {white}), Transform(), Color(1.0f), 0.0f, 0.0f, 1.0f,
                    /*holdout=*/true);
    add_square_light(*s, 0.6f, 60.0f, {0.0f, 0.0f, 1.98f});
    s->set_camera(camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f));
    s->commit();
    return s;
}

// A fog box the camera stands in, with a floor, a mirror and a glass box holding a medium of its
// own: camera rays that meet a surface in the fog record the passes, those that leave the box
// through its boundary do not.
std::shared_ptr<Scene> camera_in_fog(int w, int h) {
    auto s = std::make_shared<Scene>();
    add_box(*s, {-1.5f, -1.5f, -0.2f}, {1.5f, 1.5f, 2.5f}, add_medium_boundary(*s, medium_of(Color(0.05f), Color(0.3f), 0.0f)));
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_box(*s, {-1.1f, 0.8f, 0.0f}, {0.1f, 0.9f, 1.3f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    Material glass = smooth_glass(1.5f);
    glass.medium = s->add_medium(medium_of(Color(0.2f), Color(0.1f), 0.0f));
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.8f, 0.1f, 0.7f}, s->add_material(glass));
    s->add_light(point_light(15.0f, 0.15f, {-0.7f, -0.6f, 0.9f}));
    s->set_camera(camera_along_y({0.0f, -1.3f, 0.9f}, w, h, 18.0f));
    s->commit();
    return s;
}

struct PassRenders {
    std::vector<float> recorded[3], traced[3];  // Depth, Normal, Albedo
    int samples = 0, ready = 0, mismatched = 0;  // mismatched: ready where the rays differ, or not where they agree
};

// Every pixel sample's path as the path tracer traces it, recording its passes, into one film; the
// same samples with nothing recorded (add_aux_sample traces their own camera ray) into another.
PassRenders render_passes(const Scene& scene, bool shading, uint32_t spp) {
    RenderSettings settings;
    settings.aux_passes = true;
    settings.aux_shading = shading;
    settings.seed = 11;
    const int w = scene.camera().window_width(), h = scene.camera().window_height();
    Film recorded(w, h), traced(w, h);
    recorded.enable_aux(!shading);
    traced.enable_aux(!shading);
    const PixelFilter filter;
    RenderCounters counters;
    const std::atomic<bool> cancel{false};
    RenderContext rec_ctx{scene, settings, recorded, filter, counters, cancel, std::chrono::steady_clock::time_point::max()};
    RenderContext own_ctx{scene, settings, traced, filter, counters, cancel, std::chrono::steady_clock::time_point::max()};
    LocalCounters local;
    PassRenders out;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (uint32_t s = 0; s < spp; ++s) {
                const PixelCamera camera(rec_ctx, x, y);
                Sampler sampler;
                const Ray ray = camera.ray(s, &sampler);
                FirstHitPasses passes(rec_ctx, x, y, s);
                {
                    RecordPasses recording(local, &passes);
                    PathState st = camera_path_state(ray.o);
                    st.first_vertex_ahead = true;
                    st.medium = scene.camera_medium();
                    trace_path(scene, settings, ray, st, sampler.rng(), local, &sampler);
                }
                EXPECT_EQ(local.passes, nullptr);
                add_aux_sample(rec_ctx, x, y, s, passes);
                add_aux_sample(own_ctx, x, y, s, FirstHitPasses());
                // Where the path's first hit is the passes' own ray's and gets shaded.
                SurfaceHit hit;
                bool agree = true;
                if (scene.has_media()) {
                    RayMedia media;
                    const bool found = intersect_through(scene, ray, scene.camera_medium(), &hit, &media);
                    agree = !media.crossed && !(found && hit.holdout && shading);
                } else {
                    agree = !(scene.intersect(ray, &hit) && hit.holdout && shading);
                }
                ++out.samples;
                out.ready += passes.ready;
                out.mismatched += passes.ready != agree;
            }
    const AuxPass kinds[3] = {AuxPass::Depth, AuxPass::Normal, AuxPass::Albedo};
    for (int i = 0; i < (shading ? 3 : 1); ++i) {
        out.recorded[i] = recorded.resolve_aux(kinds[i]);
        out.traced[i] = traced.resolve_aux(kinds[i]);
    }
    return out;
}

void expect_bit_identical(const std::vector<float>& a, const std::vector<float>& b, const char* what) {
    ASSERT_EQ(a.size(), b.size()) << what;
    size_t differ = 0;
    for (size_t i = 0; i < a.size(); ++i) differ += std::memcmp(&a[i], &b[i], sizeof(float)) != 0;
    EXPECT_EQ(differ, 0u) << what << ": values differing from the passes' own ray's";
}

void check(const Scene& scene, bool shading, const char* what) {
    const PassRenders r = render_passes(scene, shading, 3);
    EXPECT_EQ(r.mismatched, 0) << what;
    EXPECT_GT(r.ready, r.samples / 4) << what;      // the paths record most passes...
    if (shading) {
        EXPECT_LT(r.ready, r.samples) << what;  // ...and leave some to the passes' own ray
    }
    const char* names[3] = {"depth", "normal", "albedo"};
    for (int i = 0; i < (shading ? 3 : 1); ++i)
        expect_bit_identical(r.recorded[i], r.traced[i], (std::string(what) + " " + names[i]).c_str());
}

TEST(AuxPasses, PathRecordsTheFirstHitPassesOfTheirOwnRay) {
    auto scene = room_with_mirror_glass_and_holdout(24, 18);
    check(*scene, true, "room, every pass");
    check(*scene, false, "room, depth alone");
}

TEST(AuxPasses, PathLeavesThePassesToTheirOwnRayBeyondMediumBoundaries) {
    auto scene = camera_in_fog(24, 18);
    check(*scene, true, "fog, every pass");
    check(*scene, false, "fog, depth alone");
}

}  // namespace
}  // namespace smis::testing
