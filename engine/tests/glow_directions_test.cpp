// Light-aimed continuations at surface vertices in fog (integrators/glow_directions.h, issue 22):
//  1. the cone sampler's sample() matches its pdf() (chi-square, stats.h) and the pdf integrates to
//     1 over the sphere, around +z and around a tilted axis;
//  2. the whole continuation (BSDF sampling and the light-aimed cone, one-sample MIS over two
//     radius-0 lights) at a shading point of a fog scene: sample() against the mixture density
//     mixture_pdf() (chi-square), with a two-lobe BSDF so that lobe labels are exercised;
//  3. unbiasedness: PATH with the technique against PATH without it on a
//     small room with fog holding a radius-0 point light, a radius-0 spot and an area light (whose
//     emission hits weigh against the mixture), per-pixel and image-mean z-tests over independent
//     renders, for the RGB and the spectral path tracer (RenderSettings::glow_directions off).
#include <gtest/gtest.h>

#include "core/sampling.h"
#include "integrators/glow_directions.h"
#include "stats.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

constexpr int kChi2Cases = 3;
constexpr uint64_t kChi2Samples = 1000000;

// A room with a fog box (pass-through boundary, mildly forward-scattering) over its lower part,
// holding a radius-0 point light and a radius-0 spot shining down, under the ceiling's square light.
// The floor is diffuse; the back wall diffuse plus a rough glossy coat (two lobes).
std::shared_ptr<Scene> glow_room(int w, int h) {
    auto s = std::make_shared<Scene>();
    const uint32_t white = s->add_material(diffuse(Color(0.7f)));
    const uint32_t red = s->add_material(diffuse(Color(0.7f, 0.15f, 0.1f)));
    Material coated = diffuse(Color(0.3f, 0.5f, 0.6f));
    coated.lobes.push_back(glossy(Color(0.3f), 0.4f).lobes[0]);
    const uint32_t back = s->add_material(coated);
    Medium fog;
    fog.sigma_a = Color(0.05f, 0.08f, 0.1f);
    fog.sigma_s = Color(0.6f, 0.5f, 0.4f);
    fog.phase = HenyeyGreenstein(0.2f);
    const uint32_t fog_box = add_medium_boundary(*s, fog);
    add_room(*s, white, white, red);
    add_box(*s, {-1.1f, 0.9f, 0.0f}, {1.1f, 1.0f, 2.0f}, back);
    add_box(*s, {-0.99f, -0.99f, 0.0f}, {0.99f, 0.95f, 1.3f}, fog_box);
    add_square_light(*s, 0.5f, 30.0f, {0.0f, 0.0f, 1.98f});
    s->add_light(point_light(10.0f, 0.0f, {-0.45f, 0.3f, 0.6f}).hidden_from_camera());
    TestLight spot = point_light(30.0f, 0.0f, {0.4f, 0.1f, 1.1f}).hidden_from_camera();
    spot.desc.type = "SPOT";
    spot.desc.spot_size = 0.9f;
    spot.desc.spot_blend = 0.3f;
    s->add_light(spot);
    s->set_camera(camera_along_y({0.0f, -2.9f, 0.8f}, w, h, 22.0f));
    s->commit();
    return s;
}

const std::shared_ptr<Scene>& glow_scene() {
    static auto s = glow_room(16, 16);
    return s;
}

double chi2_alpha() { return stats::sidak_significance(0.01, kChi2Cases); }

void expect_cone_matches_pdf(const Vec3& axis, float theta_max) {
    const Frame f(normalize(axis));
    auto sample = [&](Rng& rng) {
        const Point2 u{rng.next_float(), rng.next_float()};
        float pdf;
        const Vec3 w = f.to_world(sample_glow_cone(u, theta_max, &pdf));
        if (!(pdf > 0.0f)) return stats::DirSample::invalid();
        // The reported density is checked against pdf() where float rotation keeps sin theta to
        // 1e-3 (the pdf's 1 / sin theta amplifies the rounding of directions within 1e-3 rad).
        return stats::DirSample::valid(w, u.x * theta_max > 1e-3f ? double(pdf) : -1.0);
    };
    auto pdf = [&](const Vec3& w) {
        return glow_cone_pdf(dot(w, f.n), length(cross(w, f.n)), theta_max);
    };
    const stats::Chi2Result r = stats::chi2_test_directions(sample, pdf, kChi2Samples);
    EXPECT_TRUE(r.passes(chi2_alpha())) << r.summary();
    EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << "the cone's density integrates to 1";
}

}  // namespace

TEST(GlowDirections, ConeSampleMatchesItsPdfAndIntegratesToOne) {
    expect_cone_matches_pdf({0.0f, 0.0f, 1.0f}, 0.5f);
    expect_cone_matches_pdf({0.3f, -0.5f, 0.4f}, 1.2f);
}

TEST(GlowDirections, MixtureSampleMatchesItsPdf) {
    const Scene& scene = *glow_scene();
    ASSERT_EQ(scene.glow_lights().size(), 2u) << "both radius-0 lights in the fog, the area light not";
    // A point on the back wall's coat (two lobes), in the fog, facing both lights.
    ShadingPoint sp;
    sp.hit.p = Vec3(0.0f, 0.9f, 0.5f);
    sp.ng = sp.ns = Vec3(0.0f, -1.0f, 0.0f);
    sp.wo = normalize(Vec3(0.2f, -1.0f, 0.3f));
    sp.backfacing = false;
    Bsdf bsdf(Frame(sp.ns), sp.ng);
    Material coated = diffuse(Color(0.3f, 0.5f, 0.6f));
    coated.lobes.push_back(glossy(Color(0.3f), 0.4f).lobes[0]);
    for (const Lobe& l : coated.lobes) bsdf.add(l);
    sp.bsdf = bsdf;
    const int32_t medium = scene.medium_at(sp.hit.p);
    ASSERT_GE(medium, 0);
    const GlowDirections glow(scene, sp, medium);
    ASSERT_TRUE(glow.on());
    auto sample = [&](Rng& rng) {
        const float u_lobe = rng.next_float();
        const Point2 u_dir{rng.next_float(), rng.next_float()};
        BsdfSample bs;
        if (!glow.sample(sp, u_lobe, u_dir, rng.next_float(), &bs) || !bs.valid()) return stats::DirSample::invalid();
        return stats::DirSample::valid(bs.wi, bs.pdf);
    };
    auto pdf = [&](const Vec3& w) { return glow.mixture_pdf(sp.bsdf.pdf(sp.wo, w), w); };
    const stats::Chi2Result r = stats::chi2_test_directions(sample, pdf, kChi2Samples);
    EXPECT_TRUE(r.passes(chi2_alpha())) << r.summary();
    // What the surface cannot scatter to (below it) is dropped: the density integrates to the rest.
    EXPECT_NEAR(r.pdf_integral, double(r.n_valid) / double(r.n_samples), 3e-3);
    EXPECT_GT(r.pdf_integral, 0.5);
}

namespace {

void expect_same_as_without(const char* what, SpectralSetting spectral) {
    RenderSettings st;
    st.max_bounces = 3;
    st.spectral = spectral;
    RenderSettings off = st;
    off.glow_directions = false;
    const PixelStats ref = across_renders(glow_scene(), off, 32, 256, 100, true);
    const PixelStats got = across_renders(glow_scene(), st, 32, 256, 500, true);
    double z = 0.0;
    const double accepted = accepted_fraction(got, ref), p = smallest_channel_p_value(got, ref, &z);
    std::printf("%s: %.4f of pixel channels agree without the light-aimed directions; green image mean %.5f "
                "+- %.5f against %.5f +- %.5f, worst channel z = %.2f\n",
                what, accepted, got.image.mean(), got.image.std_error(), ref.image.mean(),
                ref.image.std_error(), z);
    EXPECT_GE(accepted, 0.99);
    EXPECT_GE(p, stats::sidak_significance(0.001, 2));
}

}  // namespace

TEST(GlowDirections, PathTracerIsUnbiased) { expect_same_as_without("PATH", SpectralSetting::Rgb); }
TEST(GlowDirections, SpectralPathTracerIsUnbiased) { expect_same_as_without("PATH, spectral SMIS", SpectralSetting::Smis); }
