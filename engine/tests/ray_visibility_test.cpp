// Ray visibility (Cycles' Object > Visibility > Ray Visibility) through the BVH: a ray skips the
// objects hidden from its type, whether the object is flattened into the top-level BVH (used once)
// or an Embree instance of a shared prototype (used twice); and the path-state rules that give a
// ray its type, hide lights and stop paths at the per-type bounce limits.
#include <gtest/gtest.h>

#include "integrators/path_tracing.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// A quad at height z over [-1, 1]^2 as one mesh; `instances` transforms place it.
uint32_t quad_mesh(Scene& s, uint32_t material) {
    const float v[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    return s.add_mesh(v, 4, t, 2, nullptr, nullptr, {material});
}

Transform moved(float x, float z) {
    Transform m;
    m.m[0][3] = x;
    m.m[2][3] = z;
    return m;
}

}  // namespace

TEST(RayVisibility, RaysSkipObjectsHiddenFromTheirType) {
    Scene s;
    uint32_t m = s.add_material(diffuse(Color(0.5f)));
    // Used once: flattened into the top-level BVH, hidden from shadow rays.
    s.add_instance(quad_mesh(s, m), moved(0.0f, 1.0f), Color(1.0f), 0.0f, 0.0f, 1.0f, false,
                   kRayAllVisibility & ~kRayShadow);
    // Used twice: an Embree instance of a prototype; the one at x = 5 hidden from camera and glossy rays.
    uint32_t shared = quad_mesh(s, m);
    s.add_instance(shared, moved(5.0f, 1.0f), Color(1.0f), 0.0f, 0.0f, 1.0f, false,
                   kRayAllVisibility & ~(kRayCamera | kRayGlossy));
    s.add_instance(shared, moved(10.0f, 1.0f));
    s.set_camera(camera_at(Vec3(0.0f, 0.0f, 10.0f), 4, 4));
    s.commit();

    auto hits = [&](float x, uint32_t mask) {
        SurfaceHit h;
        return s.intersect(Ray{Vec3(x, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), 0.0f, kInf, kShutterCentre, mask}, &h);
    };
    const uint32_t all = kRayAllVisibility;
    EXPECT_TRUE(hits(0.0f, kRayCamera));
    EXPECT_TRUE(hits(0.0f, ray_mask(kRayDiffuse)));
    EXPECT_TRUE(hits(0.0f, all));
    EXPECT_TRUE(s.occluded(Vec3(10.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), kInf));
    EXPECT_FALSE(s.occluded(Vec3(0.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), kInf));  // hidden from shadow rays
    EXPECT_TRUE(s.occluded(Vec3(0.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), kInf, kShutterCentre, ray_mask(kRayDiffuse)));

    EXPECT_FALSE(hits(5.0f, kRayCamera));
    EXPECT_FALSE(hits(5.0f, ray_mask(kRayGlossy)));
    EXPECT_TRUE(hits(5.0f, ray_mask(kRayDiffuse)));
    // A glossy transmission is a transmission ray for visibility (Cycles' path_state_ray_visibility).
    EXPECT_TRUE(hits(5.0f, ray_mask(kRayGlossy | kRayTransmission)));
    EXPECT_TRUE(s.occluded(Vec3(5.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, 1.0f), kInf));
    EXPECT_TRUE(hits(10.0f, kRayCamera));  // the other instance of the same prototype is visible
    EXPECT_TRUE(hits(10.0f, ray_mask(kRayGlossy)));
}

TEST(RayVisibility, LightsHiddenFromBounceTypesAsCycles) {
    const uint32_t no_diffuse = kRayAllVisibility & ~kRayDiffuse, no_glossy = kRayAllVisibility & ~kRayGlossy,
                   no_transmission = kRayAllVisibility & ~kRayTransmission;
    EXPECT_TRUE(light_hidden_from(no_diffuse, kRayDiffuse));
    EXPECT_TRUE(light_hidden_from(no_diffuse, kRayDiffuse | kRayTransmission));  // translucent: both
    EXPECT_FALSE(light_hidden_from(no_diffuse, kRayGlossy));
    EXPECT_TRUE(light_hidden_from(no_glossy, kRayGlossy));
    EXPECT_FALSE(light_hidden_from(no_glossy, kRayGlossy | kRayTransmission));  // glossy is reflection only
    EXPECT_TRUE(light_hidden_from(no_transmission, kRayGlossy | kRayTransmission));
    EXPECT_FALSE(light_hidden_from(no_transmission, kRayDiffuse));
    EXPECT_FALSE(light_hidden_from(kRayAllVisibility, kRayDiffuse));
}

TEST(RayVisibility, BounceTypesAndPerTypeLimits) {
    Bsdf bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
    Lobe diffuse_lobe;
    bsdf.add(diffuse_lobe);
    Lobe glossy_lobe;
    glossy_lobe.kind = LobeKind::Microfacet;
    glossy_lobe.alpha = 0.1f;
    bsdf.add(glossy_lobe);
    PathState st;
    EXPECT_EQ(st.ray_flags, uint32_t(kRayCamera));
    BsdfSample diffuse_bounce;
    diffuse_bounce.lobe = 0;
    advance_ray_type(st, bsdf, diffuse_bounce);
    EXPECT_EQ(st.ray_flags, uint32_t(kRayDiffuse));
    BsdfSample glossy_transmission;
    glossy_transmission.lobe = 1;
    glossy_transmission.transmission = true;
    advance_ray_type(st, bsdf, glossy_transmission);
    EXPECT_EQ(st.ray_flags, uint32_t(kRayGlossy | kRayTransmission));
    EXPECT_EQ(ray_mask(st.ray_flags), uint32_t(kRayTransmission));
    EXPECT_EQ(st.diffuse_bounces, 1);
    EXPECT_EQ(st.transmission_bounces, 1);
    EXPECT_EQ(st.glossy_bounces, 0);

    RenderSettings rs;
    st.depth = 2;
    EXPECT_FALSE(beyond_bounce_limits(rs, st));  // the defaults leave max_bounces alone in force
    rs.max_diffuse_bounces = 1;
    EXPECT_FALSE(beyond_bounce_limits(rs, st));  // one diffuse bounce made: its vertex is still shaded
    rs.max_diffuse_bounces = 0;
    EXPECT_TRUE(beyond_bounce_limits(rs, st));
    rs.max_diffuse_bounces = 1024;
    rs.max_transmission_bounces = 0;
    EXPECT_TRUE(beyond_bounce_limits(rs, st));
}

// Filter Glossy (Cycles' blur_glossy): the path's smallest non-Dirac BSDF density sets how far the
// microfacet lobes of the next vertices are roughened; Dirac bounces and camera rays blur nothing.
TEST(RayVisibility, FilterGlossyRaisesRoughnessAfterLowDensityBounces) {
    auto mirror_and_diffuse = [] {
        ShadingPoint sp;
        sp.bsdf = Bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
        Lobe mirror;
        mirror.kind = LobeKind::Microfacet;
        mirror.alpha = 0.0f;
        sp.bsdf.add(mirror);
        sp.bsdf.add(Lobe{});  // diffuse: never blurred
        return sp;
    };
    RenderSettings rs;
    rs.filter_glossy = 1.0f;
    PathState st;
    ShadingPoint seen_by_camera = mirror_and_diffuse();
    blur_glossy_lobes(rs, st, seen_by_camera);
    EXPECT_EQ(seen_by_camera.bsdf.lobe(0).alpha, 0.0f);

    Bsdf bsdf = mirror_and_diffuse().bsdf;
    BsdfSample dirac;
    dirac.lobe = 0;
    dirac.delta = true;
    dirac.pdf = 0.01f;
    advance_ray_type(st, bsdf, dirac);
    EXPECT_EQ(st.min_ray_pdf, kInf);
    BsdfSample diffuse_bounce;
    diffuse_bounce.lobe = 1;
    diffuse_bounce.pdf = 0.19f;
    advance_ray_type(st, bsdf, diffuse_bounce);
    BsdfSample sharper_bounce = diffuse_bounce;
    sharper_bounce.pdf = 40.0f;
    advance_ray_type(st, bsdf, sharper_bounce);
    EXPECT_EQ(st.min_ray_pdf, 0.19f);

    ShadingPoint after_diffuse = mirror_and_diffuse();
    EXPECT_TRUE(after_diffuse.bsdf.lobe_count() == 2 && !after_diffuse.bsdf.is_delta());
    blur_glossy_lobes(rs, st, after_diffuse);
    EXPECT_FLOAT_EQ(after_diffuse.bsdf.lobe(0).alpha, 0.5f * std::sqrt(1.0f - 0.19f));
    EXPECT_EQ(after_diffuse.bsdf.lobe(1).alpha, 0.0f);
    rs.filter_glossy = 0.1f;  // blur_pdf = 1.9: no blur
    ShadingPoint weak_filter = mirror_and_diffuse();
    blur_glossy_lobes(rs, st, weak_filter);
    EXPECT_EQ(weak_filter.bsdf.lobe(0).alpha, 0.0f);

    // A Dirac-only BSDF becomes rough: it then takes light samples.
    ShadingPoint only_mirror;
    only_mirror.bsdf = Bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
    Lobe glass;
    glass.kind = LobeKind::Dielectric;
    only_mirror.bsdf.add(glass);
    EXPECT_TRUE(only_mirror.bsdf.is_delta());
    rs.filter_glossy = 1.0f;
    blur_glossy_lobes(rs, st, only_mirror);
    EXPECT_FALSE(only_mirror.bsdf.is_delta());
}

TEST(RayVisibility, CamerasCastCameraRays) {
    Camera cam(camera_at(Vec3(0.0f), 8, 8));
    EXPECT_EQ(cam.generate_ray(4.0f, 4.0f).visibility, uint32_t(kRayCamera));
}

// Reflective or Refractive Caustics off: a glass lobe reached by a diffuse ray keeps the other half of
// Cycles' pair of closures; a smooth one then always takes that event, valued by its Fresnel share.
TEST(RayVisibility, OneCausticsToggleLeavesHalfTheGlass) {
    RenderSettings rs;
    rs.caustics_refractive = false;
    PathState after_diffuse;
    after_diffuse.ray_flags = kRayDiffuse;
    ShadingPoint sp;
    sp.bsdf = Bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
    Lobe glass;
    glass.kind = LobeKind::Dielectric;
    sp.bsdf.add(glass);
    drop_caustic_lobes(rs, after_diffuse, sp);
    ASSERT_EQ(sp.bsdf.lobe_count(), 1);
    EXPECT_EQ(sp.bsdf.lobe(0).glass_events, kGlassReflection);
    const Vec3 wo = normalize(Vec3(0.3f, 0.0f, 0.8f));
    const float F = fresnel_dielectric(wo.z, 1.5f);
    for (float u : {0.01f, 0.5f, 0.99f}) {
        BsdfSample s = lobe_sample(sp.bsdf.lobe(0), wo, Point2{0.5f, 0.5f}, u);
        ASSERT_TRUE(s.valid());
        EXPECT_FALSE(s.transmission);
        EXPECT_NEAR(s.value.x / s.pdf, F, 1e-6f);
    }
    rs.caustics_refractive = true;
    rs.caustics_reflective = false;
    ShadingPoint refracting = sp;
    refracting.bsdf = Bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
    refracting.bsdf.add(glass);
    drop_caustic_lobes(rs, after_diffuse, refracting);
    BsdfSample t = lobe_sample(refracting.bsdf.lobe(0), wo, Point2{0.5f, 0.5f}, 0.01f);
    ASSERT_TRUE(t.valid());
    EXPECT_TRUE(t.transmission);
    EXPECT_NEAR(t.value.x / t.pdf, (1.0f - F) / (1.5f * 1.5f), 1e-6f);
    PathState camera;  // camera rays keep the whole lobe
    ShadingPoint seen = sp;
    seen.bsdf = Bsdf(Frame(Vec3(0.0f, 0.0f, 1.0f)), Vec3(0.0f, 0.0f, 1.0f));
    seen.bsdf.add(glass);
    drop_caustic_lobes(rs, camera, seen);
    EXPECT_EQ(seen.bsdf.lobe(0).glass_events, kGlassBoth);
}
