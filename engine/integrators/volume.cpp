#include "integrators/volume.h"

#include "core/sampler.h"
#include "integrators/path_tracing.h"
#include "scene/spherical_rectangle.h"

namespace smis {

Color media_transmittance(const RayMedia& media, const Scene& scene, float t) { return media.transmittance(scene, t); }
Color media_transmittance_to_end(const RayMedia& media) { return media.transmittance_to_end(); }
namespace {

// Boundaries a ray may cross before it is treated as lost (a closed mesh costs two).
constexpr int kMaxCrossings = 64;

// sigma_t * len per channel, with 0 * inf = 0 for clear channels of infinite segments.
Color optical_depth(const Color& sigma_t, float len) {
    Color tau;
    for (int c = 0; c < 3; ++c) tau[c] = sigma_t[c] > 0.0f ? sigma_t[c] * len : 0.0f;
    return tau;
}

// The medium on the far side of a pass-through boundary crossed by direction d.
int32_t medium_beyond(const Scene& scene, const SurfaceHit& h, const Vec3& d) {
    return dot(d, h.ng) < 0.0f ? scene.material(h.material).medium : scene.world_medium();
}

// Walks the ray through pass-through boundaries; segment(t0, t1, medium) for each stretch between
// boundaries (t from ray.o). Returns the first opaque hit (t from ray.o) or false.
template <class F>
bool walk(const Scene& scene, const Ray& ray, int32_t medium, SurfaceHit* hit, int32_t* end_medium, F&& segment) {
    Ray r = ray;
    float base = 0.0f;
    for (int i = 0; i < kMaxCrossings; ++i) {
        SurfaceHit h;
        bool found = scene.intersect(r, &h);
        float t_end = found ? base + h.t : ray.tmax;
        segment(base + r.tmin, t_end, medium);
        if (!found || !scene.material(h.material).pass_through) {
            *end_medium = medium;
            if (found) {
                *hit = h;
                hit->t = t_end;
            }
            return found;
        }
        medium = medium_beyond(scene, h, r.d);
        r.o = offset_ray_origin(h.p, dot(r.d, h.ng) > 0.0f ? h.ng : -h.ng);
        base += h.t;
        r.tmin = 0.0f;
        r.tmax = ray.tmax - base;
    }
    *end_medium = medium;
    return false;
}

}  // namespace

void RayMedia::add(const Scene& scene, float t0, float t1, int32_t medium) {
    if (medium < 0 || !(t1 > t0)) return;
    tau_end += optical_depth(scene.medium(medium).sigma_t(), t1 - t0);
    if (count < kMaxSegments) seg[count++] = {t0, t1, medium};
}

Color RayMedia::transmittance(const Scene& scene, float t) const {
    Color tau(0.0f);
    for (int i = 0; i < count && seg[i].t0 < t; ++i)
        tau += optical_depth(scene.medium(seg[i].medium).sigma_t(), std::min(t, seg[i].t1) - seg[i].t0);
    return transmittance_from_tau(tau);
}

int32_t medium_across(const Scene& scene, const ShadingPoint& sp, int32_t current) {
    const Material& m = scene.material(sp.hit.material);
    if (m.medium < 0 && !m.pass_through) return current;
    return sp.backfacing ? scene.world_medium() : m.medium;
}

bool intersect_through(const Scene& scene, const Ray& ray, int32_t medium, SurfaceHit* hit, RayMedia* media) {
    media->count = 0;
    media->tau_end = Color(0.0f);
    int stretches = 0;  // one more than the boundaries passed
    const bool found = walk(scene, ray, medium, hit, &media->end_medium, [&](float t0, float t1, int32_t m) {
        ++stretches;
        media->add(scene, t0, t1, m);
    });
    media->crossed = stretches > 1;
    return found;
}

namespace {

// What a shadow ray from origin along unit dir up to tmax meets: a surface (blocked), nothing (it
// stays in its medium), or maybe boundaries to walk through (walk() then finds out).
enum class ShadowPath { kBlocked, kOneMedium, kWalk };

ShadowPath shadow_path(const Scene& scene, const Vec3& origin, const Vec3& dir, float tmax) {
    const BoundaryPlanes& boundaries = scene.boundary_planes();
    // Without the planes' test: one any-hit query for everything; a hit, on a surface or a boundary,
    // is walked.
    if (!boundaries.usable()) return scene.occluded(origin, dir, tmax) ? ShadowPath::kWalk : ShadowPath::kOneMedium;
    // One any-hit query for surfaces alone, past the boundaries: blocked shadow rays (most of them
    // when a wall stands between the medium and a light) need no closest-hit walk to a surface the
    // first query already saw; the clear ones stay in one medium when their ends lie on one side of
    // every boundary plane, which for a shadow ray inside a fog box to a light inside it is no query.
    if (scene.occluded(origin, dir, tmax, kShutterCentre, kRayShadowSurface)) return ShadowPath::kBlocked;
    return boundaries.separated(origin, origin + dir * tmax) ? ShadowPath::kOneMedium : ShadowPath::kWalk;
}

}  // namespace

Color shadow_transmittance(const Scene& scene, const Vec3& origin, const Vec3& dir, float tmax, int32_t medium) {
    // Most shadow rays meet no boundary at all: then they stay in one medium.
    switch (shadow_path(scene, origin, dir, tmax)) {
    case ShadowPath::kBlocked: return Color(0.0f);
    case ShadowPath::kOneMedium:
        return medium >= 0 ? RayMedia::transmittance_from_tau(optical_depth(scene.medium(medium).sigma_t(), tmax))
                           : Color(1.0f);
    case ShadowPath::kWalk: break;
    }
    Color tau(0.0f);
    SurfaceHit hit;
    int32_t end;
    bool blocked = walk(scene, Ray{origin, dir, 0.0f, tmax, kShutterCentre, kRayShadow}, medium, &hit, &end, [&](float t0, float t1, int32_t m) {
        if (m >= 0 && t1 > t0) tau += optical_depth(scene.medium(m).sigma_t(), t1 - t0);
    });
    return blocked ? Color(0.0f) : RayMedia::transmittance_from_tau(tau);
}

bool shadow_media(const Scene& scene, const Vec3& origin, const Vec3& dir, float tmax, int32_t medium,
                  RayMedia* media) {
    media->count = 0;
    media->tau_end = Color(0.0f);
    const ShadowPath path = shadow_path(scene, origin, dir, tmax);
    if (path == ShadowPath::kBlocked) return false;
    if (path == ShadowPath::kOneMedium) {
        media->add(scene, 0.0f, tmax, medium);
        media->end_medium = medium;
        return true;
    }
    SurfaceHit hit;
    return !walk(scene, Ray{origin, dir, 0.0f, tmax, kShutterCentre, kRayShadow}, medium, &hit, &media->end_medium,
                 [&](float t0, float t1, int32_t m) { media->add(scene, t0, t1, m); });
}

SegmentNumbers segment_numbers(Rng& rng) {
    uint64_t key;
    uint32_t sample;
    if (kWithStratified && rng.take_scattering_segment(&key, &sample)) {
        float v[6];
        scattering_segment_values(key, sample, v);
        return {v[0], v[1], {v[2], v[3]}, {v[4], v[5]}};
    }
    SegmentNumbers n;
    n.select = rng.next_float(), n.dist = rng.next_float();
    n.light = {rng.next_float(), rng.next_float()};
    n.focus = {rng.next_float(), rng.next_float()};
    return n;
}

namespace {

// Below this solid angle a rectangle is sampled by area: the two densities are then proportional to
// within float precision, and the spherical construction's angles would carry no digits.
constexpr double kMinSolidAngle = 1e-9;

}  // namespace

LightSample sample_light_from_medium(const Light& light, const Vec3& x, Point2 u, float time,
                                     RectangleSampling rectangles) {
    LightRectangle rect;
    if (rectangles == RectangleSampling::kSolidAngle && light.rectangle(&rect)) {
        LightSample s;
        if (!(dot(x - rect.corner, rect.normal) > 0.0f)) return s;  // behind the one-sided light
        SphericalRectangle sr(x, rect.corner, rect.u, rect.v);
        if (sr.solid_angle() > kMinSolidAngle) {
            Vec3 d = sr.sample(u) - x;
            float dist = length(d);
            if (!(dist > 0.0f)) return s;
            s.wi = d / dist;
            s.dist = dist;
            s.pdf = float(1.0 / sr.solid_angle());
            s.L = rect.radiance;
            return s;
        }
    }
    return light.sample_at(x, u, time);
}


namespace {

// Single scattering's RGB channels (scattering_samples): distance sampling over the medium's three
// channels, and the sample's contribution with the three transmittances.
struct RgbScattering {
    const Scene& scene;
    const RayMedia& media;
    Color L{0.0f};
    Color tr{1.0f};  // the last shadow ray's transmittance
    // The last distance sample and its segment: scattering_samples asks for the density of the
    // distance it just drew, which sample_segment_distance computed already (the same function of
    // the same arguments, so the same value).
    DistanceSample last{};
    int32_t last_medium = kNoMedium;
    float last_len = 0.0f;

    DistanceSample sample_distance(int32_t medium, float len, float u_channel, float u) {
        last = sample_segment_distance(scene.medium(medium).sigma_t(), len, u_channel, u);
        last_medium = medium;
        last_len = len;
        return last;
    }
    float distance_pdf(int32_t medium, float len, float t) const {
        if (last.pdf > 0.0f && t == last.t && medium == last_medium && len == last_len) return last.pdf;
        return segment_distance_pdf(scene.medium(medium).sigma_t(), len, t);
    }
    bool transmit(const Vec3& x, const Vec3& wi, float tmax, int32_t medium, bool cast_shadow) {
        tr = cast_shadow ? shadow_transmittance(scene, x, wi, tmax, medium) : Color(1.0f);
        return !is_black(tr);
    }
    void add(const RayMedia::Segment& s, float t, uint32_t, const LightSample& ls, float weight) {
        const Medium& med = scene.medium(s.medium);
        Color t_cam = media.transmittance(scene, s.t0) * transmittance(med.sigma_t(), t);
        L += t_cam * med.sigma_s * (ls.L * tr) * weight;
    }
};

}  // namespace

Color single_scattering(const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                        LocalCounters& counters, bool skip_plane_lights, RectangleSampling rectangles) {
    // Per scattering segment: a light chosen for the segment (MediaLightChoice), then a distance
    // from a one-sample MIS mixture of spectral-MIS distance sampling and equiangular sampling
    // towards a point of that light (the mixture's density is the average of both), then next-event estimation from there. As in
    // Cycles, the equiangular half removes the inverse-square noise of lights inside the medium.
    // Rectangular area lights are sampled by solid angle from the scattering point (their weight
    // L * solid angle is bounded), and equiangular sampling aims at an independent uniform point of
    // the light. Sampling them by area instead (RectangleSampling::kArea, the previous estimator)
    // has a weight A cos / r^2 that diverges where the ray passes close to the sampled point: with
    // equiangular sampling towards that very point the 1/r^2 cancels but a 1/h remains (h the
    // point's distance to the ray), and its second moment over the light diverges for rays that
    // cross the light. Those were the rare bright samples (volume_test.cpp measures both). For
    // other lights whose sampled point does not depend on the reference point (triangles, disks)
    // the focus is the very point next-event estimation then connects to, so the joint density of
    // (distance, light point) cancels the 1/d^2 of the connection; for the rest the focus is drawn
    // independently, which keeps the estimator unbiased for every light type.
    RgbScattering rgb{scene, media};
    scattering_samples(scene, ray, media, rng, counters, skip_plane_lights, rectangles, rgb);
    return rgb.L;
}

}  // namespace smis
