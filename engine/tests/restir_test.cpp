// Resampled direct lighting: RIS and unbiased ReSTIR (seed MIS, Alg. 1; Talbot MIS, Alg. 2; with
// and without visibility reuse) converge to the path tracer's NEE on a scene with hundreds of small
// emitters and occluders (per-pixel z-tests over independent renders, Šidák-corrected), and the same
// test rejects the biased variants (1/M normalisation; visibility left out of the MIS pdfs).
#include <gtest/gtest.h>

#include "stats.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

constexpr int kW = 24, kH = 24;

RenderSettings base_settings(DirectLightStrategy strategy) {
    RenderSettings st;
    st.max_bounces = 1;  // direct light plus one bounce: the indirect part is not under test
    st.direct_light = strategy;
    st.ris_candidates = 8;
    st.restir_neighbors = 4;
    st.restir_radius_px = 6.0f;
    return st;
}

// The image means, compared by a z-test: one test with much more power than any single pixel's.
struct Verdict {
    double pixels_accepted;
    double image_p_value;
};

const std::shared_ptr<Scene>& scene() {
    static auto s = many_lights(kW, kH);
    return s;
}

const PixelStats& reference() {
    static PixelStats ref = across_renders(scene(), base_settings(DirectLightStrategy::Nee), 64, 64, 1000);
    return ref;
}

RenderSettings restir(RestirMis mis, bool unbiased = true, bool visibility_reuse = true) {
    RenderSettings st = base_settings(DirectLightStrategy::Restir);
    st.restir_mis = mis;
    st.restir_unbiased = unbiased;
    st.restir_visibility_reuse = visibility_reuse;
    return st;
}

Verdict check(const char* name, const RenderSettings& st, int renders, uint32_t spp, uint32_t seed0) {
    PixelStats p = across_renders(scene(), st, renders, spp, seed0);
    Verdict v{accepted_fraction(p, reference()), smis::stats::z_test_difference(p.image, reference().image).p_value};
    std::printf("%-36s %.4f of pixels agree with NEE; image mean %.5f vs %.5f (+-%.5f), p = %.3g\n", name,
                v.pixels_accepted, p.image.mean(), reference().image.mean(),
                std::sqrt(p.image.variance() / p.image.count() + reference().image.variance() / reference().image.count()),
                v.image_p_value);
    return v;
}

// Unbiased: (almost) every pixel agrees and the image mean agrees at the 0.1% level.
void expect_unbiased(const Verdict& v) {
    EXPECT_GE(v.pixels_accepted, 0.99);
    EXPECT_GE(v.image_p_value, 1e-3);
}

}  // namespace

TEST(Restir, ManyLightsSceneHasHundredsOfEmitters) {
    EXPECT_GE(scene()->lights().size(), 200u);
}

TEST(Restir, RisConvergesToNee) {
    expect_unbiased(check("RIS", base_settings(DirectLightStrategy::Ris), 64, 16, 2000));
}

TEST(Restir, UnbiasedSeedMisConvergesToNee) {
    expect_unbiased(check("RESTIR SEED", restir(RestirMis::Seed), 128, 4, 3000));
}

TEST(Restir, UnbiasedTalbotMisConvergesToNee) {
    expect_unbiased(check("RESTIR TALBOT", restir(RestirMis::Talbot), 128, 4, 4000));
}

TEST(Restir, WithReuseAcrossIterationsBothMisConvergeToNee) {
    // The history (off by default) combines the previous iteration's final reservoir, whose occluded
    // samples the reuse dropped: the MIS pdfs of the history include its own visibility.
    for (RestirMis mis : {RestirMis::Seed, RestirMis::Talbot}) {
        RenderSettings st = restir(mis);
        st.restir_history_cap = 2;
        expect_unbiased(check(mis == RestirMis::Seed ? "RESTIR SEED, history cap 2" : "RESTIR TALBOT, history cap 2",
                              st, 128, 4, mis == RestirMis::Seed ? 9000 : 10000));
    }
}

TEST(Restir, WithoutVisibilityReuseBothMisConvergeToNee) {
    // The supplement's Fig. 1 "without visibility reuse": occluded samples stay in the reservoirs,
    // the MIS pdfs need no shadow rays and the estimator is still unbiased.
    expect_unbiased(check("RESTIR SEED, no visibility reuse", restir(RestirMis::Seed, true, false), 128, 4, 5000));
    expect_unbiased(check("RESTIR TALBOT, no visibility reuse", restir(RestirMis::Talbot, true, false), 128, 4, 6000));
}

TEST(Restir, BiasedVariantsAreRejected) {
    // The same test must see a broken weight: the 1/M normalisation, and the MIS pdfs without the
    // visibility that the reservoirs' support depends on, both darken near shadows.
    Verdict none = check("RESTIR NONE (1/M)", restir(RestirMis::None), 128, 4, 7000);
    Verdict seed_biased = check("RESTIR SEED, no visibility in MIS", restir(RestirMis::Seed, false), 128, 4, 8000);
    EXPECT_LT(none.pixels_accepted, 0.99);
    EXPECT_LT(seed_biased.pixels_accepted, 0.99);
    EXPECT_LT(none.image_p_value, 1e-3);
    EXPECT_LT(seed_biased.image_p_value, 1e-3);
}

TEST(Restir, SameSeedSameImageForAnyThreadCount) {
    for (RestirMis mis : {RestirMis::Seed, RestirMis::Talbot}) {
        RenderSettings st = restir(mis);
        st.samples = 3;
        st.restir_history_cap = 2;  // temporal reuse included
        st.threads = 1;
        auto one = render(scene(), st);
        st.threads = 2;
        EXPECT_EQ(one, render(scene(), st));
    }
}
