// Subsurface scattering (issue 19): the closure's lobes as Cycles 3.4 sets them up, and the path
// tracer's random walk (integrators/subsurface_walk.cpp) and Christensen-Burley disk sampling
// (integrators/subsurface_disk.cpp) against closed forms.
#include <gtest/gtest.h>

#include "integrators/subsurface_disk.h"
#include "integrators/subsurface_walk.h"
#include "subsurface_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// Scene s, committed, under a uniform sky of radiance 1, seen down the z axis from (0, 0, 3)
// through a long lens (the middle of what lies about the origin).
std::shared_ptr<Scene> under_sky(std::shared_ptr<Scene> s) {
    s->set_world(Color(1.0f));
    CameraDesc c = camera_at({0, 0, 3.0f}, 16, 16);
    c.lens = 200.0f;
    s->set_camera(c);
    s->commit();
    return s;
}

// A sphere of radius 1 with `m`, filling the view, under a uniform sky of radiance 1.
std::shared_ptr<Scene> sphere_under_sky(const Material& m) {
    auto s = std::make_shared<Scene>();
    add_sphere(*s, 1.0f, 32, 64, s->add_material(m));
    return under_sky(s);
}

// The path tracer's image of s at `samples` spp, 4 bounces (enough for an exit's sky).
std::vector<float> render_at(const std::shared_ptr<Scene>& s, uint32_t samples) {
    RenderSettings st;
    st.samples = samples;
    st.max_bounces = 4;
    return render(s, st);
}

}  // namespace

TEST(Subsurface, RadiusBelowCyclesMinimumIsDiffuse) {
    // Cycles' bssrdf_setup: a channel of radius below 1e-8 leaves the BSSRDF for a diffuse closure.
    SubsurfaceClosure c;
    c.weight = c.albedo = Color(0.8f, 0.6f, 0.4f);
    c.radius = Color(1.0f, 0.0f, 0.5f);
    Lobe lobes[3];
    ASSERT_EQ(subsurface_lobes(c, lobes), 2);
    EXPECT_EQ(lobes[0].kind, LobeKind::Diffuse);
    EXPECT_FLOAT_EQ(lobes[0].weight.y, 0.6f);
    EXPECT_FLOAT_EQ(lobes[0].weight.x, 0.0f);
    EXPECT_EQ(lobes[1].kind, LobeKind::Subsurface);
    EXPECT_FLOAT_EQ(lobes[1].weight.y, 0.0f);
    // Principled: its retro-reflection first, and the Fixed Radius scale 1 / (4 pi).
    c.principled = true;
    c.method = SubsurfaceMethod::RandomWalkFixedRadius;
    c.radius = Color(1.0f);
    ASSERT_EQ(subsurface_lobes(c, lobes), 2);
    EXPECT_EQ(lobes[0].kind, LobeKind::PrincipledPart);
    EXPECT_EQ(lobes[0].variant, PrincipledPartLobe::kRetro);
    EXPECT_NEAR(lobes[1].kind_colour.x, 0.25f / kPi, 1e-7f);
}

TEST(Subsurface, DiffuseFallbackIsThePrincipledDiffuse) {
    // After a diffuse bounce Cycles renders Principled's subsurface as its full principled diffuse:
    // the Lambert part the Subsurface lobe turns into plus the retro-reflection lobe kept beside it.
    Material m = subsurface_material(Color(0.7f, 0.5f, 0.3f), Color(0.1f), 0.0f, true);
    Bsdf b(Frame(Vec3(0, 0, 1)), Vec3(0, 0, 1));
    for (Lobe l : m.lobes) {
        l.alpha = 0.16f;  // roughness 0.4
        b.add(l);
    }
    EXPECT_TRUE(!b.is_delta());
    b.subsurface_as_diffuse();
    Lobe full;
    full.kind = LobeKind::PrincipledDiffuse;
    full.weight = Color(0.7f, 0.5f, 0.3f);
    full.alpha = 0.16f;
    Bsdf ref(Frame(Vec3(0, 0, 1)), Vec3(0, 0, 1));
    ref.add(full);
    for (Vec3 wi : {Vec3(0.3f, 0.2f, 0.9f), Vec3(-0.7f, 0.1f, 0.2f)}) {
        Vec3 wo = normalize(Vec3(0.5f, -0.3f, 0.6f));
        wi = normalize(wi);
        Color a = b.eval(wo, wi), r = ref.eval(wo, wi);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(a[k], r[k], 1e-6f);
    }
}

TEST(Subsurface, RandomWalkRadiusInvertsTheDipole) {
    // alpha' is the single-scattering albedo whose dipole reflectance is the surface albedo: the
    // scale sqrt(3 (1 - alpha')) falls from sqrt(3) (albedo 0) to ~0 (albedo 1).
    EXPECT_NEAR(random_walk_radius_scale(0.0f, 1.4f), std::sqrt(3.0f), 1e-6f);
    EXPECT_NEAR(random_walk_radius_scale(1.0f, 1.4f), std::sqrt(3.0f * 1e-6f), 2e-5f);
    float last = 10.0f;
    for (float a : {0.1f, 0.3f, 0.5f, 0.7f, 0.9f}) {
        float s = random_walk_radius_scale(a, 1.4f);
        EXPECT_LT(s, last) << a;
        last = s;
    }
}

TEST(Subsurface, WhiteFurnaceWalkLosesNoEnergy) {
    // Albedo 1: the medium absorbs nothing (alpha = 1 - 1e-6) and every walk leaves the closed
    // sphere, so its mean throughput is 1 whatever the guiding, the channel choice or the
    // anisotropy; the exit's Lambert under a uniform sky of radiance 1 then returns 1 exactly.
    // Mean free paths of 0.5 to 0.1 in a sphere of radius 1: walks end long before Cycles' cap of
    // 256 scattering events (with a mean free path of 1e-3, as Random Walk makes albedo 1, about 9%
    // of the walks in this sphere reach the cap and are lost, in Cycles as here).
    for (float g : {0.0f, 0.7f}) {
        auto s = sphere_under_sky(subsurface_material(Color(1.0f), Color(6.0f, 3.0f, 1.2f), g, false,
                                                      SubsurfaceMethod::RandomWalkFixedRadius));
        RenderSettings st;
        st.samples = 256;
        st.max_bounces = 4;
        auto img = render(s, st);
        for (int ch = 0; ch < 3; ++ch) {
            auto m = channel_mean(img, ch);
            std::printf("g %.1f channel %d: %.5f +- %.5f\n", g, ch, m.mean(), m.std_error());
            EXPECT_NEAR(m.mean(), 1.0, 4.0 * m.std_error() + 2e-3) << "g " << g << " channel " << ch;
        }
    }
}

TEST(Subsurface, InstancedObjectsWalkInTheirOwnGeometry) {
    // A mesh used twice is an Embree prototype: each instance's own scene holds its instance
    // geometry, whose hits map back to it. The second sphere lies far behind the camera.
    auto s = std::make_shared<Scene>();
    uint32_t mat = s->add_material(subsurface_material(Color(1.0f), Color(6.0f, 3.0f, 1.2f), 0.0f, false,
                                                      SubsurfaceMethod::RandomWalkFixedRadius));
    uint32_t mesh = add_sphere(*s, 1.0f, 32, 64, mat);
    Transform far;
    far.m[2][3] = 100.0f;
    s->add_instance(mesh, far);
    s->set_world(Color(1.0f));
    CameraDesc c = camera_at({0, 0, 3.0f}, 16, 16);
    c.lens = 200.0f;
    s->set_camera(c);
    s->commit();
    ASSERT_EQ(s->stats().embree_instances, 2u);
    RenderSettings st;
    st.samples = 128;
    st.max_bounces = 4;
    auto m = channel_mean(render(s, st), 1);
    EXPECT_NEAR(m.mean(), 1.0, 4.0 * m.std_error() + 2e-3);
}

TEST(Subsurface, ThickSlabReflectsTheSurfaceAlbedo) {
    // What the albedo inversion is for (Chiang et al. 2016): a semi-infinite medium with the fitted
    // alpha reflects the surface albedo. A sphere 50 mean free paths across is nearly one.
    for (float a : {0.3f, 0.6f, 0.9f}) {
        auto img = render_at(sphere_under_sky(subsurface_material(Color(a), Color(0.02f), 0.0f)), 256);
        auto m = channel_mean(img, 1);
        std::printf("albedo %.1f: %.5f +- %.5f\n", a, m.mean(), m.std_error());
        EXPECT_NEAR(m.mean(), a, 0.03 * a + 4.0 * m.std_error()) << "albedo " << a;
    }
}

TEST(Subsurface, ScenesWithoutSubsurfaceKeepTheLoopWithoutRules) {
    auto plain = sphere_under_sky(diffuse(Color(0.5f)));
    auto sss = sphere_under_sky(subsurface_material(Color(0.5f), Color(0.1f), 0.0f));
    RenderSettings st;
    EXPECT_FALSE(uses_light_path_rules(*plain, st));
    EXPECT_TRUE(uses_light_path_rules(*sss, st));
}

TEST(Subsurface, BurleyRadiusSamplingMatchesItsPdf) {
    // Chi-square of sample_radius's histogram over [0, 16 d] against radial_pdf integrated per bin
    // (Simpson): the density the disk weights divide by is the one the radii come from.
    constexpr int kBins = 64, kSamples = 400000;
    const double alpha = stats::sidak_significance(1e-3, 2);
    for (float d : {0.05f, 1.0f}) {
        const double width = burley::kTruncate * d / kBins;
        std::vector<double> observed(kBins, 0.0), expected(kBins, 0.0);
        for (int b = 0; b < kBins; ++b) {
            double sum = 0.0;
            constexpr int kSteps = 32;  // Simpson, even
            for (int i = 0; i <= kSteps; ++i) {
                // At r = 0 the density's limit, 1 / (2 d cdf(16)) (radial_pdf returns 0 there).
                const double r = std::fmax((b + double(i) / kSteps) * width, 1e-7 * d);
                sum += (i == 0 || i == kSteps ? 1.0 : (i % 2 ? 4.0 : 2.0)) * burley::radial_pdf(d, float(r));
            }
            expected[b] = sum * width / (3.0 * kSteps) * kSamples;
        }
        Rng rng(7, 0);
        for (int i = 0; i < kSamples; ++i) {
            const float r = burley::sample_radius(d, rng.next_float());
            ASSERT_TRUE(r >= 0.0f && r <= burley::kTruncate * d) << r;
            observed[std::min(int(r / width), kBins - 1)] += 1.0;
        }
        stats::Chi2Result res;
        stats::chi2_statistic(observed, expected, 5.0, kSamples, &res);
        EXPECT_TRUE(res.error.empty()) << res.error;
        EXPECT_GT(res.p_value, alpha) << "d " << d << ": chi2 " << res.chi2 << " dof " << res.dof;
        // The cut profile is normalised: its pdf integrates to 1 and its cdf reaches 1 at the cut.
        double total = 0.0;
        for (double e : expected) total += e / kSamples;
        EXPECT_NEAR(total, 1.0, 1e-4) << d;
        EXPECT_NEAR(burley::radial_cdf(d, burley::kTruncate * d), 1.0f, 1e-6f);
    }
}

TEST(Subsurface, BurleyFlatSlabReflectsItsAlbedo) {
    // Cycles 3.4 sets Christensen-Burley up with d = radius / (4 pi) and a profile normalised to 1:
    // a flat surface far from its edges reflects the closure weight (the albedo) per channel. A box
    // 10 x 10 x 2 seen from above under a uniform sky of radiance 1, d = 0.04 (cut at 0.64): the
    // top face's probes along the normal find it at the disk radius, those along the tangents miss.
    const Color albedo(0.3f, 0.6f, 0.9f);
    auto s = std::make_shared<Scene>();
    add_box(*s, Vec3(-5.0f, -5.0f, -2.0f), Vec3(5.0f, 5.0f, 0.0f),
            s->add_material(subsurface_material(albedo, Color(0.5f, 0.5f, 0.25f), 0.0f, false,
                                                SubsurfaceMethod::ChristensenBurley)));
    auto img = render_at(under_sky(s), 256);
    for (int ch = 0; ch < 3; ++ch) {
        auto m = channel_mean(img, ch);
        std::printf("channel %d: %.5f +- %.5f (albedo %.2f)\n", ch, m.mean(), m.std_error(), albedo[ch]);
        EXPECT_NEAR(m.mean(), albedo[ch], 4.0 * m.std_error() + 2e-3) << "channel " << ch;
    }
}

TEST(Subsurface, BurleyIsDiskSampledOthersWalk) {
    // The method picks the transport: only Christensen-Burley's lobe carries kDisk.
    for (auto method : {SubsurfaceMethod::RandomWalk, SubsurfaceMethod::RandomWalkFixedRadius,
                        SubsurfaceMethod::ChristensenBurley}) {
        Material m = subsurface_material(Color(0.5f), Color(1.0f), 0.0f, true, method);
        const Lobe& l = m.lobes.back();
        ASSERT_EQ(l.kind, LobeKind::Subsurface);
        EXPECT_EQ(bool(l.variant & SubsurfaceLobe::kDisk), method == SubsurfaceMethod::ChristensenBurley);
        EXPECT_TRUE(l.variant & SubsurfaceLobe::kPrincipledExit);
        if (method != SubsurfaceMethod::RandomWalk) {
            EXPECT_NEAR(l.kind_colour.x, 0.25f / kPi, 1e-7f);
        }
    }
}
