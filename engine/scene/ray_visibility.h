// Cycles' ray types and per-object ray visibility (Object Properties > Visibility > Ray Visibility).
//
// A ray carries the type bits of the scattering event that sent it (as Cycles' path flags) and an
// object is seen by the ray when its visibility shares a bit with the ray's Embree mask: every
// object's visibility is its Embree geometry mask (scene.cpp), so a ray skips the objects invisible
// to it inside the BVH traversal, at no cost for scenes whose objects are all visible.
#pragma once
#include <cstdint>

namespace smis {

enum RayVisibility : uint32_t {
    kRayCamera = 1u << 0,
    kRayDiffuse = 1u << 1,
    kRayGlossy = 1u << 2,
    kRayTransmission = 1u << 3,
    kRayShadow = 1u << 4,
    kRayVolumeScatter = 1u << 5,
    // Not a Cycles ray type: the mask bit of the objects that block shadow rays with a surface (seen
    // by shadow rays, and some triangle's material has a surface, not only a volume). A shadow ray in
    // media asks with it alone for opaque blockers, past the pass-through boundaries (volume.cpp).
    kRayShadowSurface = 1u << 30,
    // The types of rays that leave a surface after scattering (a light excluded from them is not
    // sampled for the matching lobes either).
    kRayBounceTypes = kRayDiffuse | kRayGlossy | kRayTransmission,
    // An object or light seen by every ray (Embree's default geometry mask).
    kRayAllVisibility = 0xFFFFFFFFu,
};

// The Embree mask of a ray with Cycles' path flags `flags` (kRayCamera, or the last bounce's
// kRayDiffuse / kRayGlossy, with kRayTransmission for a transmission): Cycles'
// path_state_ray_visibility, where diffuse and glossy stand for reflection only, so a transmitted
// ray is seen by the objects visible to transmission whatever its lobe.
inline uint32_t ray_mask(uint32_t flags) { return (flags & kRayTransmission) ? uint32_t(kRayTransmission) : flags; }

// Whether a light with ray visibility `visibility` is hidden from a bounce ray with path flags
// `flags` (Cycles' shade_light.h: glossy counts for reflections only; a diffuse transmission is
// both diffuse and transmission there). Camera rays are decided by Light::visible_to_camera.
inline bool light_hidden_from(uint32_t visibility, uint32_t flags) {
    const uint32_t excluded = ~visibility;
    return ((excluded & kRayDiffuse) && (flags & kRayDiffuse)) ||
           ((excluded & kRayGlossy) && (flags & (kRayGlossy | kRayTransmission)) == kRayGlossy) ||
           ((excluded & kRayTransmission) && (flags & kRayTransmission));
}

}  // namespace smis
