// Rays through homogeneous media bounded by closed meshes: walking a ray through index-matched
// (pass-through) boundaries while tracking the current medium, transmittance along camera, path and
// shadow rays, and single scattering by next-event estimation (Cycles' volume bounces = 0). Used only
// when Scene::has_media(); scenes without media never reach this code.
#pragma once
#include "integrators/path_tracing.h"

namespace smis {

constexpr int32_t kNoMedium = -1;

// The media a ray crosses up to its first opaque hit, as intervals of its parameter t (the ray's
// direction is unit length, so t is a distance). Segments in vacuum (medium -1) are not stored.
struct RayMedia {
    struct Segment {
        float t0, t1;
        int32_t medium;
    };
    static constexpr int kMaxSegments = 8;  // deeper boundary stacks are merged into the last one
    Segment seg[kMaxSegments];
    int count = 0;
    int32_t end_medium = kNoMedium;  // the medium on the ray's side of the hit (or at infinity)
    Color tau_end{0.0f};             // optical depth of the whole ray
    bool crossed = false;            // the ray passed a boundary (its hit is not the ray's first surface)
    // Bit i: skip_plane_lights applies to seg[i] (photon planes estimate its single scattering from
    // their lights); on the others the path tracer does (photon_planes.cpp, the segment partition).
    uint8_t plane_segments = 0xff;
    // Per segment (or null): the plane lights, by scene light index, that the per-light partition
    // left to the path tracer on a segment whose plane_segments bit is set (photon_planes.cpp).
    const uint32_t* plane_keep = nullptr;

    void add(const Scene& scene, float t0, float t1, int32_t medium);
    // exp(-optical depth over [0, t)), per channel.
    Color transmittance(const Scene& scene, float t) const;
    Color transmittance_to_end() const { return transmittance_from_tau(tau_end); }
    static Color transmittance_from_tau(const Color& tau) {
        return {std::exp(-tau.x), std::exp(-tau.y), std::exp(-tau.z)};
    }
};

// Medium entered by crossing the surface at sp from the side of sp.wo: a material with a volume
// switches between its interior and the world medium; surfaces without one leave it unchanged.
int32_t medium_across(const Scene& scene, const ShadingPoint& sp, int32_t current);
// Medium of a ray leaving sp in direction d, when the path arrived in `current`.
inline int32_t medium_towards(const Scene& scene, const ShadingPoint& sp, const Vec3& d, int32_t current) {
    return dot(d, sp.ng) > 0.0f ? current : medium_across(scene, sp, current);
}

// Like Scene::intersect, but passes through boundaries without a surface shader, filling `media`.
// hit->t is measured from ray.o.
bool intersect_through(const Scene& scene, const Ray& ray, int32_t medium, SurfaceHit* hit, RayMedia* media);

// Transmittance from origin along unit dir up to tmax; zero when an opaque surface blocks it.
Color shadow_transmittance(const Scene& scene, const Vec3& origin, const Vec3& dir, float tmax, int32_t medium);

// The media along a shadow ray from origin along unit dir up to tmax, into *media (its segments and
// RGB optical depth); false when an opaque surface blocks it. For spectra other than RGB, which
// take their own transmittance from the segments.
bool shadow_media(const Scene& scene, const Vec3& origin, const Vec3& dir, float tmax, int32_t medium,
                  RayMedia* media);

// How single scattering samples rectangular area lights from a scattering point: uniformly in the
// solid angle they subtend (bounded weights), or uniformly by area (the previous estimator, kept for
// the tests that compare the two).
enum class RectangleSampling { kSolidAngle, kArea };

// Single scattering along the media of a ray: per scattering segment one light chosen for that
// segment (Scene::media_lights, media_light_choice.h: power, uniform and closeness to the segment), one
// distance (one-sample MIS of spectral-MIS distance sampling and equiangular sampling towards a
// point of that light; for rectangles see RectangleSampling), one light sample from there, the
// phase function and the shadow ray's transmittance. With skip_plane_lights, rectangular area lights
// and point and spot lights without radius contribute nothing (photon planes estimate their single
// scattering instead).
Color single_scattering(const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                        LocalCounters& counters, bool skip_plane_lights = false,
                        RectangleSampling rectangles = RectangleSampling::kSolidAngle);

// Next-event sample of `light` from a point x in a medium: rectangles as `rectangles` says, every
// other light by its own sample().
LightSample sample_light_from_medium(const Light& light, const Vec3& x, Point2 u, float time,
                                     RectangleSampling rectangles);

// A scattering segment's random numbers: the light choice (whose remapped number then picks the
// technique and the channel, MediaLightChoice::sample), the distance, the point on the light and the
// equiangular focus. The same count per segment whatever happens, so later decisions keep their
// streams.
struct SegmentNumbers {
    float select, dist;
    Point2 light, focus;
};
// The pixel sample's first scattering segment (Rng::take_scattering_segment: the camera ray's, in a
// scene seen through a medium) draws from stratified groups of its own, so that over a pixel's
// samples the light choice, technique and distance are stratified jointly and the light points too,
// while the first surface vertex keeps the stratified prefix it has in scenes without media; every
// other segment draws from the stream. Unbiased either way: each number is uniform and independent.
// The groups: core/sampler.h, scattering_segment_values.
SegmentNumbers segment_numbers(Rng& rng);

// single_scattering's estimator for any set of channels (RGB's three, a spectral path's wavelengths):
// per scattering segment of `media`, one light, one distance and one light sample, as described at
// single_scattering. `channels` provides
//   sample_distance(medium, len, u_channel, u), distance_pdf(medium, len, t): distance sampling
//       over its channels (a one-sample mixture: its pdf is the channels' average),
//   transmit(x, wi, tmax, medium, cast_shadow): the shadow ray's transmittance, false when zero,
//   add(segment, t, light, light sample, weight): the sample's contribution, weight being
//       phase / (light pmf x light pdf x distance pdf), to be multiplied by the transmittance to
//       the scattering point, sigma_s and the shadow ray's transmittance per channel.
template <class Channels>
void scattering_samples(const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng, LocalCounters& counters,
                        bool skip_plane_lights, RectangleSampling rectangles, Channels& channels) {
    const MediaLightChoice& choice = scene.media_lights();
    for (int i = 0; i < media.count; ++i) {
        const RayMedia::Segment& s = media.seg[i];
        const Medium& med = scene.medium(s.medium);
        const SegmentNumbers n = segment_numbers(rng);
        const Point2 u = n.light;
        const bool skip = skip_plane_lights && (media.plane_segments >> i & 1u);
        const uint32_t keep = skip && media.plane_keep ? media.plane_keep[i] : 0u;
        if (!med.scatters() || choice.empty(skip, keep)) continue;
        const float len = s.t1 - s.t0;
        const Vec3 o = ray.o + ray.d * s.t0;
        // Lights hidden from Volume Scatter, and with skip_plane_lights the planes' lights, are
        // never chosen: their contribution here is zero.
        uint32_t li;
        float light_pmf, u_technique;
        const Color sigma_t = med.sigma_t();
        if (!choice.sample({o, ray.d, len, (sigma_t.x + sigma_t.y + sigma_t.z) / 3.0f, skip, keep}, n.select,
                           &li, &light_pmf, &u_technique))
            continue;
        const Light& light = scene.light(li);
        const bool rectangle = light.rectangle(nullptr);
        EquiangularFrame eq;
        if (!light.at_infinity()) {
            Vec3 mid = o + ray.d * (std::isinf(len) ? 1.0f : 0.5f * len);
            // The focus is the light point even when mid sees the light from behind (pdf 0): the ray
            // may still pass in front of it, close to the point.
            bool any_point = light.point_independent_of_reference();
            bool same_point = any_point && !(rectangle && rectangles == RectangleSampling::kSolidAngle);
            LightSample focus = light.sample_at(mid, same_point ? u : n.focus, ray.time);
            if ((focus.pdf > 0.0f || any_point) && focus.dist > 0.0f && std::isfinite(focus.dist))
                eq = equiangular_frame(o, ray.d, len, mid + focus.wi * focus.dist);
        }
        // The technique takes the lower or upper half of the light choice's remapped number, and
        // distance sampling the rest of it for its channel.
        const bool equiangular = eq.valid && u_technique < 0.5f;
        const float u_channel =
            eq.valid ? std::min(2.0f * u_technique - (u_technique < 0.5f ? 0.0f : 1.0f), 0x1.fffffep-1f) : u_technique;
        DistanceSample ds = equiangular ? sample_equiangular(eq, n.dist)
                                        : channels.sample_distance(s.medium, len, u_channel, n.dist);
        float pdf = channels.distance_pdf(s.medium, len, ds.t);
        if (eq.valid) pdf = 0.5f * (pdf + equiangular_pdf(eq, ds.t));
        if (!(ds.pdf > 0.0f) || !(pdf > 0.0f) || !std::isfinite(pdf)) {
            // A clear channel of an infinite segment cannot sample: part of the one-sample MIS.
            if (!std::isinf(s.t1)) ++counters.samples_rejected;
            continue;
        }
        Vec3 x = o + ray.d * ds.t;
        LightSample ls = sample_light_from_medium(light, x, u, ray.time, rectangles);
        if (!ls.valid()) {
            if (!std::isfinite(ls.pdf) || !is_finite(ls.L)) ++counters.samples_rejected;
            continue;
        }
        float tmax = std::isinf(ls.dist) ? kInf : ls.dist * (1.0f - 1e-4f);
        // Cast Shadow off: no shadow ray, so neither occlusion nor the media on the way (Cycles).
        if (!channels.transmit(x, ls.wi, tmax, s.medium, light.cast_shadow) ||
            (light.cast_shadow && !reaches_mesh_light(scene, ShadowRay{x, ls.wi, tmax, ray.time}, ls)))
            continue;
        float phase = med.phase.eval(-ray.d, ls.wi);
        channels.add(s, ds.t, li, ls, phase / (light_pmf * ls.pdf * pdf));
    }
}

}  // namespace smis
