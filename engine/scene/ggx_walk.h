// The random walk on the GGX microsurface that Cycles 3.4 uses for its Multiscatter GGX glossy closure
// (Heitz, Hanika, d'Eon and Dachsbacher 2016, "Multiple-Scattering Microfacet BSDFs with the Smith
// Model", SIGGRAPH; Cycles' bsdf_microfacet_multi_impl.h, mf_sample with the glossy phase function and
// no Fresnel): the ray enters at height 1, the height of its next intersection with the uncorrelated
// Smith microsurface is sampled from the masking function (a uniform height distribution), the
// microfacet normal there from the visible normals of the direction it travels, and the ray reflects
// about it; it leaves when the height sampling says it escapes, or dies after 10 bounces as in Cycles.
// The same walk runs on the anisotropic microsurface (alpha_x, alpha_y: Anisotropic, walk(wi, ax, ay)),
// tabulated by scene/tools/ggx_aniso_gen.cpp for lobes/multiscatter_aniso_ggx.h.
//
// The engine does not walk at render time: scene/tools/ggx_multiple_gen.cpp tabulates where the walks
// of more than one bounce leave (lobes/multiscatter_ggx.h evaluates that table), and the tests compare
// the table with fresh walks. glass_walk() is the dielectric walk of Cycles' multiscatter glass
// (mf_sample with the glass phase function), tabulated by scene/tools/ggx_glass_gen.cpp for
// lobes/glass_multiple.h.
#pragma once
#include <cmath>

#include "core/math.h"

namespace smis::ggx_walk {

constexpr int kMaxBounces = 10;  // Cycles' walks stop after 10 bounces, losing what is left

// Smith's Lambda of GGX for a direction travelling up (> 0) or down (< 0): for a downward direction
// the masking of the reversed ray, negated and minus one (Heitz 2016, supplemental, p. 12).
inline float lambda(const Vec3& w, float alpha) {
    if (w.z > 0.9999f) return 0.0f;
    if (w.z < -0.9999f) return -0.9999f;
    float inv_z2 = 1.0f / std::max(w.z * w.z, 1e-7f);
    float v = std::sqrt(1.0f + alpha * alpha * (w.x * w.x + w.y * w.y) * inv_z2);
    return 0.5f * ((w.z <= 0.0f ? -v : v) - 1.0f);
}

// The height distribution's CDF (uniform on [-1, 1]) and its inverse.
inline float height_cdf(float h) { return clampf(0.5f * (h + 1.0f), 0.0f, 1.0f); }
inline float height_of_cdf(float c) { return 2.0f * clampf(c, 0.0f, 1.0f) - 1.0f; }

// The probability that an upward ray at the height of CDF c escapes: c^Lambda.
inline float escape_probability(const Vec3& w, float c, float lam) {
    if (w.z > 0.9999f) return 1.0f;
    if (w.z < 1e-5f) return 0.0f;
    return std::pow(c, lam);
}

struct State {
    Vec3 dir;              // the direction the ray travels
    float lam = 0.0f;      // lambda(dir)
    float cdf = 1.0f;      // the height's CDF (the ray starts at the top)
    float escape = 0.0f;   // escape_probability(dir, cdf, lam)
};

// The next intersection's height; false when the ray leaves the surface.
inline bool next_height(State* s, float u) {
    if (s->dir.z > 0.9999f) return false;
    if (s->dir.z < -0.9999f) {
        s->cdf *= u;
    } else if (std::fabs(s->dir.z) >= 1e-4f) {
        if (u > 1.0f - s->escape) return false;
        // As Cycles: a ray travelling up that hits again does so at the top of the height range.
        s->cdf = s->lam >= 0.0f ? 1.0f : s->cdf * std::pow(1.0f - u, -1.0f / s->lam);
    }
    s->escape = escape_probability(s->dir, s->cdf, s->lam);
    return true;
}

// Slopes of the visible normals of the unit-roughness configuration for a direction of cosine cos_i
// (Heitz 2014's sampling of P22_wi, in the supplemental's rational approximation of the inverse CDF).
inline void sample_unit_slopes(float cos_i, float ux, float uy, float* sx, float* sy) {
    if (cos_i > 0.9999f || std::fabs(cos_i) < 1e-6f) {
        float r = std::sqrt(ux / std::max(1.0f - ux, 1e-7f)), phi = 2.0f * kPi * uy;
        *sx = r * std::cos(phi);
        *sy = r * std::sin(phi);
        return;
    }
    float sin_i = safe_sqrt(1.0f - cos_i * cos_i), tan_i = sin_i / cos_i;
    float proj = 0.5f * (cos_i + 1.0f);
    *sx = *sy = 0.0f;
    if (proj < 1e-4f) return;
    float a = 2.0f * ux * proj / cos_i - 1.0f;
    float t = a * a - 1.0f;
    if (std::fabs(t) < 1e-7f) return;
    t = 1.0f / t;
    float d = safe_sqrt(tan_i * tan_i * t * t - (a * a - tan_i * tan_i) * t);
    float x2 = tan_i * t + d;
    *sx = (a < 0.0f || x2 > 1.0f / tan_i) ? tan_i * t - d : x2;
    float u2 = uy >= 0.5f ? 2.0f * (uy - 0.5f) : 2.0f * (0.5f - uy);
    float z = (u2 * (u2 * (u2 * 0.27385f - 0.73369f) + 0.46341f)) /
              (u2 * (u2 * (u2 * 0.093073f + 0.309420f) - 1.0f) + 0.597999f);
    *sy = (uy >= 0.5f ? 1.0f : -1.0f) * z * std::sqrt(1.0f + *sx * *sx);
}

// The anisotropic microsurface of Cycles' anisotropic Multiscatter GGX (alpha_x along the tangent x,
// alpha_y across it): Lambda of the stretched direction (Cycles' mf_lambda with a float2 alpha) and
// a microfacet normal visible from w (Cycles' mf_sample_vndf: stretch by (alpha_x, alpha_y), sample the
// unit slopes, rotate, unstretch).
inline float lambda(const Vec3& w, float ax, float ay) {
    if (w.z > 0.9999f) return 0.0f;
    if (w.z < -0.9999f) return -0.9999f;
    float inv_z2 = 1.0f / std::max(w.z * w.z, 1e-7f);
    float v = std::sqrt(1.0f + (sqr(ax * w.x) + sqr(ay * w.y)) * inv_z2);
    return 0.5f * ((w.z <= 0.0f ? -v : v) - 1.0f);
}
inline Vec3 visible_normal(const Vec3& w, float ax, float ay, float ux, float uy) {
    Vec3 w11 = normalize(Vec3(ax * w.x, ay * w.y, w.z));
    float sx, sy;
    sample_unit_slopes(w11.z, ux, uy, &sx, &sy);
    float len = std::sqrt(w11.x * w11.x + w11.y * w11.y);
    float c = len > 0.0f ? w11.x / len : 1.0f, s = len > 0.0f ? w11.y / len : 0.0f;
    float x = ax * (c * sx - s * sy), y = ay * (s * sx + c * sy);
    return normalize(Vec3(-x, -y, 1.0f));
}
// The isotropic one (the same arithmetic at ax = ay).
inline Vec3 visible_normal(const Vec3& w, float alpha, float ux, float uy) {
    return visible_normal(w, alpha, alpha, ux, uy);
}

// The two microsurfaces the glossy walk runs on.
struct Isotropic {
    float alpha;
    float lam(const Vec3& w) const { return lambda(w, alpha); }
    Vec3 normal(const Vec3& w, float ux, float uy) const { return visible_normal(w, alpha, ux, uy); }
};
struct Anisotropic {
    float ax, ay;
    float lam(const Vec3& w) const { return lambda(w, ax, ay); }
    Vec3 normal(const Vec3& w, float ux, float uy) const { return visible_normal(w, ax, ay, ux, uy); }
};

struct Exit {
    Vec3 dir;          // where the walk left the surface (z > 0)
    int bounces = 0;   // 1 = single scattering; 0 = the walk died (after kMaxBounces)
};

// One walk for light arriving from wi (z > 0) on the microsurface `surface` (Isotropic, Anisotropic),
// rand() returning uniform numbers in [0, 1).
template <class Surface, class Rand>
Exit walk_on(const Vec3& wi, const Surface& surface, Rand& rand) {
    State s;
    s.dir = -wi;
    s.lam = surface.lam(s.dir);
    for (int bounces = 0; bounces < kMaxBounces; ++bounces) {
        if (!next_height(&s, rand())) return {s.dir, bounces};
        float uy = rand(), ux = rand();
        Vec3 back = -s.dir;
        Vec3 wm = surface.normal(back, ux, uy);
        s.dir = wm * (2.0f * dot(back, wm)) - back;
        s.lam = surface.lam(s.dir);
        s.escape = escape_probability(s.dir, s.cdf, s.lam);
    }
    return {Vec3(0, 0, 1), 0};
}
template <class Rand>
Exit walk(const Vec3& wi, float alpha, Rand&& rand) {
    return walk_on(wi, Isotropic{alpha}, rand);
}
// The anisotropic walk, wi in the frame of the tangent (x) and n x tangent (y).
template <class Rand>
Exit walk(const Vec3& wi, float ax, float ay, Rand&& rand) {
    return walk_on(wi, Anisotropic{ax, ay}, rand);
}

// The unpolarised dielectric Fresnel reflectance at cosine c (>= 0) for relative IOR eta (the far
// side over the near one), as Cycles' fresnel_dielectric_cos; 1 under total internal reflection.
inline float dielectric_fresnel(float c, float eta) {
    c = std::fabs(c);
    float g = eta * eta - 1.0f + c * c;
    if (!(g > 0.0f)) return 1.0f;
    g = std::sqrt(g);
    float a = (g - c) / (g + c), b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    return 0.5f * a * a * (1.0f + b * b);
}

struct GlassExit {
    Vec3 dir;              // where the walk left: z > 0 back on the side it came from, z < 0 through
    int bounces = 0;       // 1 = single scattering; 0 = the walk died (after kMaxBounces)
    int refractions = 0;   // how many of the bounces refracted
};

// One walk of Cycles' multiscatter glass for a ray arriving from wi (z > 0) at an interface of relative
// IOR eta (the far side over wi's), rand() uniform in [0, 1). Each bounce reflects with the Fresnel
// probability at its microfacet, else refracts; a refracted ray continues on the other side, where the
// walk's frame is mirrored (the direction flipped, the IOR inverted). As in Cycles' mf_sample (not its
// mf_eval), the height's CDF is not mirrored with it: the walk goes on from the same CDF.
// on_bounce(cos_i, refracted) sees every bounce: cos_i = |w.wm| of the ray arriving at its microfacet
// (what Cycles' interpolated Fresnel colour of a reflection reads).
template <class Rand, class OnBounce>
GlassExit glass_walk(const Vec3& wi, float alpha, float eta, Rand&& rand, OnBounce&& on_bounce) {
    State s;
    s.dir = -wi;
    s.lam = lambda(s.dir, alpha);
    bool outside = true;
    int refractions = 0;
    for (int bounces = 0; bounces < kMaxBounces; ++bounces) {
        if (!next_height(&s, rand())) return {outside ? s.dir : -s.dir, bounces, refractions};
        float uy = rand(), ux = rand();
        Vec3 back = -s.dir;
        Vec3 wm = visible_normal(back, alpha, ux, uy);
        float rel = outside ? eta : 1.0f / eta;
        float cos_i = dot(back, wm);
        bool reflected = rand() < dielectric_fresnel(cos_i, rel);
        on_bounce(std::fabs(cos_i), !reflected);
        if (reflected) {
            s.dir = wm * (2.0f * cos_i) - back;
        } else {
            float inv = 1.0f / rel;
            float cos_t = -safe_sqrt(1.0f - (1.0f - cos_i * cos_i) * inv * inv);
            s.dir = -normalize(wm * (cos_i * inv + cos_t) - back * inv);  // mirrored onto the other side
            outside = !outside;
            ++refractions;
        }
        s.lam = lambda(s.dir, alpha);
        s.escape = escape_probability(s.dir, s.cdf, s.lam);
    }
    return {Vec3(0, 0, 1), 0, refractions};
}
template <class Rand>
GlassExit glass_walk(const Vec3& wi, float alpha, float eta, Rand&& rand) {
    return glass_walk(wi, alpha, eta, rand, [](float, bool) {});
}

}  // namespace smis::ggx_walk
