// The scene's bounding box as a test that camera rays take before the BVH: a ray that surely misses
// the box hits nothing, so Embree need not be asked. Embree's rtcIntersect1 costs about 550
// instructions for such a ray even when it misses the root node (ray set-up, the traversal's
// prologue); the slab test below costs about 25. It pays where most camera rays leave the scene
// (an object in front of an empty World: 04_lenna's camera rays miss its one cube 99% of the time)
// and is switched off where every camera ray meets the box (a room, a Cornell box), see
// Scene::update_camera_bounds_test.
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>

#include "scene/camera.h"

namespace smis {

struct SceneBounds {
    Vec3 lo{kInf}, hi{-kInf};  // empty: no geometry

    // [lo, hi] grown by 1e-4 of the scene's size, for Embree's own rounding near the box's faces.
    static SceneBounds padded(const Vec3& lo, const Vec3& hi) {
        SceneBounds b;
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return b;
        const Vec3 extent = hi - lo;
        const float scale = std::max({extent.x, extent.y, extent.z, std::fabs(lo.x), std::fabs(lo.y), std::fabs(lo.z),
                                      std::fabs(hi.x), std::fabs(hi.y), std::fabs(hi.z)});
        const Vec3 pad(1e-4f * scale + 1e-30f);
        b.lo = lo - pad;
        b.hi = hi + pad;
        return b;
    }
    bool finite() const { return is_finite(lo) && is_finite(hi); }

    // False only when the ray surely misses the box within [tmin, tmax]: the slab test (Kay and
    // Kajiya 1986), each axis narrowing the interval [t0, t1] of distances inside the box. Each
    // distance is off by a few ulps (relative 2e-7), so the interval counts as empty only when t0
    // exceeds t1 by 1e-5 of their size: a camera far from a small scene (distances of 1e4 for a
    // box of size 1) never loses a hit to rounding. A direction component 0 makes that axis'
    // distances infinite (the origin outside the slab) or NaN (on a slab plane: 0 x inf, the ray in
    // that plane); an axis with a NaN distance gives no bound and an infinite t0 fails the
    // tolerance test, so such rays (and NaN rays) stay "may meet": Embree answers them.
    bool may_meet(const Ray& r) const {
        float t0 = r.tmin, t1 = r.tmax;
        slab(lo.x, hi.x, r.o.x, r.d.x, &t0, &t1);
        slab(lo.y, hi.y, r.o.y, r.d.y, &t0, &t1);
        slab(lo.z, hi.z, r.o.z, r.d.z, &t0, &t1);
        return !(t0 - t1 > 1e-5f * (std::fabs(t0) + std::fabs(t1)));
    }

private:
    static void slab(float lo, float hi, float o, float d, float* t0, float* t1) {
        const float inv = 1.0f / d;
        const float ta = (lo - o) * inv, tb = (hi - o) * inv;
        if (!(ta == ta && tb == tb)) return;  // NaN: no bound from this axis
        *t0 = std::max(*t0, std::min(ta, tb));
        *t1 = std::min(*t1, std::max(ta, tb));
    }
};

}  // namespace smis
