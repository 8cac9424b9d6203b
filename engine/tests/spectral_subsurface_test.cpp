// Spectral rendering of subsurface scattering: the random walk and Christensen-Burley's disk with a
// spectral path's wavelengths as their channels (integrators/spectral_path.cpp, SpectralThroughput::
// subsurface), against the RGB path tracer and single-wavelength paths.
#include <gtest/gtest.h>

#include "spectral_agreement.h"
#include "subsurface_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// A random-walk sphere (principled exit, anisotropic) and a thin Christensen-Burley slab on a white
// floor, lit by a rectangle above and a point light behind the slab (seen through it); mean free
// paths of the order of the objects, so the walks matter (their diffuse fallback renders darker:
// image mean 7% below, z -10 in GreyWalkAndDiskConvergeToRgb).
std::shared_ptr<Scene> subsurface_scene(const Color& albedo, const Color& radius) {
    auto s = std::make_shared<Scene>();
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_sphere(*s, 0.45f, 16, 32,
               s->add_material(subsurface_material(albedo, radius, 0.3f, true)), true,
               {-0.5f, 0.0f, 0.45f});
    add_box(*s, {0.15f, -0.04f, 0.0f}, {0.9f, 0.04f, 0.8f},
            s->add_material(subsurface_material(albedo, radius * 0.5f, 0.0f, false, SubsurfaceMethod::ChristensenBurley)));
    LightDesc area;
    area.type = "AREA";
    area.size = 1.5f;
    area.power = 60.0f;
    area.visible_to_camera = false;
    area.to_world.m[2][3] = 2.2f;
    s->add_light(area);
    LightDesc point;
    point.type = "POINT";
    point.power = 30.0f;
    point.radius = 0.1f;
    point.to_world.m[0][3] = 0.5f, point.to_world.m[1][3] = 0.3f, point.to_world.m[2][3] = 0.4f;
    s->add_light(point);
    s->set_camera(camera_along_y({0.0f, -3.2f, 0.6f}, 16, 16, 30.0f));
    s->commit();
    return s;
}

}  // namespace

// Grey albedo and radius have flat spectra: every spectral mode must converge to the RGB path
// tracer's walks pixel by pixel (per-pixel z-tests over independent renders, Sidak-corrected) and in
// the image mean per channel.
TEST(SpectralSubsurface, GreyWalkAndDiskConvergeToRgb) {
    expect_agreement(subsurface_scene(Color(0.8f), Color(0.3f)), {"SMIS", "HERO", "UNIFORM"}, "RGB", 16, 64);
}

// Coloured albedo and radius: the four-wavelength walks (each flight drawn from one wavelength, weighed
// by the mixture over the path's wavelengths) must agree with single-wavelength paths (UNIFORM: the
// walk at one wavelength alone).
TEST(SpectralSubsurface, ColouredWalkAndDiskAgreeWithSingleWavelengthPaths) {
    expect_agreement(subsurface_scene(Color(0.9f, 0.5f, 0.25f), Color(0.4f, 0.15f, 0.05f)), {"SMIS", "HERO"},
                     "UNIFORM", 16, 128);
}
// Coloured subsurface against the RGB path tracer: the upsampled albedo and radius spectra do not
// reproduce RGB's per-channel walks exactly (a spectrum's RGB projection is not its three channels'
// own walks), so the image means agree within a tolerance, measured (SMIS 24 x 256 spp against
// RGB: R +0.1%, G +1.0%, B -1.5%, each within 3 standard errors of zero or 1.5%).
TEST(SpectralSubsurface, ColouredSpectralImageMatchesRgbWithinTwoPercent) {
    auto scene = subsurface_scene(Color(0.9f, 0.5f, 0.25f), Color(0.4f, 0.15f, 0.05f));
    PixelStats rgb = across_renders(scene, spectral_settings("RGB"), 12, 128, 300, true);
    PixelStats got = across_renders(scene, spectral_settings("SMIS"), 12, 128, 200, true);
    for (int c = 0; c < 3; ++c) {
        const double a = got.channel_image[c].mean(), b = rgb.channel_image[c].mean();
        const double se = std::sqrt(got.channel_image[c].variance() / 12 + rgb.channel_image[c].variance() / 12);
        std::printf("channel %d: SMIS %.5f RGB %.5f, relative %+.4f, standard error %.4f\n", c, a, b, a / b - 1.0,
                    se / b);
        EXPECT_LT(std::fabs(a - b), 0.02 * b + 3.0 * se) << c;
    }
}
