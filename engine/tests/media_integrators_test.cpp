// Resampled direct lighting (RIS, ReSTIR) and path-space filtering in scenes with participating
// media: the unbiased variants converge to the path tracer (per-pixel z-tests over independent
// renders, Šidák-corrected, and the image means) on a room with a fog box, a mirror wall, a glass
// ball and a lamp inside the fog; the biased variants' bias is measured; the same test rejects a
// 5% error (its power).
#include <gtest/gtest.h>

#include "stats.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

constexpr int kW = 20, kH = 20;

// The room of psf_test's dirac_room (red left wall, mirror right wall, smooth glass ball, a thin
// card) with fog in its lower part: a pass-through box (index-matched boundary) the camera looks
// into, which holds the ball, the card and a small point lamp, under the ceiling's square light,
// and a thin World volume everywhere else (the camera's medium). Paths cross the fog's boundary on
// the way to and from every vertex in it; the ball's inside is the fog too (a surface without a
// volume leaves the medium unchanged).
std::shared_ptr<Scene> fog_room(int w, int h) {
    auto s = std::make_shared<Scene>();
    const uint32_t white = s->add_material(diffuse(Color(0.7f)));
    const uint32_t red = s->add_material(diffuse(Color(0.7f, 0.15f, 0.1f)));
    const uint32_t green = s->add_material(diffuse(Color(0.15f, 0.6f, 0.25f)));
    const uint32_t mirror = s->add_material(glossy(Color(0.9f), 0.0f));
    Material glass;
    Lobe smooth_glass;
    smooth_glass.kind = LobeKind::Dielectric;
    smooth_glass.alpha = 0.0f;
    smooth_glass.eta = 1.5f;
    glass.lobes.push_back(smooth_glass);
    const uint32_t ball = s->add_material(glass);
    Medium fog;
    fog.sigma_a = Color(0.05f, 0.08f, 0.12f);
    fog.sigma_s = Color(0.7f, 0.6f, 0.45f);
    fog.phase = HenyeyGreenstein(0.3f);
    const uint32_t fog_box = add_medium_boundary(*s, fog);
    Medium haze;
    haze.sigma_a = Color(0.02f);
    haze.sigma_s = Color(0.05f, 0.08f, 0.1f);
    s->set_world_medium(s->add_medium(haze));
    add_room(*s, white, white, red);
    add_box(*s, {0.98f, -1.0f, 0.0f}, {1.0f, 1.0f, 2.0f}, mirror);
    add_box(*s, {-0.95f, -0.95f, 0.02f}, {0.3f, 0.95f, 1.1f}, fog_box);
    add_sphere(*s, 0.3f, 16, 32, ball, true, {-0.4f, 0.3f, 0.32f});
    const float card[] = {-0.1f, -0.2f, 0.0f, 0.6f, -0.2f, 0.0f, 0.6f, -0.2f, 0.55f, -0.1f, -0.2f, 0.55f};
    const int32_t card_tris[] = {0, 1, 2, 0, 2, 3};
    s->add_instance(s->add_mesh(card, 4, card_tris, 2, nullptr, nullptr, {green}), Transform());
    add_square_light(*s, 0.6f, 60.0f, {0.0f, 0.0f, 1.98f});
    s->add_light(point_light(6.0f, 0.05f, {0.5f, 0.3f, 0.7f}).hidden_from_camera());
    s->set_camera(camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f));
    s->commit();
    return s;
}

const std::shared_ptr<Scene>& scene() {
    static auto s = fog_room(kW, kH);
    return s;
}

RenderSettings base_settings() {
    RenderSettings st;
    st.max_bounces = 3;
    st.ris_candidates = 8;
    st.restir_neighbors = 4;
    st.restir_radius_px = 6.0f;
    // Path-space filtering with a large, fixed radius and much reuse, so any bias of the reuse shows.
    st.psf_radius_px = 10.0f;
    st.psf_max_neighbors = 32;
    st.psf_radius_alpha = 1.0f;
    return st;
}

const PixelStats& reference() {
    static PixelStats ref = across_renders(scene(), base_settings(), 24, 64, 1000, true);
    return ref;
}

struct Verdict {
    double pixels_accepted;
    double image_p_value;
    double relative_bias;  // green image mean against PATH's
};

Verdict verdict(const std::string& name, const PixelStats& p) {
    const PixelStats& ref = reference();
    double z = 0.0;
    Verdict v{accepted_fraction(p, ref), smallest_channel_p_value(p, ref, &z), p.image.mean() / ref.image.mean() - 1.0};
    std::printf("%-36s %.4f of pixel channels agree with PATH; green image mean %+.2f%% (PATH %.5f +- %.5f), "
                "worst channel z = %.2f\n",
                name.c_str(), v.pixels_accepted, 100.0 * v.relative_bias, ref.image.mean(), ref.image.std_error(), z);
    return v;
}

Verdict check(const std::string& name, const RenderSettings& st, int renders, uint32_t spp, uint32_t seed0) {
    return verdict(name, across_renders(scene(), st, renders, spp, seed0, true));
}

void expect_unbiased(const Verdict& v) {
    EXPECT_GE(v.pixels_accepted, 0.99);
    EXPECT_GE(v.image_p_value, stats::sidak_significance(0.001, 3));
}

RenderSettings with(const std::string& integrator) {
    RenderSettings st = base_settings();
    select_integrator(st, integrator);
    return st;
}

}  // namespace

TEST(MediaIntegrators, RisConvergesToThePathTracer) {
    expect_unbiased(check("RIS", with("PATH+RIS"), 24, 16, 2000));
}

TEST(MediaIntegrators, UnbiasedRestirConvergesToThePathTracer) {
    // Visibility reuse with visibility in the MIS ([T > 0] from each reservoir's own vertex and
    // medium), with and without the history; and without visibility reuse (unshadowed MIS pdfs).
    for (const char* mis : {"PATH+RESTIR_SEED", "PATH+RESTIR_TALBOT"}) {
        RenderSettings st = with(mis);
        expect_unbiased(check(std::string(mis) + ", visibility reuse", st, 24, 16, 3000));
        st.restir_history_cap = 2;
        expect_unbiased(check(std::string(mis) + ", history cap 2", st, 24, 16, 4000));
        st.restir_history_cap = 0;
        st.restir_visibility_reuse = false;
        expect_unbiased(check(std::string(mis) + ", no visibility reuse", st, 24, 16, 5000));
    }
}

TEST(MediaIntegrators, UnbiasedPathSpaceFilteringConvergesToThePathTracer) {
    const PixelStats unbiased = across_renders(scene(), with("PSF_SMIS_UNBIASED"), 24, 16, 6000, true);
    expect_unbiased(verdict("PSF_SMIS_UNBIASED", unbiased));
    expect_unbiased(check("PSF_PATH", with("PSF_PATH"), 24, 16, 7000));

    // The power of these comparisons: PSF_SMIS_UNBIASED's renders scaled by 0.95 (means and their
    // variances) must be rejected, per pixel or by the image mean.
    PixelStats scaled = unbiased;
    const double k = 0.95;
    for (double& m : scaled.mean) m *= k;
    for (double& v : scaled.var) v *= k * k;
    const double acc = accepted_fraction(scaled, reference());
    const stats::MeanEstimator& a = unbiased.image;
    const stats::MeanEstimator& r = reference().image;
    const double z = (k * a.mean() - r.mean()) /
                     std::sqrt(k * k * a.variance() / double(a.count()) + r.variance() / double(r.count()));
    std::printf("PSF_SMIS_UNBIASED x 0.95: %.4f of pixel channels agree, green image-mean z = %.2f\n", acc, z);
    EXPECT_TRUE(acc < 0.99 || stats::two_sided_p_value(z) < stats::sidak_significance(0.001, 3));
}

TEST(MediaIntegrators, BiasedVariantsHaveASmallMeasuredBias) {
    // Practical path-space filtering reuses the sampler's unoccluded T(x1_j, z1) L_out(z1); ReSTIR's
    // 1/M and its MIS without visibility darken near shadows. Measured at a 10 px radius that does
    // not shrink (the default shrinks it, and the bias with it).
    for (const char* name : {"PSF_SMIS", "PSF_KELLER", "PATH+RESTIR_NONE"}) {
        const Verdict v = check(std::string(name) + " (biased)", with(name), 24, 16, 8000);
        EXPECT_LT(std::fabs(v.relative_bias), 0.1) << name;
    }
}

TEST(MediaIntegrators, SameSeedSameImageWhateverTheThreadCount) {
    for (const char* name : {"PSF_SMIS_UNBIASED", "PSF_SMIS", "PATH+RIS", "PATH+RESTIR_SEED"}) {
        RenderSettings st = with(name);
        st.samples = 2;
        st.seed = 11;
        expect_same_image_whatever_the_thread_count(scene(), st, 3, name);
    }
}
