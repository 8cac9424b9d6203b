// One conversion of an engine Ray into Embree's ray-hit record, for every closest-hit query (the
// scene's BVH and the photon planes' BVH).
#pragma once
#include <embree3/rtcore.h>

#include "scene/camera.h"

namespace smis {

inline RTCRayHit embree_ray_hit(const Ray& ray) {
    RTCRayHit rh;
    rh.ray.org_x = ray.o.x, rh.ray.org_y = ray.o.y, rh.ray.org_z = ray.o.z;
    rh.ray.dir_x = ray.d.x, rh.ray.dir_y = ray.d.y, rh.ray.dir_z = ray.d.z;
    rh.ray.tnear = ray.tmin;
    rh.ray.tfar = ray.tmax;
    rh.ray.mask = ray.visibility;
    rh.ray.flags = 0;
    rh.ray.time = ray.time;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

}  // namespace smis
