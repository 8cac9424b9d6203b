// The lobes of one BSSRDF closure as Cycles 3.4 sets them up (closure/bssrdf.h, bssrdf_setup and
// bssrdf_setup_radius; svm/closure.h's Subsurface Scattering and Principled cases).
#pragma once
#include "scene/lobes/dispatch.h"

namespace smis {

// The node's Falloff / Principled's Subsurface Method, in the add-on's order (0: Principled's default).
enum class SubsurfaceMethod : uint8_t { RandomWalk = 0, RandomWalkFixedRadius = 1, ChristensenBurley = 2 };

struct SubsurfaceClosure {
    Color weight;      // closure weight: albedo x mix weight (x Principled's diffuse share)
    Color albedo;      // Subsurface Scattering's Color, Principled's mix of Base and Subsurface Color
    Color radius;      // Radius x Scale (Principled: Subsurface Radius x Subsurface)
    float ior = 1.4f;  // clamped to [1.01, 3.8] as Cycles does
    float anisotropy = 0.0f;  // clamped to [0, 0.9]
    SubsurfaceMethod method = SubsurfaceMethod::RandomWalk;
    bool principled = false;  // Principled: a retro-reflection lobe at the entry, a Fresnel'd exit
    float roughness = 0.5f;   // Principled's Roughness (its retro-reflection)
    uint8_t index = 0;        // the Subsurface lobe's template index (Principled's retro-reflection: the next)
};

// Cycles' random-walk radius for Random Walk (not Fixed Radius): the mean free path scaled by
// sqrt(3 (1 - alpha')), alpha' the single-scattering albedo whose diffuse dipole reflectance (Jensen
// et al. 2001, with the Fdr fit of eta) equals the surface albedo, found by 12 bisection steps.
float random_walk_radius_scale(float albedo, float ior);

// Appends the closure's lobes to out (at most 3): Principled's retro-reflection (the whole weight),
// a diffuse lobe carrying the channels whose radius is below Cycles' BSSRDF_MIN_RADIUS (1e-8), and
// the Subsurface lobe with the other channels. Returns how many.
int subsurface_lobes(const SubsurfaceClosure& c, Lobe* out);

}  // namespace smis
