// Spectral rendering (paper §5): colorimetry, Jakob-Hanika upsampling, wavelength sampling and the
// spectral path tracer's estimators.
#include <gtest/gtest.h>

#include "spectral/rgb_to_spectrum.h"
#include "spectral/spectra.h"
#include "spectral/wavelength_sampling.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::spectral;
using namespace smis::testing;

namespace {

// The importance density of the spectral path tracer, observer response times a light's SPD (plus a
// little uniform density): spiky for F10 (the paper's Fig. 8), smooth for D65.
WavelengthPdf observer_times(EmitterKind kind) {
    EmitterSpectrum light(kind, Color(1.0f), 0.0f);
    std::vector<double> bins(WavelengthPdf::kBins);
    for (int b = 0; b < WavelengthPdf::kBins; ++b) {
        float l = kLambdaMin + b + 0.5f;
        Vec3 c = cie_xyz(l);
        bins[b] = light(l) * (c.x + c.y + c.z) + 0.01;
    }
    return WavelengthPdf(bins);
}

const SpectralMode kAllModes[] = {SpectralMode::Uniform, SpectralMode::SpectralIs, SpectralMode::Hero,
                                  SpectralMode::Smis, SpectralMode::SmisIndependent, SpectralMode::BruteForce};

}  // namespace

TEST(Spectral, ObserverTablesIntegrateToTheCieConstants) {
    double y = 0.0;
    for (int k = 0; k < kTableSamples; ++k) y += cie_y(kLambdaMin + k);
    EXPECT_NEAR(y, kCieYIntegral, 1e-3);
    // D65 at unit luminance is the white of the RGB space.
    EmitterSpectrum d65(EmitterKind::D65, Color(1.0f), 0.0f);
    Color rgb(0.0f);
    for (int k = 0; k < kTableSamples; ++k) rgb += rgb_response(kLambdaMin + k) * d65(kLambdaMin + k);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgb[c], 1.0, 2e-3) << c;
}

// Integral of ybar by the estimators' wavelength sets: sum_i ybar(l_i) W_i with r_j = 1, 10^6 sets.
// Within 1e-3 of the table's integral with the smooth (D65) importance density for every mode; with
// the spiky F10 density (whose ybar / p has a large variance) a z-test.
TEST(Spectral, YbarIntegralByImportanceSampledWavelengths) {
    for (EmitterKind light : {EmitterKind::D65, EmitterKind::F10}) {
        for (SpectralMode mode : kAllModes) {
            WavelengthSampler sampler(mode, 4, observer_times(light));
            const int sets = mode == SpectralMode::BruteForce ? 4000 : 1000000;
            stats::MeanEstimator est;
            Rng rng(7, 0);
            WavelengthSet ws;
            for (int s = 0; s < sets; ++s) {
                float u = rng.next_float(), v = rng.next_float();
                sampler.sample(u, v, rng, &ws);
                double mix = 0.0;
                for (int j = 0; j < ws.n; ++j) mix += ws.a[j];
                double sum = 0.0;
                for (int i = 0; i < ws.n; ++i) sum += cie_y(ws.lambda[i]) / (ws.q[i] * mix);
                est.add(sum / kCieYIntegral);
            }
            SCOPED_TRACE(std::string(spectral_mode_name(mode)) + (light == EmitterKind::D65 ? " D65" : " F10"));
            if (light == EmitterKind::D65) {
                EXPECT_LT(std::fabs(est.mean() - 1.0), 1e-3) << "+- " << est.std_error();
            }
            EXPECT_GT(stats::z_test_mean(est, 1.0).p_value, 1e-4);
        }
    }
}

// Jakob-Hanika round trip RGB -> reflectance spectrum -> RGB under D65 over a dense grid of the sRGB
// gamut (every linear colour in [0, 1]^3, 33 steps per axis, including its faces and edges).
TEST(Spectral, JakobHanikaRoundTripUnderD65) {
    const int steps = 33;
    double worst = 0.0, worst_table = 0.0;
    Color worst_at;
    for (int i = 0; i < steps; ++i)
        for (int j = 0; j < steps; ++j)
            for (int k = 0; k < steps; ++k) {
                Color c(i / float(steps - 1), j / float(steps - 1), k / float(steps - 1));
                Color back = sigmoid_reflectance_rgb(rgb_to_sigmoid(c));
                Color table = sigmoid_reflectance_rgb(rgb_to_sigmoid_table(c));
                double e = max_component(vmax(back - c, c - back));
                if (e > worst) worst = e, worst_at = c;
                worst_table = std::max(worst_table, double(max_component(vmax(table - c, c - table))));
            }
    RecordProperty("max_error", std::to_string(worst));
    std::printf("JH round trip: max |error| %.3g (table only %.3g), worst at (%g %g %g)\n", worst, worst_table,
                worst_at.x, worst_at.y, worst_at.z);
    EXPECT_LT(worst, 1e-3);
}

// Unbounded colours and RGB emitters come back as the same colour (per unit luminance).
TEST(Spectral, RgbEmittersKeepTheirColour) {
    for (Color c : {Color(1.0f), Color(4.0f, 1.0f, 0.2f), Color(0.1f, 0.3f, 0.9f)}) {
        EmitterSpectrum e(EmitterKind::Rgb, c, 0.0f);
        Color rgb(0.0f);
        for (int k = 0; k < kTableSamples; ++k) rgb += rgb_response(kLambdaMin + k) * e(kLambdaMin + k);
        Color expect = c / luminance(c);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(rgb[ch], expect[ch], 2e-3 * max_component(expect)) << ch;
    }
}

// A strand's emission, upsampled per hit (EmitterSpectrum::upsampled: the table's coefficients and the
// luminance the colour implies) comes back as its colour per unit luminance too, within the table's
// round trip, and its luminance is 1 as the fitted emitters'. (The saturated orange is the emissive
// hair scene's tip colour, scenes/hair.py.)
TEST(Spectral, UpsampledEmittersKeepTheirColour) {
    for (Color c : {Color(1.0f), Color(4.0f, 1.0f, 0.2f), Color(0.1f, 0.3f, 0.9f), Color(1.0f, 0.6f, 0.1f),
                    Color(0.3f, 0.05f, 0.02f)}) {
        EmitterSpectrum e = EmitterSpectrum::upsampled(c);
        Color rgb(0.0f);
        for (int k = 0; k < kTableSamples; ++k) rgb += rgb_response(kLambdaMin + k) * e(kLambdaMin + k);
        Color expect = c / luminance(c);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(rgb[ch], expect[ch], 0.03 * max_component(expect)) << ch;
        EXPECT_NEAR(spectrum_luminance(e), 1.0, 0.01);
        std::printf("upsampled (%g %g %g): rgb/expected %.4f %.4f %.4f, luminance %.4f\n", c.x, c.y, c.z,
                    rgb.x / expect.x, rgb.y / expect.y, rgb.z / expect.z, spectrum_luminance(e));
    }
}

TEST(Spectral, MeasuredAndDispersiveMaterials) {
    // Gold reflects red more than blue at normal incidence; every metal is a good mirror at grazing.
    const tables::MetalTable* au = find_metal("Au");
    ASSERT_NE(au, nullptr);
    EXPECT_GT(fresnel_conductor(1.0f, metal_ior(*au, 650.0f)), 0.9f);
    EXPECT_LT(fresnel_conductor(1.0f, metal_ior(*au, 450.0f)), 0.45f);
    EXPECT_EQ(find_metal("Unobtainium"), nullptr);
    // N-BK7 reproduces its catalogue n_d; an Abbe glass has its n_d and V_d.
    Dispersion bk7;
    ASSERT_TRUE(Dispersion::sellmeier("N-BK7", &bk7));
    EXPECT_NEAR(bk7.eta(587.56f), 1.5168f, 1e-4);
    Dispersion abbe = Dispersion::abbe(1.6f, 30.0f);
    EXPECT_NEAR(abbe.eta(587.56f), 1.6f, 1e-5);
    EXPECT_NEAR((abbe.eta(587.56f) - 1.0f) / (abbe.eta(486.13f) - abbe.eta(656.27f)), 30.0f, 0.05f);
}

namespace {

// Floor, a gold glossy sphere and a dispersive glass sphere lit by an F10 area light, a D65 point
// light and a blackbody emissive quad: every spectral feature in one small scene.
std::shared_ptr<Scene> spectral_scene(int size, bool spectral_content = true) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.8f, 0.7f, 0.6f)));
    Material gold = glossy(Color(1.0f), 0.3f);
    if (spectral_content) gold.spectral.metal = "Au";
    uint32_t au = s->add_material(gold);
    Material glass = smooth_glass(1.5f);
    if (spectral_content) glass.spectral.dispersion = "N-SF11";
    uint32_t gl = s->add_material(glass);
    Material lamp = diffuse(Color(0.0f), Color(2.0f));
    if (spectral_content) lamp.spectral.emission_spectrum = "BLACKBODY", lamp.spectral.emission_temperature = 3000.0f;
    uint32_t lm = s->add_material(lamp);
    add_box(*s, {-3, -3, -0.1f}, {3, 3, 0}, white);
    add_sphere(*s, 0.5f, 12, 24, au);
    add_box(*s, {0.2f, -0.3f, 0.0f}, {0.8f, 0.3f, 0.7f}, gl);
    add_box(*s, {-0.2f, 1.0f, 0.0f}, {1.2f, 1.1f, 1.2f}, lm);  // seen through the glass
    LightDesc area;
    area.type = "AREA";
    area.size = 1.0f;
    area.power = 80.0f;
    area.to_world.m[2][3] = 2.5f;
    if (spectral_content) area.spectrum = "F10";
    s->add_light(area);
    LightDesc point;
    point.type = "POINT";
    point.power = 40.0f;
    point.radius = 0.1f;
    point.color = Color(0.9f, 0.8f, 1.0f);
    point.to_world.m[0][3] = 1.5f, point.to_world.m[1][3] = -1.5f, point.to_world.m[2][3] = 1.5f;
    if (spectral_content) point.spectrum = "D65";
    s->add_light(point);
    CameraDesc c = camera_along_y({0.0f, -3.0f, 0.35f}, size, size, 30.0f);
    s->set_camera(c);
    s->commit();
    return s;
}

std::vector<float> render_mode(const std::shared_ptr<Scene>& scene, const std::string& mode, uint32_t spp,
                               uint32_t seed) {
    RenderSettings st;
    st.samples = spp;
    st.seed = seed;
    st.max_bounces = 6;
    st.spectral = setting_value<SpectralSetting>(mode);
    return render(scene, st);
}

}  // namespace

TEST(Spectral, AutoSelectsRgbWithoutSpectralContent) {
    RenderSettings st;
    EXPECT_EQ(resolve_spectral_mode(st, *spectral_scene(4, false)), SpectralSetting::Rgb);
    EXPECT_EQ(resolve_spectral_mode(st, *spectral_scene(4, true)), SpectralSetting::Smis);
    st.spectral = SpectralSetting::Hero;
    EXPECT_EQ(resolve_spectral_mode(st, *spectral_scene(4, false)), SpectralSetting::Hero);
    EXPECT_THROW(setting_value<SpectralSetting>("NOPE"), std::invalid_argument);
}

TEST(Spectral, UnknownSpectralNamesAreClearErrors) {
    Scene s;
    Material m = diffuse(Color(0.5f));
    m.spectral.metal = "Unobtainium";
    EXPECT_THROW(s.add_material(m), std::invalid_argument);
    LightDesc l;
    l.type = "POINT";
    l.power = 1.0f;
    l.spectrum = "F99";
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
}

// A white diffuse plane lit by a D65 area light is neutral grey in every spectral mode.
TEST(Spectral, WhiteSurfaceUnderD65IsNeutral) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.8f)));
    add_box(*s, {-5, -5, -0.1f}, {5, 5, 0}, white);
    LightDesc area;
    area.type = "AREA";
    area.size = 2.0f;
    area.power = 100.0f;
    area.spectrum = "D65";
    area.to_world.m[2][3] = 1.0f;
    s->add_light(area);
    CameraDesc c = camera_at({0, 0, 2}, 32, 32);
    s->set_camera(c);
    s->commit();
    // Per pixel R - G and B - G have mean 0 (z-test over the independent pixels) and are small.
    for (const char* mode : {"HERO", "SMIS"}) {
        auto img = render_mode(s, mode, 256, 1);
        stats::MeanEstimator g, rg, bg;
        for (size_t p = 0; p < img.size() / 4; ++p) {
            g.add(img[4 * p + 1]);
            rg.add(img[4 * p] - img[4 * p + 1]);
            bg.add(img[4 * p + 2] - img[4 * p + 1]);
        }
        SCOPED_TRACE(mode);
        EXPECT_GT(g.mean(), 0.05);
        // 2e-3 relative: the D65 table against the RGB matrices' white (measured 1e-4..1e-3).
        EXPECT_GT(stats::z_test_mean(rg, 0.0, 2e-3 * g.mean()).p_value, 1e-3) << rg.mean() << " +- " << rg.std_error();
        EXPECT_GT(stats::z_test_mean(bg, 0.0, 2e-3 * g.mean()).p_value, 1e-3) << bg.mean() << " +- " << bg.std_error();
        // ... with a resolution that makes a 1% tint detectable.
        EXPECT_LT(rg.std_error(), 3e-3 * g.mean());
        EXPECT_LT(bg.std_error(), 3e-3 * g.mean());
    }
}

// The pixel sequence of the wavelength offsets is a function of (pixel, sample, seed) only: the same
// seed gives the same image on one thread or two, for every mode; another seed another image.
TEST(Spectral, SameSeedSameImageWhateverTheThreadCount) {
    auto scene = spectral_scene(16);
    for (const char* mode : {"SPECTRAL_IS", "HERO", "SMIS", "BRUTE_FORCE"}) {
        RenderSettings st;
        st.samples = 8;
        st.seed = 5;
        st.max_bounces = 6;
        st.spectral = setting_value<SpectralSetting>(mode);
        expect_same_image_whatever_the_thread_count(scene, st, 2, mode);
    }
}

// Every estimator has the expectation of BRUTE_FORCE: per pixel, the difference between a render of
// the mode and an independent BRUTE_FORCE render has mean 0; z-tests per mode and channel over the
// pixels (independent), Sidak-corrected over the 15 tests.
TEST(Spectral, EveryModeIsUnbiased) {
    auto scene = spectral_scene(32);
    const int spp = 32;
    auto reference = render_mode(scene, "BRUTE_FORCE", spp, 1000);
    const char* modes[] = {"UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT"};
    double alpha = stats::sidak_significance(1e-3, 15);
    double brightest = 0.0;
    for (const char* mode : modes) {
        auto img = render_mode(scene, mode, spp, 1);
        for (int ch = 0; ch < 3; ++ch) {
            stats::MeanEstimator d, ref;
            for (size_t p = 0; p < img.size() / 4; ++p) {
                d.add(img[4 * p + ch] - reference[4 * p + ch]);
                ref.add(reference[4 * p + ch]);
            }
            brightest = std::max(brightest, ref.mean());
            auto z = stats::z_test_mean(d, 0.0);
            EXPECT_GT(z.p_value, alpha) << mode << " channel " << ch << " mean diff " << d.mean() << " +- "
                                        << d.std_error() << " (reference mean " << ref.mean() << ")";
        }
    }
    EXPECT_GT(brightest, 0.01);  // the scene is lit: the test can fail
}

namespace {

// A glass ball (a ball lens) before an emissive half-plane whose edge is off the axis, seen directly
// through the ball: the edge's image inside the ball is displaced by an amount that depends on the IOR,
// so with dispersion the red and blue images of the edge separate (a colour fringe).
std::shared_ptr<Scene> ball_lens(const std::string& dispersion) {
    auto s = std::make_shared<Scene>();
    Material glass = smooth_glass(1.7f);
    glass.spectral.dispersion = dispersion;
    glass.spectral.abbe = 20.0f;
    add_sphere(*s, 0.5f, 48, 96, s->add_material(glass));
    Material lamp = diffuse(Color(0.0f), Color(1.0f));
    lamp.spectral.emission_spectrum = "D65";
    add_box(*s, {0.12f, -10.0f, -3.1f}, {10.0f, 10.0f, -3.0f}, s->add_material(lamp));
    CameraDesc c = camera_at({0.0f, 0.0f, 2.5f}, 32, 32);
    c.lens = 120.0f;
    s->set_camera(c);
    s->commit();
    return s;
}

// Horizontal separation (pixels) of the red and blue images: difference of their x centroids.
double red_blue_separation(const std::vector<float>& img, int w) {
    double sr = 0, sb = 0, xr = 0, xb = 0;
    for (size_t p = 0; p < img.size() / 4; ++p) {
        double x = double(p % w);
        xr += x * img[4 * p], sr += img[4 * p];
        xb += x * img[4 * p + 2], sb += img[4 * p + 2];
    }
    return xr / sr - xb / sb;
}

}  // namespace

// The red - blue separation over eight independent renders with dispersion and eight at constant IOR:
// dispersion moves it by many standard errors (a one-pair noise estimate was too fragile: the effect
// is ~0.07 px at this size), and the constant-IOR separation stays near zero.
TEST(Spectral, DispersiveGlassSeparatesColours) {
    stats::MeanEstimator on, off;
    for (uint32_t seed = 1; seed <= 8; ++seed) {
        on.add(red_blue_separation(render_mode(ball_lens("ABBE"), "SMIS", 256, seed), 32));
        off.add(red_blue_separation(render_mode(ball_lens("NONE"), "SMIS", 256, seed), 32));
    }
    std::printf("red - blue centroid: dispersive %.4f +- %.4f px, constant IOR %.4f +- %.4f px\n", on.mean(),
                on.std_error(), off.mean(), off.std_error());
    auto z = stats::z_test_difference(on, off);
    EXPECT_GT(std::fabs(z.z), 5.0);
    EXPECT_LT(std::fabs(off.mean()), 0.05);
}

// An independent reference for the spectral modes (EveryModeIsUnbiased compares them with
// BRUTE_FORCE, which shares eq. 21's code, the wavelength density and the division by it, and the RGB
// response): renders at single wavelengths (RenderSettings::spectral_wavelength: the radiance itself,
// nothing sampled or weighted), integrated against the CIE observer here and taken to linear Rec.709
// by the IEC matrix. The wavelengths are the 2-point Gauss-Legendre nodes of every 1 nm interval of
// [360, 830]: the observer and the emission tables are linear between whole nanometres, so the rule
// is exact for their products, and the reference has no wavelength noise, which all its pixels would
// share and the test below could not see (one jittered wavelength per nanometre put the F10 light's
// blue 5% off). Every mode, BRUTE_FORCE included, must agree with it per channel in the mean over the
// pixels of the difference. Checked red: with every mode's RGB response scaled by 1.03 in the spectral
// path's set-up, SMIS and BRUTE_FORCE disagreed (blue z = 4.1 and 5.6) while EveryModeIsUnbiased passed.
TEST(Spectral, EveryModeAgreesWithSingleWavelengthRenders) {
    constexpr int kSize = 16;
    auto scene = spectral_scene(kSize);
    const size_t pixels = size_t(kSize) * kSize;
    std::vector<Vec3> xyz(pixels, Vec3(0.0f));
    const float node = 0.5f / std::sqrt(3.0f);
    uint32_t seed = 5000;
    for (int nm = 0; nm < kTableSamples - 1; ++nm)
        for (float offset : {0.5f - node, 0.5f + node}) {
            RenderSettings st;
            st.samples = 16;
            st.seed = seed++;
            st.max_bounces = 6;
            st.spectral_wavelength = kLambdaMin + float(nm) + offset;
            auto img = render(scene, st);
            const Vec3 cmf = cie_xyz(st.spectral_wavelength) * 0.5f;  // the node's weight: half the interval
            for (size_t p = 0; p < pixels; ++p) {
                EXPECT_EQ(img[4 * p], img[4 * p + 1]);  // the radiance itself, the same in every channel
                xyz[p] += cmf * img[4 * p + 1];
            }
        }
    std::vector<Color> reference(pixels);
    for (size_t p = 0; p < pixels; ++p) reference[p] = xyz_to_rgb(xyz[p] * float(1.0 / kCieYIntegral));

    const char* modes[] = {"UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT", "BRUTE_FORCE"};
    const double alpha = stats::sidak_significance(1e-3, 18);
    double brightest = 0.0;
    for (const char* mode : modes) {
        auto img = render_mode(scene, mode, 512, 7);
        for (int ch = 0; ch < 3; ++ch) {
            stats::MeanEstimator d, ref;
            for (size_t p = 0; p < pixels; ++p) {
                d.add(img[4 * p + ch] - reference[p][ch]);
                ref.add(reference[p][ch]);
            }
            brightest = std::max(brightest, ref.mean());
            auto z = stats::z_test_mean(d, 0.0);
            std::printf("%-16s channel %d: mean difference %+.5f +- %.5f (reference %.5f)\n", mode, ch, d.mean(),
                        d.std_error(), ref.mean());
            EXPECT_GT(z.p_value, alpha) << mode << " channel " << ch;
        }
    }
    EXPECT_GT(brightest, 0.01);
    RenderSettings outside;
    outside.spectral_wavelength = 900.0f;  // beyond the observer's range: a clear error
    EXPECT_THROW(render(scene, outside), std::invalid_argument);
}
