// Building blocks of unidirectional path tracing, shared by the path tracer and by the integrators
// that reuse parts of paths (path-space filtering): shading-point set-up, next-event estimation,
// emission found along a ray with its MIS weight, and tracing the rest of a path.
#pragma once
#include "integrators/integrator.h"

namespace smis {

// A surface hit ready for shading: frames facing the incoming direction, as Cycles does.
struct ShadingPoint {
    SurfaceHit hit;
    Vec3 wo;          // towards the previous vertex
    Vec3 ng, ns;      // geometric and shading normals, flipped to the side of wo
    bool backfacing;  // the ray arrived from the back of the triangle (inside a closed glass object)
    Bsdf bsdf;
};
ShadingPoint make_shading_point(const Scene& scene, const SurfaceHit& hit, const Vec3& ray_dir);
// Origin for a ray leaving the shading point in direction d (offset to the correct side).
inline Vec3 spawn_origin(const ShadingPoint& sp, const Vec3& d) {
    return offset_ray_origin(sp.hit.p, dot(d, sp.ng) > 0.0f ? sp.ng : -sp.ng);
}

// The MIS state carried from one vertex to the next.
struct PathState {
    int depth = 0;           // bounces before the vertex the next ray will find (Cycles' bounce)
    bool prev_delta = true;  // camera rays and Dirac bounces: emission is not MIS-weighted
    float prev_pdf = 0.0f;   // solid-angle pdf of the BSDF sample that produced the ray
    Vec3 prev_p;             // where that ray started (for the triangle lights' pdf)
    // A camera path before its first non-specular vertex, where settings.direct_light applies.
    bool first_vertex_ahead = false;
    // The previous vertex's light-sampling density, for MIS, as a multiple of the NEE density
    // (pmf x light pdf): M for resampled light sampling (RIS, ReSTIR), see reservoir_contribution.
    float light_pdf_scale = 1.0f;
};

// Next-event estimation at a shading point: one light chosen by power, one point on it.
struct DirectSample {
    Vec3 wi;
    Color weighted{0.0f};  // Le * w_light / pdf_light: multiply by bsdf.eval(wo, wi) for the contribution
    bool valid = false;
};
DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                           LocalCounters& counters);

// Emission reaching the ray's origin from lights that are not geometry (area, point, spot) in front
// of the first hit, from that hit if it emits, or from lights at infinity when nothing is hit;
// MIS-weighted against next-event estimation from the previous vertex.
Color emission_along(const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                     const SurfaceHit& hit, const PathState& state);

// Radiance arriving at ray.o along -ray.d: the path tracer from `state` on (NEE + BSDF sampling with
// MIS, Russian roulette, Cycles' bounce limit).
Color trace_path(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                 LocalCounters& counters);

// Russian roulette after a few bounces; returns false to stop, else rescales beta.
bool russian_roulette(int depth, Color& beta, float eta_scale, Rng& rng);

}  // namespace smis
