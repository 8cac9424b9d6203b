// Sampling warps, each paired with the density of what it returns, so callers can use the value in MIS.
#pragma once
#include "core/math.h"

namespace smis {

struct Point2 {
    float x = 0, y = 0;
};

[[gnu::always_inline]] inline Point2 sample_uniform_disk_concentric(Point2 u) {
    float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    if (ox == 0.0f && oy == 0.0f) return {0.0f, 0.0f};
    float r, theta;
    if (std::fabs(ox) > std::fabs(oy)) {
        r = ox;
        theta = (kPi / 4.0f) * (oy / ox);
    } else {
        r = oy;
        theta = kPi / 2.0f - (kPi / 4.0f) * (ox / oy);
    }
    return {r * std::cos(theta), r * std::sin(theta)};
}
inline float uniform_disk_pdf() { return kInvPi; }  // on the unit disk, area measure

// Uniform point on the regular polygon with `corners` >= 3 corners on the unit circle, one corner
// at angle `rotation` + pi/corners (Cycles' bokeh polygon): a corner wedge chosen by u.x, then a
// uniform point in that triangle. pdf 1/area.
inline Point2 sample_regular_polygon(int corners, float rotation, Point2 u) {
    float scaled = u.x * corners;
    int k = std::min(corners - 1, static_cast<int>(scaled));
    float v = scaled - k;  // reused: uniform in [0, 1) again
    // Uniform in the triangle (centre, corner k, corner k+1): r = sqrt for area, then along the edge.
    float r = std::sqrt(v), t = u.y;
    float half = kPi / corners;
    Point2 p{r * std::cos(half), r * (2.0f * t - 1.0f) * std::sin(half)};
    float a = rotation + 2.0f * half * k;
    float c = std::cos(a), s = std::sin(a);
    return {c * p.x - s * p.y, s * p.x + c * p.y};
}
inline float regular_polygon_area(int corners) {
    return 0.5f * corners * std::sin(2.0f * kPi / corners);
}

// Cosine-weighted hemisphere around +z; pdf in solid angle. Always inlined: every diffuse bounce
// samples it, and with more lobe kinds in the dispatch the compiler stopped inlining it (+1.1% of
// cornell's instructions with the call).
[[gnu::always_inline]] inline Vec3 sample_cosine_hemisphere(Point2 u) {
    Point2 d = sample_uniform_disk_concentric(u);
    float z = safe_sqrt(1.0f - d.x * d.x - d.y * d.y);
    return {d.x, d.y, z};
}
inline float cosine_hemisphere_pdf(float cos_theta) { return cos_theta > 0.0f ? cos_theta * kInvPi : 0.0f; }

inline Vec3 sample_uniform_sphere(Point2 u) {
    float z = 1.0f - 2.0f * u.x;
    float r = safe_sqrt(1.0f - z * z);
    float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_sphere_pdf() { return kInv4Pi; }

// Uniform over the hemisphere around +z (z = 1 - u.x in (0, 1]); pdf in solid angle.
inline Vec3 sample_uniform_hemisphere(Point2 u) {
    float z = 1.0f - u.x;
    float r = safe_sqrt(1.0f - z * z);
    float phi = 2.0f * kPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}
inline float uniform_hemisphere_pdf() { return 0.5f * kInvPi; }

// Uniform direction in the cone around +z whose half-angle has 1 - cos = one_minus_cos (passed
// directly because 1 - cos loses all precision for small cones such as the sun's); pdf in solid angle.
inline Vec3 sample_uniform_cone(Point2 u, float one_minus_cos) {
    float cos_t = 1.0f - u.x * one_minus_cos;
    float sin_t = safe_sqrt(u.x * one_minus_cos * (2.0f - u.x * one_minus_cos));
    float phi = 2.0f * kPi * u.y;
    return {std::cos(phi) * sin_t, std::sin(phi) * sin_t, cos_t};
}
inline float uniform_cone_pdf(float one_minus_cos) { return 1.0f / (2.0f * kPi * one_minus_cos); }

// Directions around +z whose polar angle theta is uniform in [0, theta_max] and azimuth uniform: in
// solid angle (d omega = sin theta d theta d phi) the density is
//   p(omega) = 1 / (2 pi theta_max sin theta)   for theta < theta_max, else 0,
// which is ~ 1 / (2 pi theta_max theta) near the axis and integrates to 1 exactly. It matches the
// 1 / theta profile of the light scattered by a medium towards a point light seen along +z
// (integrators/glow_directions.h). *pdf is 0 for the axis itself (theta = 0, probability zero).
inline Vec3 sample_glow_cone(Point2 u, float theta_max, float* pdf) {
    const float theta = u.x * theta_max;
    const float sin_t = std::sin(theta), cos_t = std::cos(theta);
    const float phi = 2.0f * kPi * u.y;
    *pdf = sin_t > 0.0f ? 1.0f / (2.0f * kPi * theta_max * sin_t) : 0.0f;
    return {std::cos(phi) * sin_t, std::sin(phi) * sin_t, cos_t};
}
// The density of sample_glow_cone at the direction with cos theta = cos_t, sin theta = sin_t >= 0.
inline float glow_cone_pdf(float cos_t, float sin_t, float theta_max) {
    if (!(sin_t > 0.0f) || !(std::atan2(sin_t, cos_t) < theta_max)) return 0.0f;
    return 1.0f / (2.0f * kPi * theta_max * sin_t);
}

// Uniform point on a triangle as barycentrics (b1, b2) (Heitz 2019 low-distortion map); pdf 1/area.
inline Point2 sample_uniform_triangle(Point2 u) {
    float b0, b1;
    if (u.x < u.y) {
        b0 = u.x / 2.0f;
        b1 = u.y - b0;
    } else {
        b1 = u.y / 2.0f;
        b0 = u.x - b1;
    }
    return {b0, b1};
}

// Multiple importance sampling heuristics for two techniques with one sample each.
enum class MisHeuristic { Balance, Power };
inline float mis_weight(MisHeuristic h, float pdf_this, float pdf_other) {
    if (h == MisHeuristic::Power) {
        pdf_this *= pdf_this;
        pdf_other *= pdf_other;
    }
    float denom = pdf_this + pdf_other;
    if (!(denom > 0.0f) || !std::isfinite(denom)) return pdf_this > pdf_other ? 1.0f : 0.0f;
    return pdf_this / denom;
}

}  // namespace smis
