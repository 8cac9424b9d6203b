// Spectral rendering with participating media: per-wavelength transmittance along rays and shadow
// rays, single scattering with the wavelengths' mixture of distance densities, and media inside glass.
#include <gtest/gtest.h>

#include "spectral_agreement.h"

using namespace smis;
using namespace smis::testing;

namespace {

Medium medium_of(const Color& sigma_a, const Color& sigma_s, float g) {
    Medium m;
    m.sigma_a = sigma_a;
    m.sigma_s = sigma_s;
    m.phase = HenyeyGreenstein(g);
    return m;
}

// Fog (an index-matched box) around a white floor, a mirror and a glass block that holds a medium of
// its own, lit by a rectangle above and a point light inside the fog; the camera looks in from outside.
// `spectral_light`: the point light has a D65 spectrum (spectral content).
std::shared_ptr<Scene> foggy_mirror_and_glass(const Medium& fog, const Medium& inside_glass, bool spectral_light = false) {
    auto s = std::make_shared<Scene>();
    Material boundary;
    boundary.name = "fog";
    boundary.pass_through = true;
    boundary.medium = s->add_medium(fog);
    add_box(*s, {-1.5f, -1.5f, -0.2f}, {1.5f, 1.5f, 2.5f}, s->add_material(boundary));
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_box(*s, {-1.1f, 0.8f, 0.0f}, {0.1f, 0.9f, 1.3f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    Material glass = smooth_glass(1.5f);
    glass.medium = s->add_medium(inside_glass);
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.8f, 0.1f, 0.7f}, s->add_material(glass));
    LightDesc area;
    area.type = "AREA";
    area.size = 1.5f;
    area.power = 60.0f;
    area.visible_to_camera = false;  // its randomly covered edge pixels would dominate the noise
    area.to_world.m[2][3] = 2.2f;
    s->add_light(area);
    LightDesc point;
    point.type = "POINT";
    point.power = 15.0f;
    point.radius = 0.15f;
    if (spectral_light) point.spectrum = "D65";
    point.to_world.m[0][3] = -0.7f, point.to_world.m[1][3] = -0.6f, point.to_world.m[2][3] = 0.9f;
    s->add_light(point);
    s->set_camera(camera_along_y({0.0f, -3.2f, 0.6f}, 16, 16, 30.0f));
    s->commit();
    return s;
}

}  // namespace

// Grey media, grey surfaces and white lights have flat spectra: every spectral mode must then
// converge to the RGB path tracer, pixel by pixel (per-pixel z-tests over independent renders,
// Sidak-corrected) and in the image mean per channel.
TEST(SpectralMedia, GreyFogMirrorAndGlassConvergeToRgb) {
    auto scene = foggy_mirror_and_glass(medium_of(Color(0.1f), Color(0.5f), 0.3f), medium_of(Color(0.8f), Color(0.4f), 0.0f));
    expect_agreement(scene, {"SMIS", "HERO"}, "RGB", 10, 64);
}

// Coloured media: the four-wavelength estimators (each wavelength's own transmittance, the mixture
// of their distance densities for single scattering) must agree with single-wavelength paths
// (UNIFORM: one wavelength per path, its distances drawn from that wavelength alone).
TEST(SpectralMedia, ColouredFogAgreesWithSingleWavelengthPaths) {
    auto scene = foggy_mirror_and_glass(medium_of(Color(0.05f, 0.5f, 1.9f), Color(0.3f, 0.3f, 0.1f), 0.5f),
                                        medium_of(Color(1.5f, 0.3f, 0.1f), Color(0.1f), 0.0f));
    expect_agreement(scene, {"SMIS", "HERO"}, "UNIFORM", 10, 128);
}

// Explicit spectral modes render scenes with media (refused before), AUTO picks SMIS for a scene with
// spectral content and media, and photon planes, RGB estimators, refuse an explicit spectral mode.
TEST(SpectralMedia, SpectralModesAcceptMediaAndPlanesStayRgb) {
    auto scene =
        foggy_mirror_and_glass(medium_of(Color(0.1f), Color(0.5f), 0.0f), medium_of(Color(0.5f), Color(0.0f), 0.0f), true);
    RenderSettings st = spectral_settings("SMIS");
    st.samples = 2;
    auto img = render(scene, st);
    for (float v : img) ASSERT_TRUE(std::isfinite(v));
    EXPECT_GT(channel_mean(img, 1).mean(), 0.02);
    EXPECT_EQ(resolve_spectral_mode(RenderSettings{}, *scene), SpectralSetting::Smis);
    st.volume_estimator = VolumeEstimator::PlanesSmisExact;
    EXPECT_THROW(render(scene, st), std::invalid_argument);
    st.spectral = SpectralSetting::Auto;
    EXPECT_EQ(resolve_spectral_mode(st, *scene), SpectralSetting::Rgb);
}
