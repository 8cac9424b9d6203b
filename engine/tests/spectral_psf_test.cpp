// Spectral rendering with path-space filtering (psf_spectral.h): one wavelength set per iteration,
// the prefix throughput and the suffix radiance per wavelength. The unbiased weightings converge to
// the spectral path tracer of the same mode (per-pixel z-tests over independent renders,
// Šidák-corrected, and the image means per channel) on a scene with a spectrally peaked (F10) light,
// a D65 lamp in fog, measured gold, a coloured wall, a mirror and a dispersive glass block holding a
// coloured medium (its reflections are prefixes with wavelength-dependent densities, its refractions
// keep the conditioning wavelength alone); every spectral mode renders with every weighting with no
// non-finite pixel.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "spectral_agreement.h"

using namespace smis;
using namespace smis::testing;

namespace {

// The closed room of this file's scenes: white, with an orange left wall.
std::shared_ptr<Scene> white_room_orange_left() {
    auto s = std::make_shared<Scene>();
    const uint32_t white = s->add_material(diffuse(Color(0.7f)));
    const uint32_t orange = s->add_material(diffuse(Color(0.75f, 0.3f, 0.08f)));
    add_room(*s, white, white, orange);
    return s;
}

// psf_test's room (media_integrators_test's fog room) made spectral: an F10 square light under the
// ceiling, a coloured left wall, measured gold, a mirror wall, a dispersive (N-SF11) glass block
// holding a coloured medium, fog (a pass-through box) in the lower part with a D65 lamp in it.
// Closed, so that the indirect light path-space filtering reuses is a large part of the image.
std::shared_ptr<Scene> spectral_fog_scene(int w, int h) {
    auto s = white_room_orange_left();
    add_box(*s, {0.98f, -1.0f, 0.0f}, {1.0f, 1.0f, 2.0f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    Material gold = glossy(Color(1.0f), 0.3f);
    gold.spectral.metal = "Au";
    add_sphere(*s, 0.25f, 12, 24, s->add_material(gold), true, {-0.5f, 0.3f, 0.25f});
    Medium tint;
    tint.sigma_a = Color(0.6f, 0.2f, 0.05f);
    Material glass = smooth_glass(1.5f);
    glass.spectral.dispersion = "N-SF11";
    glass.medium = s->add_medium(tint);
    add_box(*s, {0.1f, -0.4f, 0.0f}, {0.6f, 0.1f, 0.6f}, s->add_material(glass));
    Medium fog;
    fog.sigma_a = Color(0.05f, 0.08f, 0.12f);
    fog.sigma_s = Color(0.5f, 0.4f, 0.25f);
    Material boundary;
    boundary.name = "fog";
    boundary.pass_through = true;
    boundary.medium = s->add_medium(fog);
    add_box(*s, {-0.95f, -0.95f, 0.02f}, {0.95f, 0.95f, 0.9f}, s->add_material(boundary));
    s->add_light(area_light(0.6f, 60.0f, {0.0f, 0.0f, 1.98f}).spectrum("F10").hidden_from_camera());
    s->add_light(point_light(5.0f, 0.05f, {0.5f, 0.4f, 0.6f}).spectrum("D65").hidden_from_camera());
    s->set_camera(camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f));
    s->commit();
    return s;
}

const std::shared_ptr<Scene>& scene() {
    static auto s = spectral_fog_scene(14, 14);
    return s;
}

RenderSettings settings(const char* integrator, const char* mode) {
    RenderSettings st;
    st.integrator = setting_value<IntegratorKind>(integrator);
    st.spectral = setting_value<SpectralSetting>(mode);
    st.max_bounces = 4;
    return st;
}

// Per-pixel and image-mean agreement of `integrator` with spectral PATH in `mode`.
void expect_agreement(const char* integrator, const char* mode, int renders, uint32_t spp, uint32_t path_spp) {
    PixelStats ref = across_renders(scene(), settings("PATH", mode), renders, path_spp, 7000, true);
    EXPECT_GT(ref.image.mean(), 0.02);  // lit: the test can fail
    const std::string label = std::string(integrator) + " " + mode;
    smis::testing::expect_agreement(across_renders(scene(), settings(integrator, mode), renders, spp, 8000, true), ref,
                                    label.c_str(), "PATH");
}

}  // namespace

TEST(SpectralPsf, UnbiasedConvergesToSpectralPathSmis) { expect_agreement("PSF_SMIS_UNBIASED", "SMIS", 16, 64, 128); }
TEST(SpectralPsf, PathConvergesToSpectralPathHero) { expect_agreement("PSF_PATH", "HERO", 16, 64, 128); }

// Every spectral mode with every weighting renders, with no non-finite pixel.
TEST(SpectralPsf, EveryModeAndWeightingRendersFinite) {
    auto s = spectral_fog_scene(8, 8);
    for (const char* integrator : {"PSF_PATH", "PSF_KELLER", "PSF_SMIS", "PSF_SMIS_UNBIASED"})
        for (const char* mode : {"UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT", "BRUTE_FORCE"}) {
            RenderSettings st = settings(integrator, mode);
            st.samples = 2;
            st.psf_extra_paths = 2;
            auto img = render(s, st);
            for (float v : img) ASSERT_TRUE(std::isfinite(v)) << integrator << " " << mode;
            // One wavelength per path takes the observer's negative lobes: lit means positive only with several.
            if (std::string(mode) != "UNIFORM" && std::string(mode) != "SPECTRAL_IS") {
                EXPECT_GT(channel_mean(img, 1).mean(), 0.0) << integrator << " " << mode;
            }
        }
}

// Clamping (Cycles' Clamp Indirect) limits each estimate a path adds by its whole throughput times
// the radiance, as RGB. PSF_PATH shares nothing, so clamped or not it is the spectral path tracer
// pixel for pixel in expectation: its suffix after z1 (traced at unit throughput) must be clamped
// under the whole path's throughput, as psf_rgb.cpp's suffix is.
TEST(SpectralPsf, PathClampsItsSuffixAsTheSpectralPathTracer) {
    auto s = small_room(12, 12);
    RenderSettings st = settings("PATH", "HERO");
    st.clamp_indirect = 0.02f;
    PixelStats ref = across_renders(s, st, 16, 64, 7000, true);
    RenderSettings unclamped = st;
    unclamped.clamp_indirect = 0.0f;
    double z = 0.0;  // the clamp changes the image: the test can fail
    EXPECT_LT(smallest_channel_p_value(across_renders(s, unclamped, 16, 64, 7100, true), ref, &z), 1e-6) << z;
    st.integrator = IntegratorKind::PsfPath;
    smis::testing::expect_agreement(across_renders(s, st, 16, 64, 8000, true), ref, "PSF_PATH clamped", "PATH");
}

// A room seen through glass: a dispersive (N-SF11) pane beside a plain one, between the camera and
// the lit walls, so that most camera paths pass glass before x1. The dispersive refractions keep the
// conditioning wavelength alone (r = 1 there, 0 elsewhere) and its reflections weight each
// wavelength by F(l_j) / F(l_c) (a prefix no other shares), while the plain pane's prefixes, with as
// many Dirac bounces, reach the same walls with r = 1: only psf_spectral.cpp's spectral_class keeps
// them apart.
namespace {
std::shared_ptr<Scene> behind_dispersive_glass(int w, int h) {
    auto s = white_room_orange_left();
    add_box(*s, {0.2f, 0.2f, 0.0f}, {0.7f, 0.7f, 0.8f}, s->add_material(diffuse(Color(0.2f, 0.5f, 0.7f))));
    Material glass = smooth_glass(1.5f);
    const uint32_t plain = s->add_material(glass);
    glass.spectral.dispersion = "N-SF11";
    const uint32_t dispersive = s->add_material(glass);
    add_box(*s, {-0.9f, -0.9f, 0.0f}, {0.0f, -0.85f, 1.5f}, dispersive);
    add_box(*s, {0.0f, -0.9f, 0.0f}, {0.9f, -0.85f, 1.5f}, plain);
    s->add_light(area_light(0.6f, 60.0f, {0.0f, 0.0f, 1.98f}).spectrum("F10").hidden_from_camera());
    s->set_camera(camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f));
    s->commit();
    return s;
}
}  // namespace

// The unbiased weighting shares suffixes only within a spectral class: through the glass it still
// converges to the spectral path tracer of the same mode.
TEST(SpectralPsf, UnbiasedBehindDispersiveGlassConvergesToSpectralPath) {
    auto s = behind_dispersive_glass(12, 12);
    for (const char* mode : {"HERO", "SMIS"}) {
        PixelStats ref = across_renders(s, settings("PATH", mode), 16, 64, 7000, true);
        EXPECT_GT(ref.image.mean(), 0.02);  // lit: the test can fail
        const std::string label = std::string("PSF_SMIS_UNBIASED ") + mode;
        smis::testing::expect_agreement(across_renders(s, settings("PSF_SMIS_UNBIASED", mode), 16, 32, 8000, true),
                                        ref, label.c_str(), "PATH");
    }
}
