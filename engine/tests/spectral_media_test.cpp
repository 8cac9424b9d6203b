// Spectral rendering with participating media: per-wavelength transmittance along rays and shadow
// rays, single scattering with the wavelengths' mixture of distance densities, and media inside glass.
#include <gtest/gtest.h>

#include "spectral_agreement.h"

using namespace smis;
using namespace smis::testing;


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
