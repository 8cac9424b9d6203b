#include "integrators/media_segments.h"

namespace smis {

bool connection_through_media(const Scene& scene, const ShadowRay& s, uint32_t visibility, int32_t medium, Color* tr) {
    // Most connections meet no surface at all: one medium, and an any-hit query is enough.
    if (!scene.occluded(s.o, s.d, s.tmax, s.time, visibility)) {
        if (tr) *tr = medium >= 0 ? transmittance(scene.medium(medium).sigma_t(), s.tmax) : Color(1.0f);
        return true;
    }
    SurfaceHit hit;
    RayMedia media;
    if (intersect_through(scene, Ray{s.o, s.d, 0.0f, s.tmax, s.time, visibility}, medium, &hit, &media)) return false;
    if (tr) *tr = media.transmittance_to_end();
    return true;
}

}  // namespace smis
