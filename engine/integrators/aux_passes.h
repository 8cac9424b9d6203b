// The auxiliary passes (Depth, Normal, Albedo) recorded at a camera sample's first hit. Only runs
// when a pass is enabled (Film::has_aux), so renders without passes trace no extra ray.
#pragma once
#include "integrators/integrator.h"

namespace smis {

struct ShadingPoint;

// Depth and normal of the first hit along the camera ray, as Cycles' Z and Normal passes. Albedo
// as Cycles' denoising albedo: the first hit that is not a perfect mirror or smooth glass gives its
// closures' reflectance (weights, Fresnel-scaled at normal incidence for specular layers and
// metals), times the throughput of the Dirac bounces that led there (at most
// kAuxMaxDeltaBounces, chosen with `rng`, a stream of its own so the image does not change).
constexpr int kAuxMaxDeltaBounces = 8;
AuxSample first_hit_aux(const Scene& scene, const Ray& camera_ray, Rng& rng);
// The same from a first hit the integrator's own camera path has shaded already (`first`, the
// camera ray's hit for sample s of window pixel (x, y)): no second camera ray; the albedo's Dirac
// bounces, if any, draw from the same stream of their own as first_hit_aux's.
AuxSample first_hit_passes(const RenderContext& ctx, int x, int y, uint32_t s, const ShadingPoint& first);
// Only the depth (normal and albedo left at their background values): when no pass needs more.
AuxSample first_hit_depth(const Scene& scene, const Ray& camera_ray);

// Records sample `s` of window pixel (x, y) in the auxiliary passes when they are on.
// `camera_depth`: the camera ray's depth where the integrator recorded it (LocalCounters), so that
// the Z pass alone traces nothing; NaN to trace the ray here.
void add_aux_sample(RenderContext& ctx, int x, int y, uint32_t s, const Ray& camera_ray, float diagnostic = 0.0f,
                    float camera_depth = std::numeric_limits<float>::quiet_NaN());

}  // namespace smis
