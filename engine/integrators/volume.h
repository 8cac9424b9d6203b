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

// How single scattering samples rectangular area lights from a scattering point: uniformly in the
// solid angle they subtend (bounded weights), or uniformly by area (the previous estimator, kept for
// the tests that compare the two).
enum class RectangleSampling { kSolidAngle, kArea };

// Single scattering along the media of a ray: per scattering segment one light chosen by power, one
// distance (one-sample MIS of spectral-MIS distance sampling and equiangular sampling towards a
// point of that light; for rectangles see RectangleSampling), one light sample from there, the
// phase function and the shadow ray's transmittance. With skip_plane_lights, rectangular area lights
// and point and spot lights without radius contribute nothing (photon planes estimate their single
// scattering instead).
Color single_scattering(const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                        LocalCounters& counters, bool skip_plane_lights = false,
                        RectangleSampling rectangles = RectangleSampling::kSolidAngle);

}  // namespace smis
