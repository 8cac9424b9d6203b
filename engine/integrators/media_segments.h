// The pieces of a path through participating media that the integrators built on their own path
// loops (ReSTIR's stage 1) take from the path tracer: a camera or bounce ray's segment up to its
// first opaque hit; and a reconnection between two points (path-space filtering's gather). Only called for
// scenes with media (Scene::has_media()); the surface-only loops never reach this code.
#pragma once
#include "integrators/volume.h"

namespace smis {

// What a ray's segment up to its first opaque hit gives the path, as trace_path_impl<kMedia> takes
// it: the emission found along it (MIS-weighted against the previous vertex's light sample,
// attenuated by the media), the single scattering along it while the path may still bounce (Cycles'
// volume bounces = 0: no path continues from a scattering point), the whole segment's transmittance
// (the path's throughput is multiplied by it) and the medium at its end (the next vertex's).
// Emission and scattering are per unit throughput: multiply by the path's throughput before it.
struct MediaSegment {
    bool found = false;
    Color emission{0.0f}, scattering{0.0f}, transmittance{1.0f};
    int32_t end_medium = kNoMedium;
};
MediaSegment trace_media_segment(const Scene& scene, const RenderSettings& settings, const Ray& ray,
                                 const PathState& state, SurfaceHit* hit, Rng& rng, LocalCounters& counters);

// One segment of a camera path's prefix as ReSTIR's stage 1 takes it: the
// emission found along `ray` (clamped as Clamp Direct's at depth <= 1) and, with media (kMedia: the
// scene has some), the single scattering along it are added to *L under the throughput beta; with
// media the segment's transmittance goes into beta and the medium at its end into st. Returns
// whether the ray found a surface (*hit).
template <bool kMedia>
bool trace_prefix_segment(const Scene& scene, const RenderSettings& settings, const Ray& ray, PathState& st,
                          Color& beta, SurfaceHit* hit, Rng& rng, LocalCounters& counters, Color* L) {
    if constexpr (kMedia) {
        const MediaSegment seg = trace_media_segment(scene, settings, ray, st, hit, rng, counters);
        *L += clamp_contribution(settings, beta * seg.emission, st.depth <= 1) + beta * seg.scattering;
        beta *= seg.transmittance;
        st.medium = seg.end_medium;
        return seg.found;
    } else {
        const bool found = scene.intersect(ray, hit);
        *L += clamp_contribution(settings, beta * emission_along(scene, settings, ray, found, *hit, st), st.depth <= 1);
        return found;
    }
}

// A reconnection along the shadow ray s, which starts in `medium` (path-space filtering's connections
// from one pixel's x1 to another's z1): false when an opaque surface blocks it (a boundary without a
// surface shader does not: the path's own rays pass it), else *tr, when given, receives its
// transmittance through the media on the way. `visibility`: the objects that can block it.
bool connection_through_media(const Scene& scene, const ShadowRay& s, uint32_t visibility, int32_t medium, Color* tr);

}  // namespace smis
