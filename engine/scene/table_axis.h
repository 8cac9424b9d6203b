// Multilinear lookups in the build-time walk tables (scene/ggx_multiple.cpp, scene/ggx_glass.cpp):
// where a coordinate falls on an axis of samples, flat beyond the outermost ones.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace smis::table_axis {

// A coordinate x on an axis of n samples: the lower sample and the weight of the upper one.
struct Axis {
    int lo;
    float t;
};
inline Axis axis(float x, int n) {
    x = clampf(x, 0.0f, float(n - 1));  // also maps NaN to 0
    int lo = std::min(int(x), n - 2);
    return {lo, x - float(lo)};
}
// Roughness sqrt(alpha) on n rows from 0 to 1.
inline Axis rough_axis(float alpha, int n) { return axis(std::sqrt(clampf(alpha, 0.0f, 1.0f)) * float(n - 1), n); }
// A value in [0, 1] on n cells sampled at their centres (the incident cosine).
inline Axis centred_axis(float x, int n) { return axis(x * float(n) - 0.5f, n); }
// The azimuth between the projections of wo and wi (0: wi on wo's side of the normal) on n cells of [0, pi].
inline Axis azimuth_axis(const Vec3& wo, const Vec3& wi, int n) {
    float lo = std::sqrt(wo.x * wo.x + wo.y * wo.y), li = std::sqrt(wi.x * wi.x + wi.y * wi.y);
    float cos_phi = lo > 0.0f && li > 0.0f ? clampf((wo.x * wi.x + wo.y * wi.y) / (lo * li), -1.0f, 1.0f) : 1.0f;
    return centred_axis(std::acos(cos_phi) * kInvPi, n);
}

inline float interp(float t, float a, float b) { return a + (b - a) * t; }
// The weight of sample lo + k (k = 0 or 1) of an axis.
inline float weight(const Axis& a, int k) { return k ? a.t : 1.0f - a.t; }

}  // namespace smis::table_axis
