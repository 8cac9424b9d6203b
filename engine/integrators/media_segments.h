// A reconnection through participating media between two points (path-space filtering's gather).
// Only called for scenes with media (Scene::has_media()); the surface-only loops never reach this code.
#pragma once
#include "integrators/volume.h"

namespace smis {

// A reconnection along the shadow ray s, which starts in `medium` (path-space filtering's connections
// from one pixel's x1 to another's z1): false when an opaque surface blocks it (a boundary without a
// surface shader does not: the path's own rays pass it), else *tr, when given, receives its
// transmittance through the media on the way. `visibility`: the objects that can block it.
bool connection_through_media(const Scene& scene, const ShadowRay& s, uint32_t visibility, int32_t medium, Color* tr);

}  // namespace smis
