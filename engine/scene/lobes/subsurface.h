// Subsurface scattering's entry (Cycles 3.4's BSSRDF closures: Subsurface Scattering node, Principled
// Subsurface). It has no BSDF value: when the mixture picks it (by its weight, as Cycles picks a
// BSSRDF among the closures), sample() returns a Dirac event of throughput weight / P(pick) into the
// surface, and the path tracer walks inside the object from there (integrators/subsurface_walk.h;
// Christensen-Burley: finds the exit by disk sampling, integrators/subsurface_disk.h) and goes on
// from the exit point with a diffuse lobe. Parameters (scene/subsurface_closure.cpp):
//   weight   the closure weight (Cycles' bssrdf->weight: albedo x mix weight)
//   f0       the surface albedo (the colour the walk's single-scattering albedo is inverted from)
//   kind_colour  the mean free path per channel after Cycles' bssrdf_setup_radius
//   alpha    the phase function's anisotropy g in [0, 0.9]
//   variant  kPrincipledExit: the exit lobe is principled (1 - FL/2) Lambert, else plain Lambert;
//            kDisk: Christensen-Burley's disk sampling (kind_colour is its profile's d), else the walk.
// Integrators without subsurface transport, and paths after a diffuse bounce (Cycles' diffuse
// ancestor), replace it with its diffuse fallback (Bsdf::subsurface_as_diffuse).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct SubsurfaceLobe : LobeDefaults<SubsurfaceLobe> {
    static constexpr LobeKind kKind = LobeKind::Subsurface;
    static constexpr const char* kName = "subsurface";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr uint8_t kPrincipledExit = 1;
    static constexpr uint8_t kDisk = 2;  // Christensen-Burley: disk sampling, not the walk

    // A Dirac event for the mixture: no eval, no pdf, no light samples of its own.
    static bool is_delta(const Lobe&) { return true; }
    static LobeTerms terms(const Lobe&, const Vec3&, const Vec3&) { return {}; }

    static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2, float) {
        BsdfSample s;
        if (!(wo.z > 0.0f)) return s;
        s.wi = Vec3(0.0f, 0.0f, -1.0f);
        s.value = lobe.weight;
        s.pdf = 1.0f;
        s.delta = true;
        s.transmission = true;
        return s;
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
