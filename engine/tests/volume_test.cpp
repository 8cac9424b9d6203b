// Participating media: the phase function and distance sampling against their densities, transmittance
// and single scattering against quadrature, and the photon-plane estimators (West et al. 2020, §6)
// converging to the path tracer's image (independent renders, z-tests), with a power check and
// numerical stress cases (parallel and grazing planes, 1:1000 lights, extreme densities).
#include <cstring>

#include <gtest/gtest.h>

#include "integrators/path_tracing.h"
#include "integrators/photon_plane_set.h"
#include "integrators/volume.h"
#include "scene/spherical_rectangle.h"
#include "stats.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;
namespace st = smis::stats;

namespace {

Point2 rand2(Rng& rng) {
    float a = rng.next_float();
    return {a, rng.next_float()};
}

// The look-at camera of the volume scenes: at `pos`, looking along +Y.
CameraDesc camera_looking_y(const Vec3& pos, int w, int h, float lens) {
    CameraDesc c = camera_at(pos, w, h);
    c.to_world.m[1][1] = 0.0f, c.to_world.m[1][2] = -1.0f;
    c.to_world.m[2][1] = 1.0f, c.to_world.m[2][2] = 0.0f;
    c.lens = lens;
    return c;
}

// A rectangle light of size sx x sy at `pos`, emitting along -Z rotated by `tilt_x` radians about X.
LightDesc rect_light(const Vec3& pos, float sx, float sy, float power, float tilt_x = 0.0f) {
    LightDesc l;
    l.type = "AREA";
    l.shape = "RECTANGLE";
    // Invisible to the camera: the randomly covered edge pixels of a visible light would dominate
    // the image-level noise the convergence test relies on.
    l.visible_to_camera = false;
    l.size = sx;
    l.size_y = sy;
    l.power = power;
    float c = std::cos(tilt_x), s = std::sin(tilt_x);
    l.to_world.m[1][1] = c, l.to_world.m[1][2] = -s;
    l.to_world.m[2][1] = s, l.to_world.m[2][2] = c;
    l.to_world.m[0][3] = pos.x, l.to_world.m[1][3] = pos.y, l.to_world.m[2][3] = pos.z;
    return l;
}

Medium make_medium(const Color& sigma_a, const Color& sigma_s, float g = 0.0f) {
    Medium m;
    m.sigma_a = sigma_a;
    m.sigma_s = sigma_s;
    m.phase = HenyeyGreenstein(g);
    return m;
}

// Fig. 11 in miniature: a fog box (index-matched boundary) around a floor, a block and two
// rectangular lights, one of them 8:1; the camera looks in from outside.
std::shared_ptr<Scene> fog_box(int w, int h, const Medium& fog, std::vector<LightDesc> lights = {}) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    uint32_t fog_mat = add_medium_boundary(*s, fog);
    add_box(*s, {-1.5f, -1.5f, -0.2f}, {1.5f, 1.5f, 2.5f}, fog_mat);
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, white);
    add_box(*s, {-0.3f, 0.0f, 0.0f}, {0.3f, 0.5f, 0.8f}, white);
    if (lights.empty())
        lights = {rect_light({-0.5f, 0.2f, 2.0f}, 0.6f, 0.4f, 30.0f, 0.3f),
                  rect_light({0.7f, 0.6f, 1.6f}, 0.8f, 0.1f, 20.0f, -0.4f)};
    for (const LightDesc& l : lights) s->add_light(l);
    s->set_camera(camera_looking_y({0.0f, -3.5f, 1.0f}, w, h, 28.0f));
    s->commit();
    return s;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Sampling routines

TEST(Medium, HenyeyGreensteinSamplesMatchItsDensity) {
    const Vec3 wo = normalize(Vec3(0.3f, -0.4f, 0.8f));
    const float gs[] = {0.0f, 0.6f, -0.8f, 0.95f};
    double alpha = st::sidak_significance(0.01, 4);
    for (float g : gs) {
        HenyeyGreenstein hg(g);
        auto sample = [&](Rng& rng) {
            PhaseSample ps = hg.sample(wo, rand2(rng));
            return st::DirSample::valid(ps.wi, ps.pdf);
        };
        auto pdf = [&](const Vec3& wi) { return double(hg.pdf(wo, wi)); };
        st::Chi2Result r = st::chi2_test_directions(sample, pdf, 400000);
        std::printf("[chi2] HG g=%.2f %s\n", g, r.summary().c_str());
        EXPECT_TRUE(r.passes(alpha)) << "g " << g << ": " << r.summary();
        EXPECT_NEAR(r.pdf_integral, 1.0, 2e-3) << "g " << g;
    }
    // Cycles' sign convention: g > 0 scatters forward, i.e. towards wi = -wo.
    HenyeyGreenstein forward(0.6f);
    EXPECT_GT(forward.eval(wo, -wo), forward.eval(wo, wo));
}

TEST(Medium, SegmentDistanceSamplingIsUnbiasedForColouredMedia) {
    // E[g(t) / pdf(t)] = integral of g over the segment, for coloured sigma_t (one-sample spectral MIS),
    // including a clear channel and an infinite segment.
    struct Case {
        Color sigma_t;
        float len;
    } cases[] = {{{0.3f, 1.2f, 4.0f}, 2.0f}, {{0.0f, 0.5f, 2.0f}, 3.0f}, {{0.2f, 0.7f, 1.5f}, kInf}, {{1e-9f, 1e-9f, 1e-9f}, 1.0f}};
    for (const Case& c : cases) {
        // g(t) = exp(-t) t, integral over [0, len): 1 - (1 + len) e^-len.
        double expected = std::isinf(c.len) ? 1.0 : 1.0 - (1.0 + c.len) * std::exp(-double(c.len));
        st::MeanEstimator est;
        Rng rng(7, 11);
        for (int i = 0; i < 200000; ++i) {
            DistanceSample ds = sample_segment_distance(c.sigma_t, c.len, rng.next_float(), rng.next_float());
            if (ds.pdf > 0.0f) {
                EXPECT_NEAR(ds.pdf, segment_distance_pdf(c.sigma_t, c.len, ds.t), 1e-4f * ds.pdf);
                est.add(std::exp(-double(ds.t)) * ds.t / ds.pdf);
            } else {
                est.add(0.0);
            }
        }
        auto z = st::z_test_mean(est, expected);
        EXPECT_GT(z.p_value, 1e-3) << "sigma_t " << c.sigma_t.x << "," << c.sigma_t.y << "," << c.sigma_t.z
                                   << " len " << c.len << ": " << est.mean() << " vs " << expected;
    }
}

TEST(Medium, ChordThroughARectangle) {
    Chord c = chord_through(0.5f, 0.25f, 2.0f, 1.0f, 1.0f, 0.0f);
    EXPECT_NEAR(c.length(), 2.0f, 1e-6f);
    c = chord_through(0.5f, 0.25f, 2.0f, 1.0f, 0.0f, 1.0f);
    EXPECT_NEAR(c.length(), 1.0f, 1e-6f);
    float r = std::sqrt(0.5f);
    c = chord_through(0.5f, 0.5f, 1.0f, 1.0f, r, r);  // the diagonal of the unit square
    EXPECT_NEAR(c.length(), std::sqrt(2.0f), 1e-5f);
}

TEST(Medium, SphericalRectangleSamplesMatchItsSolidAngle) {
    // Directions towards the sampled points against the density 1 / solid angle on the rectangle's
    // directions; the chi-square's pdf integral checks the solid angle itself.
    struct Case {
        Vec3 ref, corner, u, v;
    } cases[] = {
        {{0.2f, -0.1f, 1.0f}, {-0.5f, -0.3f, 0.0f}, {1.2f, 0.0f, 0.0f}, {0.0f, 0.7f, 0.0f}},    // above, ~1.3 sr
        {{0.0f, 0.0f, 0.02f}, {-2.0f, -1.0f, 0.0f}, {3.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}},    // just above: ~2 pi
        {{1.5f, 0.4f, -0.05f}, {-0.4f, -0.4f, 0.0f}, {0.0f, 0.8f, 0.8f}, {0.6f, 0.0f, 0.0f}},   // tilted, below
    };
    double alpha = st::sidak_significance(0.01, 3);
    for (const Case& c : cases) {
        SphericalRectangle sr(c.ref, c.corner, c.u, c.v);
        ASSERT_GT(sr.solid_angle(), 0.0);
        Vec3 n = normalize(cross(c.u, c.v));
        auto sample = [&](Rng& rng) {
            return st::DirSample::valid(normalize(sr.sample(rand2(rng)) - c.ref), 1.0 / sr.solid_angle());
        };
        auto pdf = [&](const Vec3& wi) {
            float denom = dot(wi, n);
            if (std::fabs(denom) < 1e-9f) return 0.0;
            float t = dot(c.corner - c.ref, n) / denom;
            Vec3 q = c.ref + wi * t - c.corner;
            float a = dot(q, c.u) / length_sq(c.u), b = dot(q, c.v) / length_sq(c.v);
            return t > 0.0f && a >= 0.0f && a <= 1.0f && b >= 0.0f && b <= 1.0f ? 1.0 / sr.solid_angle() : 0.0;
        };
        // The rectangle's edges cut cells: finer first subdivisions find the thin slivers.
        st::Chi2Options opt;
        opt.integration.subdivisions = 16;
        st::Chi2Result r = st::chi2_test_directions(sample, pdf, 400000, opt);
        std::printf("[chi2] spherical rectangle (solid angle %.4f) %s\n", sr.solid_angle(), r.summary().c_str());
        EXPECT_TRUE(r.passes(alpha)) << r.summary();
        EXPECT_NEAR(r.pdf_integral, 1.0, 3e-3);
    }
    // Seen edge-on (the reference on the rectangle's plane): nothing to sample.
    EXPECT_EQ(SphericalRectangle({3.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}).solid_angle(), 0.0);
}

// ---------------------------------------------------------------------------------------------
// Transmittance and single scattering against quadrature

TEST(Medium, ShadowTransmittanceThroughABoxIsBeersLaw) {
    Medium fog = make_medium({0.1f, 0.2f, 0.3f}, {0.4f, 0.3f, 0.2f});
    auto scene = fog_box(8, 8, fog);
    // From outside, through the fog box above the floor and block: 3 m of fog along x at z = 1.8.
    Color tr = shadow_transmittance(*scene, {-3.0f, 0.7f, 2.3f}, {1.0f, 0.0f, 0.0f}, 6.0f, kNoMedium);
    Color expected = transmittance(fog.sigma_t(), 3.0f);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(tr[c], expected[c], 1e-4f);
    // Blocked by the floor.
    EXPECT_TRUE(is_black(shadow_transmittance(*scene, {0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, -1.0f}, 3.0f, 0)));
    EXPECT_EQ(scene->camera_medium(), kNoMedium);
    EXPECT_EQ(scene->medium_at({0.0f, 0.0f, 1.0f}), 0);
}

TEST(Medium, ShadowRaysThroughBoundaryPlanesMatchTheWalk) {
    // The shadow queries' shortcuts (a surfaces-only any-hit query, the boundary planes) against
    // the closest-hit walk through the boundaries itself (intersect_through), bit for bit: random
    // segments inside the fog box, out of it, blocked by the floor or the block, and ending within
    // the margin of a face. The fog box's planes are in use (six of them).
    Medium fog = make_medium({0.1f, 0.2f, 0.3f}, {0.4f, 0.3f, 0.2f});
    auto scene = fog_box(8, 8, fog);
    ASSERT_TRUE(scene->boundary_planes().usable());
    ASSERT_EQ(scene->boundary_planes().size(), 6u);
    Rng rng(7, 0);
    int blocked = 0, clear_inside = 0, crossing = 0;
    for (int i = 0; i < 4000; ++i) {
        auto point = [&](float pad) {
            return Vec3(-1.5f - pad + (3.0f + 2.0f * pad) * rng.next_float(), -1.5f - pad + (3.0f + 2.0f * pad) * rng.next_float(),
                        -0.2f - pad + (2.7f + 2.0f * pad) * rng.next_float());
        };
        Vec3 a = point(0.5f), b = point(i % 4 == 0 ? 0.0f : 0.5f);
        if (i % 7 == 0) b.x = 1.5f - 2e-4f * rng.next_float();  // within the margin of the face x = 1.5
        const Vec3 d = b - a;
        const float len = length(d);
        if (!(len > 1e-3f)) continue;
        const Vec3 dir = d / len;
        const int32_t medium = scene->medium_at(a);
        SurfaceHit hit;
        RayMedia media;
        const bool hits = intersect_through(*scene, Ray{a, dir, 0.0f, len, kShutterCentre, kRayShadow}, medium, &hit, &media);
        const Color expected = hits ? Color(0.0f) : media.transmittance_to_end();
        const Color tr = shadow_transmittance(*scene, a, dir, len, medium);
        for (int c = 0; c < 3; ++c) ASSERT_EQ(tr[c], expected[c]) << "segment " << i << " channel " << c;
        RayMedia shadow;
        ASSERT_EQ(shadow_media(*scene, a, dir, len, medium, &shadow), !hits) << "segment " << i;
        if (!hits) {
            const Color from_media = shadow.transmittance_to_end();
            for (int c = 0; c < 3; ++c) ASSERT_EQ(from_media[c], expected[c]) << "segment " << i;
        }
        blocked += hits;
        const bool inside = media.count == 1 && media.seg[0].t0 == 0.0f && media.seg[0].t1 == len;
        clear_inside += !hits && inside;
        crossing += !hits && !inside;
    }
    // Every kind of segment was met often.
    EXPECT_GT(blocked, 200);
    EXPECT_GT(clear_inside, 200);
    EXPECT_GT(crossing, 200);
}

namespace {

// The single-scattering estimator's mean along `ray` against a fine quadrature (midpoint rule) of
//   int T(0, t) sigma_s rho(t) L_light(t) T(t, light) dt
// over the ray's one medium segment (cut at t_far for an infinite one), for a point light.
void expect_single_scattering_matches_quadrature(const Scene& scene, const Ray& ray, int32_t start_medium,
                                                 float t_far) {
    const Light& light = scene.light(0);
    RayMedia media;
    SurfaceHit hit;
    intersect_through(scene, ray, start_medium, &hit, &media);
    ASSERT_EQ(media.count, 1);
    const auto seg = media.seg[0];
    const Medium& med = scene.medium(seg.medium);
    const int n = 200000;
    const float t1 = std::min(seg.t1, t_far);
    Color expected(0.0f);
    double dt = double(t1 - seg.t0) / n;
    for (int i = 0; i < n; ++i) {
        float t = seg.t0 + float((i + 0.5) * dt);
        Vec3 x = ray.o + ray.d * t;
        LightSample ls = light.sample(x, {0.5f, 0.5f});
        Color tr = shadow_transmittance(scene, x, ls.wi, ls.dist, seg.medium);
        expected += transmittance(med.sigma_t(), t - seg.t0) * med.sigma_s * tr * ls.L *
                    float(med.phase.eval(-ray.d, ls.wi) * dt);
    }
    st::MeanEstimator est[3];
    LocalCounters counters;
    for (int i = 0; i < 200000; ++i) {
        Rng rng(3, i);
        Color L = single_scattering(scene, ray, media, rng, counters);
        for (int c = 0; c < 3; ++c) est[c].add(L[c]);
    }
    for (int c = 0; c < 3; ++c) {
        auto z = st::z_test_mean(est[c], expected[c]);
        std::printf("single scattering channel %d: %.6f +- %.6f, quadrature %.6f\n", c, est[c].mean(),
                    est[c].std_error(), expected[c]);
        EXPECT_GT(z.p_value, st::sidak_significance(0.01, 3)) << "channel " << c;
        EXPECT_LT(est[c].std_error(), 0.01 * expected[c]);  // the test has power at 1%
    }
    EXPECT_EQ(counters.samples_rejected, 0u);
}

LightDesc point_light(const Vec3& p, float power) {
    LightDesc l;
    l.type = "POINT";
    l.power = power;
    l.color = Color(1.0f, 0.9f, 0.8f);
    l.to_world.m[0][3] = p.x, l.to_world.m[1][3] = p.y, l.to_world.m[2][3] = p.z;
    return l;
}

}  // namespace

TEST(Medium, SingleScatteringMatchesQuadrature) {
    // A ray through the fog box (entered through its index-matched boundary), a point light inside.
    Medium fog = make_medium({0.15f, 0.05f, 0.3f}, {0.5f, 0.3f, 0.1f}, 0.4f);
    auto scene = fog_box(8, 8, fog, {point_light({0.3f, 0.4f, 1.9f}, 50.0f)});
    expect_single_scattering_matches_quadrature(*scene, Ray{{-3.0f, 0.0f, 1.5f}, normalize(Vec3(1.0f, 0.1f, 0.0f)), 0.0f, kInf},
                                                kNoMedium, kInf);
}

TEST(Medium, WorldVolumeSingleScatteringMatchesQuadrature) {
    // The world's volume fills space: the ray's segment is infinite (the integrand decays with
    // transmittance; the quadrature stops where it is below 1e-6 of its peak).
    auto s = std::make_shared<Scene>();
    s->set_world_medium(s->add_medium(make_medium({0.1f, 0.2f, 0.05f}, {0.4f, 0.2f, 0.3f}, -0.3f)));
    s->add_light(point_light({0.5f, 2.0f, 0.3f}, 40.0f));
    s->set_camera(camera_looking_y({0.0f, 0.0f, 0.0f}, 8, 8, 30.0f));
    s->commit();
    EXPECT_TRUE(s->has_media());
    EXPECT_EQ(s->camera_medium(), s->world_medium());
    expect_single_scattering_matches_quadrature(*s, Ray{{0.0f, 0.0f, 0.0f}, normalize(Vec3(0.1f, 1.0f, 0.05f)), 0.0f, kInf},
                                                s->world_medium(), 60.0f);
}

namespace {

// Single-scattering samples along one ray through the fog box, with rectangles sampled either way.
st::MeanEstimator single_scattering_samples(const Scene& scene, const Ray& ray, RectangleSampling rectangles, int n,
                                            uint64_t seed, double* max_sample = nullptr) {
    RayMedia media;
    SurfaceHit hit;
    intersect_through(scene, ray, kNoMedium, &hit, &media);
    st::MeanEstimator est;
    LocalCounters counters;
    double max_value = 0.0;
    for (int i = 0; i < n; ++i) {
        Rng rng(seed, i);
        double v = single_scattering(scene, ray, media, rng, counters, false, rectangles).y;
        est.add(v);
        max_value = std::max(max_value, v);
    }
    if (max_sample) *max_sample = max_value;
    return est;
}

// Rays of fog_box's camera: through the 0.6 x 0.4 light, just under it (its lit side), past the
// 8:1 light's end, and through open fog.
const Vec3 kFogCamera{0.0f, -3.5f, 1.0f};
const Vec3 kFogTargets[] = {{-0.45f, 0.25f, 2.02f}, {-0.5f, 0.2f, 1.85f}, {1.05f, 0.6f, 1.5f}, {0.3f, 0.0f, 1.0f}};


// Single scattering of every light along `ray` by quadrature: the midpoint rule in t over the ray's
// one medium segment, and per point the light integral from 16 x 16 stratified solid-angle samples
// of each rectangle (the sampler is checked on its own by the chi-square above) with their shadow
// rays, and the one direction of each delta light (point, spot, sun). For an isotropic phase function the integrand over a light is L T(shadow), nearly constant.
Color single_scattering_quadrature(const Scene& scene, const Ray& ray, int nt) {
    RayMedia media;
    SurfaceHit hit;
    intersect_through(scene, ray, kNoMedium, &hit, &media);
    const auto seg = media.seg[0];
    const Medium& med = scene.medium(seg.medium);
    Color sum(0.0f);
    double dt = double(seg.t1 - seg.t0) / nt;
    for (int i = 0; i < nt; ++i) {
        float t = seg.t0 + float((i + 0.5) * dt);
        Vec3 x = ray.o + ray.d * t;
        Color in(0.0f);
        for (const auto& light : scene.lights()) {
            if (light->is_delta()) {  // a point, spot or sun: one direction
                LightSample ls = light->sample(x, {0.5f, 0.5f});
                if (!ls.valid()) continue;
                float tmax = std::isinf(ls.dist) ? kInf : ls.dist * (1.0f - 1e-4f);
                in += shadow_transmittance(scene, x, ls.wi, tmax, seg.medium) * ls.L * float(med.phase.eval(-ray.d, ls.wi));
                continue;
            }
            LightRectangle rect;
            if (!light->rectangle(&rect) || !(dot(x - rect.corner, rect.normal) > 0.0f)) continue;
            SphericalRectangle sr(x, rect.corner, rect.u, rect.v);
            const int k = 16;
            for (int a = 0; a < k; ++a)
                for (int b = 0; b < k; ++b) {
                    Vec3 d = sr.sample({(a + 0.5f) / k, (b + 0.5f) / k}) - x;
                    float dist = length(d);
                    Color tr = shadow_transmittance(scene, x, d / dist, dist * (1.0f - 1e-4f), seg.medium);
                    in += tr * rect.radiance *
                          float(med.phase.eval(-ray.d, d / dist) * sr.solid_angle() / (k * k));
                }
        }
        sum += transmittance(med.sigma_t(), t - seg.t0) * med.sigma_s * in * float(dt);
    }
    return sum;
}

}  // namespace

TEST(Medium, SolidAngleRectangleSamplingConvergesWithLessVariance) {
    // On each ray the single-scattering mean with rectangles sampled by solid angle (and equiangular
    // sampling towards an independent light point) agrees with quadrature. The previous estimator
    // (area sampling, equiangular towards the connected point) has the same mean but heavy-tailed
    // weights A cos / r^2 (1/h after equiangular sampling) on rays through or near a light; the new
    // weights are bounded.
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(8, 8, fog);
    const int n = 200000;
    double alpha = st::sidak_significance(0.01, 2 * 4);
    double variance_new = 0.0, variance_old = 0.0;
    for (const Vec3& target : kFogTargets) {
        Ray ray{kFogCamera, normalize(target - kFogCamera), 0.0f, kInf};
        double expected = single_scattering_quadrature(*scene, ray, 2000).y;
        double max_new, max_old;
        st::MeanEstimator fresh = single_scattering_samples(*scene, ray, RectangleSampling::kSolidAngle, n, 5, &max_new);
        st::MeanEstimator old = single_scattering_samples(*scene, ray, RectangleSampling::kArea, n, 6, &max_old);
        auto z_new = st::z_test_mean(fresh, expected), z_old = st::z_test_mean(old, expected);
        std::printf("ray to (%.2f %.2f %.2f): quadrature %.5f; solid angle %.5f +- %.5f (z %.2f, var %.4g, max %.3g); "
                    "area %.5f +- %.5f (z %.2f, var %.4g, max %.3g)\n",
                    target.x, target.y, target.z, expected, fresh.mean(), fresh.std_error(), z_new.z, fresh.variance(),
                    max_new, old.mean(), old.std_error(), z_old.z, old.variance(), max_old);
        EXPECT_GT(z_new.p_value, alpha);
        EXPECT_GT(z_old.p_value, alpha);
        EXPECT_LT(fresh.std_error(), 0.025 * expected);  // the test has power at ~5%
        variance_new += fresh.variance() / (expected * expected);
        variance_old += old.variance() / (expected * expected);
    }
    std::printf("summed relative variance: solid angle %.4g, area %.4g (ratio %.4f)\n", variance_new, variance_old,
                variance_new / variance_old);
    EXPECT_LT(variance_new, 0.1 * variance_old);
}

TEST(Medium, PathSampleHandsItsCameraRayMediaToThePlaneGather) {
    // The photon planes' gather takes its camera ray's media segments from the first path sample,
    // which has just traced that ray (LocalCounters::camera_media), instead of tracing it again: they
    // must be intersect_through's for that ray bit for bit (so the image is the one the gather gave
    // tracing the ray itself), whatever the path traces after its first segment (bounces in and out
    // of the fog trace more rays with media).
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(8, 8, fog);
    RenderSettings settings;
    settings.max_bounces = 4;
    Rng dirs(3, 0);
    int crossed = 0, hits = 0;
    for (int i = 0; i < 400; ++i) {
        // Every second ray aims at the floor (or the block in front of it): those bounce on.
        const float z = i % 2 ? 0.0f : -0.1f + 2.8f * dirs.next_float();
        const Vec3 target(-1.6f + 3.2f * dirs.next_float(), -1.4f + 2.8f * dirs.next_float(), z);
        const Ray ray{kFogCamera, normalize(target - kFogCamera), 0.0f, kInf};
        RayMedia shared, own;
        shared.count = -1;
        LocalCounters local;
        local.camera_media = &shared;
        PathState state = camera_path_state(ray.o);
        state.medium = scene->camera_medium();
        Rng rng(17, uint64_t(i));
        trace_path(*scene, settings, ray, state, rng, local);
        ASSERT_EQ(local.camera_media, nullptr) << "ray " << i;
        SurfaceHit hit;
        hits += intersect_through(*scene, ray, scene->camera_medium(), &hit, &own);
        ASSERT_EQ(shared.count, own.count) << "ray " << i;
        for (int k = 0; k < own.count; ++k) {
            EXPECT_EQ(std::memcmp(&shared.seg[k].t0, &own.seg[k].t0, sizeof(float)), 0) << "ray " << i;
            EXPECT_EQ(std::memcmp(&shared.seg[k].t1, &own.seg[k].t1, sizeof(float)), 0) << "ray " << i;
            EXPECT_EQ(shared.seg[k].medium, own.seg[k].medium) << "ray " << i;
        }
        EXPECT_EQ(shared.end_medium, own.end_medium) << "ray " << i;
        EXPECT_EQ(std::memcmp(&shared.tau_end, &own.tau_end, sizeof(Color)), 0) << "ray " << i;
        EXPECT_EQ(shared.crossed, own.crossed) << "ray " << i;
        crossed += own.count > 0;
    }
    // Most rays cross the fog, and most of those hit the floor or the block (and bounce on).
    EXPECT_GT(crossed, 300);
    EXPECT_GT(hits, 150);
}

// ---------------------------------------------------------------------------------------------
// Photon planes against the path tracer

namespace {

constexpr int kW = 24, kH = 24, kBlock = 4;

// Per 4x4-block means of the green channel over K independent renders, and the whole image's mean.
struct BlockStats {
    std::vector<st::MeanEstimator> blocks;
    st::MeanEstimator image;
};

BlockStats across_renders(const std::shared_ptr<Scene>& scene, const std::string& estimator, int renders,
                          uint32_t samples, uint32_t seed0, float scale = 1.0f, int smis_planes = 2,
                          uint32_t plane_shadow_rays = 0, uint32_t plane_surface_samples = 0,
                          bool plane_stratified = true, float plane_min_crossings = 0.0f,
                          float plane_min_light_crossings = 0.0f, uint32_t plane_pilot_stride = 2,
                          uint32_t plane_path_pixel_samples = 1) {
    BlockStats bs;
    bs.blocks.resize((kW / kBlock) * (kH / kBlock));
    for (int r = 0; r < renders; ++r) {
        RenderSettings s;
        s.volume_estimator = setting_value<VolumeEstimator>(estimator);
        s.samples = samples;
        s.seed = seed0 + r;
        s.max_bounces = 0;
        s.photon_planes = 2048;
        s.smis_planes = smis_planes;
        s.plane_shadow_rays = plane_shadow_rays;
        s.plane_surface_samples = plane_surface_samples;
        s.plane_stratified = plane_stratified;
        s.plane_min_crossings = plane_min_crossings;
        s.plane_min_light_crossings = plane_min_light_crossings;
        s.plane_pilot_stride = plane_pilot_stride;
        s.plane_path_pixel_samples = plane_path_pixel_samples;
        s.filter = PixelFilterKind::Box;
        s.filter_width = 1.0f;
        auto img = render(scene, s);
        std::vector<double> sum(bs.blocks.size(), 0.0);
        for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) sum[(y / kBlock) * (kW / kBlock) + x / kBlock] += img[4 * (y * kW + x) + 1];
        double total = 0.0;
        for (size_t b = 0; b < sum.size(); ++b) {
            bs.blocks[b].add(scale * sum[b] / (kBlock * kBlock));
            total += scale * sum[b];
        }
        bs.image.add(total / (kW * kH));
    }
    return bs;
}

// Blocks (and the whole image, counted as one more) whose means differ significantly, Šidák over
// them and `family` comparisons.
int disagreeing_blocks(const BlockStats& a, const BlockStats& ref, int family) {
    double alpha = st::sidak_significance(0.01, (int(a.blocks.size()) + 1) * family);
    int bad = st::z_test_difference(a.image, ref.image, 1e-7).p_value < alpha;
    for (size_t b = 0; b < a.blocks.size(); ++b)
        bad += st::z_test_difference(a.blocks[b], ref.blocks[b], 1e-7).p_value < alpha;
    return bad;
}

}  // namespace

namespace {

// fog_box's two rectangles with a bright point light behind the block (volume_slit's trap: most of
// the power, occluded from much of the fog), a spot, a rectangle near the top facing up (most of the
// box behind it) and a sun.
std::shared_ptr<Scene> fog_box_mixed_lights(const Medium& fog) {
    LightDesc spot = point_light({0.6f, -0.4f, 2.2f}, 40.0f);
    spot.type = "SPOT";
    spot.spot_size = 0.8f;
    spot.spot_blend = 0.3f;
    LightDesc sun;
    sun.type = "SUN";
    sun.strength = 0.5f;
    sun.to_world.m[0][2] = 0.3f;  // -Z of the light tilted: sunlight from above, a little sideways
    return fog_box(8, 8, fog,
                   {rect_light({-0.5f, 0.2f, 2.0f}, 0.6f, 0.4f, 30.0f, 0.3f),
                    rect_light({0.7f, 0.6f, 1.6f}, 0.8f, 0.1f, 20.0f, -0.4f), point_light({0.0f, 1.2f, 0.4f}, 400.0f),
                    spot, rect_light({-1.2f, -1.2f, 2.4f}, 0.3f, 0.3f, 25.0f, kPi), sun});
}

}  // namespace

TEST(Medium, SegmentLightChoiceIsANormalisedPmfWithADefensiveFloor) {
    // For segments of every kind (inside the box, through it, infinite, starting behind a one-sided
    // light), the per-segment choice: sums to 1 over the lights that may light media, gives each at
    // least the defensive floor (a power / P + b / n), chooses each light with the probability it
    // reports (stratified u: the share of u choosing a light equals its pmf to 1 / K), and leaves
    // out rectangles and points with skip_plane_lights. With more lights than the segment part
    // handles, (power + uniform) / 2.
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box_mixed_lights(fog);
    const MediaLightChoice& choice = scene->media_lights();
    const uint32_t n = uint32_t(scene->lights().size());
    Rng rng(17, 3);
    const int K = 20000;
    for (int trial = 0; trial < 40; ++trial) {
        Vec3 o(4.0f * rng.next_float() - 2.0f, 4.0f * rng.next_float() - 2.0f, 3.0f * rng.next_float() - 0.3f);
        Vec3 d = sample_uniform_sphere(rand2(rng));
        float len = trial % 4 == 0 ? kInf : 5.0f * rng.next_float();
        for (bool skip : {false, true}) {
            MediaLightChoice::Segment seg{o, d, len, trial % 3 == 0 ? 0.0f : 0.4f, skip};
            std::vector<int> hits(n, 0);
            for (int k = 0; k < K; ++k) {
                uint32_t li;
                float pmf;
                ASSERT_TRUE(choice.sample(seg, (k + 0.5f) / K, &li, &pmf));
                ASSERT_EQ(pmf, choice.pmf(seg, li));
                ++hits[li];
            }
            double sum = 0.0, power_sum = 0.0;
            int eligible = 0;
            for (uint32_t i = 0; i < n; ++i) {
                const Light& l = scene->light(i);
                bool plane_light = l.rectangle(nullptr) || l.point(nullptr);
                if (!(skip && plane_light)) ++eligible, power_sum += scene->light_power_pmf(i);
            }
            for (uint32_t i = 0; i < n; ++i) {
                const Light& l = scene->light(i);
                const float p = choice.pmf(seg, i);
                sum += p;
                EXPECT_NEAR(double(hits[i]) / K, p, 2.0 / K) << "trial " << trial << " light " << i;
                if (skip && (l.rectangle(nullptr) || l.point(nullptr))) {
                    EXPECT_EQ(p, 0.0f);
                } else {
                    double floor = MediaLightChoice::kPowerWeight * scene->light_power_pmf(i) / power_sum +
                                   MediaLightChoice::kUniformWeight / eligible;
                    EXPECT_GE(p, 0.999 * floor) << "trial " << trial << " light " << i;
                }
            }
            EXPECT_NEAR(sum, 1.0, 1e-5);
        }
    }
    // Many lights: the defensive mixture alone, still what sample() reports.
    std::vector<LightDesc> many;
    for (int i = 0; i < MediaLightChoice::kMaxSegmentLights + 8; ++i)
        many.push_back(point_light({-1.0f + 0.05f * i, 0.5f, 1.5f}, 1.0f + float(i)));
    auto crowd = fog_box(8, 8, fog, many);
    MediaLightChoice::Segment seg{{0.0f, -1.4f, 1.0f}, {0.0f, 1.0f, 0.0f}, 2.8f, 0.3f, false};
    double power_total = 0.0;
    for (size_t i = 0; i < many.size(); ++i) power_total += crowd->light_power_pmf(uint32_t(i));
    double sum = 0.0;
    for (uint32_t i = 0; i < many.size(); ++i) {
        float p = crowd->media_lights().pmf(seg, i);
        EXPECT_NEAR(p, 0.5 * (crowd->light_power_pmf(i) / power_total + 1.0 / many.size()), 1e-6);
        sum += p;
    }
    EXPECT_NEAR(sum, 1.0, 1e-5);
    for (int k = 0; k < 100; ++k) {
        uint32_t li;
        float pmf;
        ASSERT_TRUE(crowd->media_lights().sample(seg, (k + 0.5f) / 100.0f, &li, &pmf));
        EXPECT_EQ(pmf, crowd->media_lights().pmf(seg, li));
    }
}

TEST(Medium, SegmentLightChoiceSingleScatteringMatchesQuadrature) {
    // Single scattering with the per-segment light choice (rectangles, one facing away, a bright
    // point light behind the block, a spot and a sun) agrees with quadrature on each of fog_box's
    // rays. (Checked red: dividing by the power-based pmf instead of the chosen light's segment pmf,
    // every ray disagrees.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f}, 0.3f);
    auto scene = fog_box_mixed_lights(fog);
    const int n = 100000;
    double alpha = st::sidak_significance(0.01, 4);
    for (const Vec3& target : kFogTargets) {
        Ray ray{kFogCamera, normalize(target - kFogCamera), 0.0f, kInf};
        double expected = single_scattering_quadrature(*scene, ray, 2000).y;
        st::MeanEstimator est = single_scattering_samples(*scene, ray, RectangleSampling::kSolidAngle, n, 9);
        auto z = st::z_test_mean(est, expected);
        std::printf("mixed lights, ray to (%.2f %.2f %.2f): quadrature %.5f; single scattering %.5f +- %.5f (z %.2f, "
                    "relative variance %.4g)\n",
                    target.x, target.y, target.z, expected, est.mean(), est.std_error(), z.z,
                    est.variance() / (expected * expected));
        EXPECT_GT(z.p_value, alpha);
        EXPECT_LT(est.std_error(), 0.02 * expected);  // the test has power at ~5%
    }
}

TEST(PhotonPlanes, AllEstimatorsConvergeToThePathTracer) {
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(kW, kH, fog);
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    const char* estimators[] = {"PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_COS", "PLANES_SMIS_EXACT"};
    for (const char* e : estimators) {
        BlockStats planes = across_renders(scene, e, 16, 8, 2200);
        int bad = disagreeing_blocks(planes, ref, 4);
        double rel_se = 0;
        for (size_t b = 0; b < planes.blocks.size(); ++b)
            rel_se += planes.blocks[b].std_error() / std::max(1e-9, planes.blocks[b].mean());
        std::printf("%-18s image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks disagreeing: %d of %zu + image "
                    "(mean relative standard error of a block %.4f)\n",
                    e, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad,
                    planes.blocks.size(), rel_se / planes.blocks.size());
        EXPECT_EQ(bad, 0) << e;
    }
    // n = 3 orientations: the partners come from rotating by pi / 3 twice.
    BlockStats three = across_renders(scene, "PLANES_SMIS_EXACT", 16, 8, 300, 1.0f, 3);
    int bad3 = disagreeing_blocks(three, ref, 4);
    std::printf("PLANES_SMIS_EXACT n=3: image mean %.5f +- %.5f, blocks disagreeing %d\n", three.image.mean(),
                three.image.std_error(), bad3);
    EXPECT_EQ(bad3, 0);
    // Power: a 5% error (e.g. a lost factor in a weight) on the best estimator must be detected.
    BlockStats scaled = across_renders(scene, "PLANES_SMIS_EXACT", 16, 8, 200, 0.95f);
    int detected = disagreeing_blocks(scaled, ref, 4);
    std::printf("5%% scaled SMIS_EXACT: %d blocks (or the image) disagree, image z = %.2f\n", detected,
                st::z_test_difference(scaled.image, ref.image).z);
    EXPECT_GT(detected, 0);
}

TEST(PhotonPlanes, SurfaceSamplesPerPlaneSetConvergeToThePathTracer) {
    // One plane set serves M path samples per pixel: the path tracer's part is their mean, the
    // planes' part is gathered once and not divided. M = 1 (one path sample per plane set, as before)
    // and M = 6 must both agree with PATH. (Checked red: summing the M path samples instead of
    // averaging them makes 17 of the 37 comparisons disagree at M = 6, the image mean 2.4x PATH's.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(kW, kH, fog);
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    for (uint32_t m : {1u, 6u}) {
        BlockStats planes = across_renders(scene, "PLANES_SMIS_EXACT", 16, 8, 2700 + m, 1.0f, 2, 0, m);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("PLANES_SMIS_EXACT, M = %u: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks disagreeing %d\n",
                    m, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        EXPECT_EQ(bad, 0) << m;
    }
}

TEST(PhotonPlanes, RussianRouletteOnVisibilityConvergesToThePathTracer) {
    // About K shadow rays per camera ray's segment instead of one per crossing (hundreds), chosen by
    // unshadowed contribution and divided by their probability: the occluding block's shadow in the
    // fog must survive, and so must the image mean. The z-tests estimate each block's variance from
    // the renders: 48 renders of 3 samples (about the cost of 16 of 8) keep that estimate, and with
    // it the test's false alarms at the nominal 1% where 16 renders' heavy-tailed block means
    // (Student's t with 15 degrees of freedom tested as a normal) raised them well above it.
    // (Checked red: without the 1/q, 26 and 17 of the 37 comparisons disagree, the image mean at
    // 0.33x and 0.48x PATH's.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(kW, kH, fog);
    BlockStats ref = across_renders(scene, "PATH", 32, 512, 2100);
    for (uint32_t k : {1u, 8u}) {
        BlockStats rr = across_renders(scene, "PLANES_SMIS_EXACT", 48, 3, 2600 + 100 * k, 1.0f, 2, k);
        int bad = disagreeing_blocks(rr, ref, 2);
        std::printf("PLANES_SMIS_EXACT, K = %u: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks disagreeing %d\n",
                    k, rr.image.mean(), rr.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        EXPECT_EQ(bad, 0) << k;
    }
}

TEST(PhotonPlanes, WorldVolumeBeyondTheGeometryConvergesToThePathTracer) {
    // A World volume, a small floor under a light that faces the camera, the camera five units away:
    // most of the single scattering the camera sees happens far outside the geometry's bounding
    // sphere, and on rays that leave the scene. The planes must sweep that far (checked red: swept
    // to the geometry's bounding sphere around the light's centre, the planes read 0.31x PATH, every
    // block disagreeing).
    auto s = std::make_shared<Scene>();
    s->set_world_medium(s->add_medium(make_medium({0.02f, 0.03f, 0.04f}, {0.15f, 0.12f, 0.1f})));
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    add_box(*s, {-0.5f, -0.5f, -0.1f}, {0.5f, 0.5f, 0.0f}, white);
    s->add_light(rect_light({0.0f, 0.3f, 0.8f}, 0.6f, 0.4f, 30.0f, -1.2f));
    s->set_camera(camera_looking_y({0.0f, -5.0f, 0.5f}, kW, kH, 28.0f));
    s->commit();
    BlockStats ref = across_renders(s, "PATH", 16, 256, 2100);
    for (const char* e : {"PLANES_UNWEIGHTED", "PLANES_SMIS_EXACT"}) {
        BlockStats planes = across_renders(s, e, 24, 8, 2200);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("%-18s world volume: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks disagreeing: %d\n", e,
                    planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        EXPECT_EQ(bad, 0) << e;
    }
}

TEST(PhotonPlanes, PointAndSpotLightPlanesConvergeToThePathTracer) {
    // Planes through a point light with uniform normals, weighted by the closed-form density of
    // their crossing (photon_planes.cpp): a spot light (cone falloff and blend) and a point light in
    // one fog box, each light's planes drawn by power from one set. (Checked red: without the spot's
    // falloff in the planes' weight, all 37 comparisons disagree, the image mean 4.3x PATH's.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f}, 0.5f);
    LightDesc spot = point_light({-0.4f, 0.3f, 2.0f}, 60.0f);
    spot.type = "SPOT";
    spot.spot_size = 1.0f;  // radians; pointing down (-Z of the identity transform)
    spot.spot_blend = 0.4f;
    auto scene = fog_box(kW, kH, fog, {spot, point_light({0.7f, 0.6f, 1.2f}, 15.0f)});
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    for (const char* e : {"PLANES_UNWEIGHTED", "PLANES_SMIS_EXACT"}) {
        BlockStats planes = across_renders(scene, e, 16, 8, 2300);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("%-18s point and spot lights: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks disagreeing: %d\n",
                    e, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        for (size_t b = 0; b < planes.blocks.size(); ++b) {
            double z = st::z_test_difference(planes.blocks[b], ref.blocks[b], 1e-7).z;
            if (std::fabs(z) > 3.0)
                std::printf("  block %zu: %.5f +- %.5f against %.5f +- %.5f, z %.2f\n", b, planes.blocks[b].mean(),
                            planes.blocks[b].std_error(), ref.blocks[b].mean(), ref.blocks[b].std_error(), z);
        }
        EXPECT_EQ(bad, 0) << e;
    }
}

TEST(PhotonPlanes, StratifiedPlaneSetsConvergeToThePathTracer) {
    // Plane sets drawn from Owen-scrambled Sobol points (PlaneSequence) instead of independent
    // numbers: every plane alone keeps its distribution, so the image must still agree with PATH,
    // here with rectangles, a point light and a spot drawing from one set, stratified and not. The
    // variance of these 4x4-pixel blocks is printed, not tested: averaged over 16 pixels it hardly
    // changes (0.54 either way), the gain is per pixel (SMAPE on volume_spot, README). (Checked red:
    // the stratified light choice scaled by 0.9, 0.9 light_u(i), makes 19 of the 37
    // comparisons disagree.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f}, 0.3f);
    LightDesc spot = point_light({-0.4f, 0.3f, 2.0f}, 60.0f);
    spot.type = "SPOT";
    spot.spot_size = 1.0f;
    spot.spot_blend = 0.4f;
    auto scene = fog_box(kW, kH, fog,
                         {rect_light({-0.5f, 0.2f, 2.0f}, 0.6f, 0.4f, 30.0f, 0.3f), spot,
                          point_light({0.7f, 0.6f, 1.2f}, 15.0f)});
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    double variance[2] = {0.0, 0.0};
    for (bool stratified : {true, false}) {
        BlockStats planes = across_renders(scene, "PLANES_SMIS_EXACT", 24, 4, 2900, 1.0f, 2, 0, 1, stratified);
        int bad = disagreeing_blocks(planes, ref, 2);
        for (const st::MeanEstimator& b : planes.blocks) variance[stratified] += b.variance() / (b.mean() * b.mean());
        std::printf("PLANES_SMIS_EXACT, %s plane sets: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks "
                    "disagreeing %d; summed relative variance of the blocks %.4g\n",
                    stratified ? "stratified" : "independent", planes.image.mean(), planes.image.std_error(),
                    ref.image.mean(), ref.image.std_error(), bad, variance[stratified]);
        EXPECT_EQ(bad, 0) << stratified;
    }
}

namespace {

// The integrator's statistics after one iteration of 2048 planes with the segment partition's settings.
std::map<std::string, double> partition_stats(const std::shared_ptr<Scene>& scene, float min_crossings,
                                              float min_light_crossings, uint32_t pilot_stride = 2,
                                              uint32_t path_pixel_samples = 1) {
    RenderSettings probe;
    probe.volume_estimator = VolumeEstimator::PlanesSmisExact;
    probe.samples = 1;
    probe.max_bounces = 0;
    probe.photon_planes = 2048;
    probe.plane_min_crossings = min_crossings;
    probe.plane_min_light_crossings = min_light_crossings;
    probe.plane_pilot_stride = pilot_stride;
    probe.plane_path_pixel_samples = path_pixel_samples;
    RenderSession session(scene, probe);
    session.run();
    return session.integrator_stats();
}

// fog_box's two rectangles and a dim point light: the partitions' scene.
std::shared_ptr<Scene> three_light_fog_box() {
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    return fog_box(kW, kH, fog,
                   {rect_light({-0.5f, 0.2f, 2.0f}, 0.6f, 0.4f, 30.0f, 0.3f),
                    rect_light({0.7f, 0.6f, 1.6f}, 0.8f, 0.1f, 20.0f, -0.4f), point_light({0.7f, 0.6f, 1.2f}, 4.0f)});
}

// Both partitions on `scene` (pilot stride 3) against PATH, with one path sample per plane set and
// with M = 4: no block may disagree.
void expect_both_partitions_match_path(const std::shared_ptr<Scene>& scene, uint32_t seed0, uint32_t path_pixel_samples,
                                       const char* label) {
    constexpr float kMinCrossings = 12.0f, kMinLightCrossings = 20.0f;
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    for (uint32_t m : {1u, 4u}) {
        BlockStats planes = across_renders(scene, "PLANES_SMIS_EXACT", 24, 4, seed0 + m, 1.0f, 2, 0, m, true,
                                           kMinCrossings, kMinLightCrossings, 3, path_pixel_samples);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("PLANES_SMIS_EXACT, %s, M = %u: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks "
                    "disagreeing %d\n",
                    label, m, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(),
                    bad);
        EXPECT_EQ(bad, 0) << m;
    }
}

}  // namespace

TEST(PhotonPlanes, SegmentPartitionConvergesToThePathTracer) {
    // plane_min_crossings: camera-ray segments a pilot plane set crosses rarely take their plane
    // lights' single scattering from the path tracer, the gather skips them. First the split must
    // be real (a good part of the segments on either side), then the image must agree with PATH,
    // with one path sample per plane set and with M = 4 (the path tracer's share is averaged over
    // them, the planes' gathered once). (Checked red: the gather not skipping the path tracer's
    // segments, double counting there, makes 18 and 26 of the 37 comparisons disagree, the image
    // mean 1.06x PATH's; the path tracer skipping them too, so that nobody estimates them, 24 and
    // 26, 0.93x.)
    Medium fog = make_medium({0.05f, 0.08f, 0.12f}, {0.35f, 0.3f, 0.25f});
    auto scene = fog_box(kW, kH, fog);
    constexpr float kMinCrossings = 12.0f;
    auto stats = partition_stats(scene, kMinCrossings, 0.0f);
    const double share = stats["path_segments"] / std::max(1.0, stats["pilot_segments"]);
    std::printf("segments the path tracer takes: %g of %g (%.2f)\n", stats["path_segments"], stats["pilot_segments"],
                share);
    EXPECT_GT(share, 0.2);
    EXPECT_LT(share, 0.8);
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    for (uint32_t m : {1u, 4u}) {
        BlockStats planes = across_renders(scene, "PLANES_SMIS_EXACT", 24, 4, 3100 + m, 1.0f, 2, 0, m, true,
                                           kMinCrossings);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("PLANES_SMIS_EXACT, partition, M = %u: image mean %.5f +- %.5f (PATH %.5f +- %.5f); blocks "
                    "disagreeing %d\n",
                    m, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        EXPECT_EQ(bad, 0) << m;
    }
}

TEST(PhotonPlanes, PerLightPartitionConvergesToThePathTracer) {
    // plane_min_light_crossings: on a camera-ray segment, a plane light the pilot plane set crosses
    // rarely there takes its single scattering from the path tracer (the media light choice then
    // includes it, MediaLightChoice::Segment::keep_plane_lights), while the other plane lights stay
    // with the planes. fog_box's two rectangles and a dim point light: first the split must be real
    // (a good part of the segments keep a light with the path tracer, and not every pair), then the
    // image must agree with PATH with one and with 4 path samples per plane set. (Checked red: the
    // gather not skipping the kept lights' crossings, double counting them, makes 30 and 34 of the
    // 37 comparisons disagree, the image mean 1.19x PATH's.)
    auto scene = three_light_fog_box();
    constexpr float kMinLightCrossings = 20.0f;
    auto stats = partition_stats(scene, 0.0f, kMinLightCrossings);
    const double pairs = stats["path_segment_lights"], segments = stats["pilot_segments"];
    std::printf("(segment, light) pairs the path tracer takes: %g, of %g segments x 3 lights\n", pairs, segments);
    EXPECT_GT(pairs, 0.2 * segments);
    EXPECT_LT(pairs, 0.8 * 3 * segments);
    BlockStats ref = across_renders(scene, "PATH", 16, 1024, 2100);
    for (uint32_t m : {1u, 4u}) {
        BlockStats planes = across_renders(scene, "PLANES_SMIS_EXACT", 24, 4, 3300 + m, 1.0f, 2, 0, m, true, 0.0f,
                                           kMinLightCrossings);
        int bad = disagreeing_blocks(planes, ref, 2);
        std::printf("PLANES_SMIS_EXACT, per-light partition, M = %u: image mean %.5f +- %.5f (PATH %.5f +- %.5f); "
                    "blocks disagreeing %d\n",
                    m, planes.image.mean(), planes.image.std_error(), ref.image.mean(), ref.image.std_error(), bad);
        EXPECT_EQ(bad, 0) << m;
    }
}

TEST(PhotonPlanes, SubsampledPilotAndSkippedGathersConvergeToThePathTracer) {
    // plane_pilot_stride: the pilot gathers on every third pixel in x and y only, each pixel
    // averages the pilot pixels within 5 of it, segment indices no window pilot ray has go to the
    // path tracer, and a camera ray none of whose segments is left to the planes skips its gather
    // (PhotonPlanesIntegrator::gathers). Both partitions on the three-light fog box: first the skip
    // must happen (some gathers skipped, not all), then the image must agree with PATH with one and
    // with 4 path samples per plane set. (Checked red: gathers() skipping a camera ray as soon as
    // one plane light of a planes' segment is the path tracer's, instead of all of them, skips 573 of
    // 576 and makes 23 and 28 of the 37 comparisons disagree, the image mean 0.61x PATH's.)
    auto scene = three_light_fog_box();
    auto stats = partition_stats(scene, 12.0f, 20.0f, 3);
    std::printf("gathers skipped: %g of %d camera rays; path segments %g of %g, (segment, light) pairs %g\n",
                stats["gathers_skipped"], kW * kH, stats["path_segments"], stats["pilot_segments"],
                stats["path_segment_lights"]);
    EXPECT_GT(stats["gathers_skipped"], 0.05 * kW * kH);
    EXPECT_LT(stats["gathers_skipped"], 0.95 * kW * kH);
    expect_both_partitions_match_path(scene, 3500, 1, "pilot stride 3");
}

TEST(PhotonPlanes, MorePathSamplesWhereNothingGathersConvergeToThePathTracer) {
    // plane_path_pixel_samples: a pixel none of whose camera-ray segments the partitions leave to
    // the planes takes K = 3 path samples per pass (sample indices (s M + m) K + k), the others one
    // and the gather. Both partitions on the three-light fog box as in the test above: first the
    // split must be real and K in use, then the image must agree with PATH with M = 1 and M = 4.
    // (Checked red: every pixel taking K samples per pass and gathering only when it takes one, i.e.
    // the gathering pixels' planes lost, makes 26 and 29 of the 37 comparisons disagree, the image
    // mean 0.61x PATH's.)
    auto scene = three_light_fog_box();
    constexpr uint32_t kPathSamples = 3;
    auto stats = partition_stats(scene, 12.0f, 20.0f, 3, kPathSamples);
    std::printf("gathers skipped: %g of %d camera rays; path samples per pass there %g\n", stats["gathers_skipped"],
                kW * kH, stats["path_pixel_samples"]);
    EXPECT_GT(stats["gathers_skipped"], 0.05 * kW * kH);
    EXPECT_LT(stats["gathers_skipped"], 0.95 * kW * kH);
    EXPECT_EQ(stats["path_pixel_samples"], double(kPathSamples));
    expect_both_partitions_match_path(scene, 3700, kPathSamples, "3 path samples where nothing gathers");
}

TEST(PhotonPlanes, StressCasesStayFinite) {
    struct Case {
        const char* name;
        Medium fog;
        std::vector<LightDesc> lights;
    };
    Medium normal = make_medium({0.05f, 0.05f, 0.05f}, {0.3f, 0.3f, 0.3f});
    std::vector<Case> cases = {
        // A light in the plane of the camera's middle rows (camera and light at z = 1): those rays run
        // along the light's chords, so crossings nearly parallel to planes are frequent.
        {"parallel", normal, {rect_light({0.0f, 0.5f, 1.0f}, 1.0f, 1.0f, 30.0f)}},
        // A light seen edge-on, planes swept nearly along it (grazing).
        {"grazing", normal, {rect_light({0.0f, 0.0f, 1.0f}, 1.2f, 0.8f, 30.0f, kPi / 2.0f - 1e-3f)}},
        {"aspect 1:1000", normal, {rect_light({0.0f, 0.3f, 1.8f}, 2.0f, 0.002f, 30.0f)}},
        {"aspect 1000:1", normal, {rect_light({0.0f, 0.3f, 1.8f}, 0.002f, 2.0f, 30.0f)}},
        {"density 1e-6", make_medium(Color(1e-7f), Color(1e-6f)), {}},
        {"density 1e3", make_medium(Color(100.0f), Color(1000.0f)), {}},
        {"clear channel", make_medium({0.0f, 0.1f, 0.5f}, {0.0f, 0.3f, 0.2f}), {}},
    };
    const char* estimators[] = {"PATH", "PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_COS", "PLANES_SMIS_EXACT"};
    for (const Case& c : cases) {
        auto scene = fog_box(16, 16, c.fog, c.lights);
        for (const char* e : estimators) {
            RenderSettings s;
            s.volume_estimator = setting_value<VolumeEstimator>(e);
            s.samples = 2;
            s.max_bounces = 1;
            s.photon_planes = 4096;
            RenderSession session(scene, s);
            session.run();
            auto img = session.pixels();
            bool finite = true;
            for (float v : img) finite = finite && std::isfinite(v);
            RenderProgress p = session.progress();
            auto stats = session.integrator_stats();
            std::printf("[stress] %-14s %-18s nan caught %llu, rejected %llu (parallel %g, non-finite %g)\n", c.name,
                        e, (unsigned long long)p.nan_caught, (unsigned long long)p.samples_rejected,
                        stats.count("parallel_rejected") ? stats["parallel_rejected"] : 0.0,
                        stats.count("nonfinite_rejected") ? stats["nonfinite_rejected"] : 0.0);
            EXPECT_TRUE(finite) << c.name << " " << e;
            EXPECT_EQ(p.nan_caught, 0u) << c.name << " " << e;
        }
    }
}

TEST(PhotonPlanes, UnknownEstimatorAndBadSettingsAreRefused) {
    auto scene = fog_box(8, 8, make_medium(Color(0.1f), Color(0.1f)));
    RenderSettings s;
    EXPECT_THROW(setting_value<VolumeEstimator>("PLANES_BOGUS"), std::invalid_argument);
    s.volume_estimator = VolumeEstimator::PlanesCmis;
    s.integrator = IntegratorKind::PsfSmis;
    EXPECT_THROW(RenderSession(scene, s), std::invalid_argument);
    s.integrator = IntegratorKind::Path;
    s.smis_planes = 0;
    EXPECT_THROW(RenderSession(scene, s), std::invalid_argument);
}

TEST(Medium, ScenesWithoutMediaReportNone) {
    auto scene = small_room(8, 8);
    EXPECT_FALSE(scene->has_media());
    auto fog = fog_box(8, 8, make_medium(Color(0.1f), Color(0.1f)));
    EXPECT_TRUE(fog->has_media());
}
