// Subsurface scattering in the integrators built on their own prefix loops: the subsurface exit is a
// surface vertex like any other. RIS and unbiased ReSTIR (seed and Talbot MIS) converge to the path
// tracer on a scene with a random-walk sphere (a retro lobe beside the Subsurface one: x1 is the
// entry, the exit takes plain NEE) and a Christensen-Burley slab (the Subsurface lobe alone: the
// exit is x1 and takes the reservoir); per-pixel z-tests over independent renders, Sidak-corrected.
#include <gtest/gtest.h>

#include "subsurface_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

RenderSettings with(const std::string& integrator) {
    RenderSettings st;
    st.max_bounces = 4;
    st.ris_candidates = 8;
    st.restir_neighbors = 4;
    st.restir_radius_px = 6.0f;
    select_integrator(st, integrator);
    return st;
}

const std::shared_ptr<Scene>& scene() {
    static auto s = subsurface_scene(Color(0.9f, 0.6f, 0.4f), Color(0.3f, 0.15f, 0.08f), 20, 20);
    return s;
}

const PixelStats& reference() {
    static PixelStats ref = across_renders(scene(), with("PATH"), 16, 64, 1000, true);
    return ref;
}

void expect_converges(const std::string& name, int renders, uint32_t spp, uint32_t seed0) {
    const PixelStats p = across_renders(scene(), with(name), renders, spp, seed0, true);
    const PixelStats& ref = reference();
    double z = 0.0;
    const double acc = accepted_fraction(p, ref), p_mean = smallest_channel_p_value(p, ref, &z);
    std::printf("%-20s %.4f of pixel channels agree with PATH; image means %.5f %.5f %.5f (PATH %.5f %.5f %.5f), "
                "worst channel z %+.2f\n",
                name.c_str(), acc, p.channel_image[0].mean(), p.channel_image[1].mean(), p.channel_image[2].mean(),
                ref.channel_image[0].mean(), ref.channel_image[1].mean(), ref.channel_image[2].mean(), z);
    EXPECT_GT(ref.image.mean(), 0.02);  // lit: the test can fail
    EXPECT_GE(acc, 0.99) << name;
    EXPECT_GE(p_mean, stats::sidak_significance(0.001, 3)) << name;
}

}  // namespace

TEST(SubsurfaceIntegrators, RisConvergesToThePathTracer) { expect_converges("PATH+RIS", 16, 64, 2000); }

TEST(SubsurfaceIntegrators, UnbiasedRestirConvergesToThePathTracer) {
    expect_converges("PATH+RESTIR_SEED", 16, 64, 3000);
    expect_converges("PATH+RESTIR_TALBOT", 16, 64, 4000);
}

// Path-space filtering: x1's BSDF samples that pick its Subsurface lobe, and prefixes ending on a
// Subsurface lobe alone, keep PATH's walk per pixel; z1's subsurface is its diffuse fallback (Cycles'
// rule after x1's diffuse bounces; this scene's x1 have no glossy lobe), so PSF_PATH and the
// unbiased SMIS weighting converge to PATH.
TEST(SubsurfaceIntegrators, PathSpaceFilteringConvergesToThePathTracer) {
    expect_converges("PSF_PATH", 16, 64, 5000);
    expect_converges("PSF_SMIS_UNBIASED", 16, 64, 6000);
}

// ReSTIR where every x1 is the exit of a Subsurface lobe alone (a Dirac entry): x1 takes the
// reservoir, so x1's BSDF sample must weigh the emission it finds against the resampled light
// density (light_pdf_scale M, as at any other x1), or the two strategies' MIS weights at x1 do not
// sum to 1. A slab filling the frame under a large area light close above it (light and BSDF
// densities of one order), direct light only (max_bounces 1), 8 candidates: the image mean
// against the path tracer's, z-test over independent renders.
TEST(SubsurfaceIntegrators, RestirAtSubsurfaceExitsConvergesToThePathTracer) {
    static auto slab = [] {
        auto s = std::make_shared<Scene>();
        add_box(*s, {-2.0f, -2.0f, -0.3f}, {2.0f, 2.0f, 0.0f},
                s->add_material(subsurface_material(Color(0.8f), Color(0.2f), 0.0f)));
        s->add_light(area_light(2.5f, 40.0f, {0.0f, 0.0f, 0.8f}).hidden_from_camera());
        s->set_camera(camera_at({0.0f, 0.0f, 2.0f}, 12, 12));
        s->commit();
        return s;
    }();
    auto settings = [](const std::string& name) {
        RenderSettings st = with(name);
        st.max_bounces = 1;
        return st;
    };
    const PixelStats ref = across_renders(slab, settings("PATH"), 16, 32, 7000);
    for (const char* name : {"PATH+RESTIR_SEED", "PATH+RESTIR_TALBOT", "PATH+RIS"}) {
        const PixelStats p = across_renders(slab, settings(name), 16, 32, 8000);
        const stats::ZTest t = stats::z_test_difference(p.image, ref.image);
        std::printf("%-18s image mean %.5f vs PATH %.5f: z %+.2f\n", name, p.image.mean(), ref.image.mean(), t.z);
        EXPECT_GT(ref.image.mean(), 0.02);  // lit: the test can fail
        EXPECT_GE(t.p_value, 1e-3) << name;
    }
}
