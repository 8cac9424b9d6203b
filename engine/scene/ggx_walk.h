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
// By default the engine does not walk at render time: scene/tools/ggx_multiple_gen.cpp tabulates where
// the walks of more than one bounce leave (lobes/multiscatter_ggx.h evaluates that table), and the tests
// compare the table with fresh walks. Only the setting multiscatter_cycles_walk walks per sample and per
// evaluation, as Cycles does (cycles_eval, cycles_pdf below; lobes/multiscatter_walk.h). glass_walk() is the dielectric walk of Cycles' multiscatter glass
// (mf_sample with the glass phase function), tabulated by scene/tools/ggx_glass_gen.cpp for
// lobes/glass_multiple.h.
#pragma once
#include <algorithm>
#include <cmath>
#include <utility>

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
// rand() returning uniform numbers in [0, 1). on_bounce(cos_i) sees every bounce's w.wm (what Cycles'
// interpolated Fresnel colour of the Principled reflection reads).
template <class Surface, class Rand, class OnBounce>
Exit walk_on(const Vec3& wi, const Surface& surface, Rand& rand, OnBounce&& on_bounce) {
    State s;
    s.dir = -wi;
    s.lam = surface.lam(s.dir);
    for (int bounces = 0; bounces < kMaxBounces; ++bounces) {
        if (!next_height(&s, rand())) return {s.dir, bounces};
        float uy = rand(), ux = rand();
        Vec3 back = -s.dir;
        Vec3 wm = surface.normal(back, ux, uy);
        float cos_i = dot(back, wm);
        on_bounce(cos_i);
        s.dir = wm * (2.0f * cos_i) - back;
        s.lam = surface.lam(s.dir);
        s.escape = escape_probability(s.dir, s.cdf, s.lam);
    }
    return {Vec3(0, 0, 1), 0};
}
template <class Surface, class Rand>
Exit walk_on(const Vec3& wi, const Surface& surface, Rand& rand) {
    return walk_on(wi, surface, rand, [](float) {});
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

// Cycles' interpolate_fresnel_color: cspec0 (1 - FH) + FH with FH the dielectric Fresnel at cos_i
// normalised between F0 = F(1) and 1, at the closure's IOR eta (on either side of a glass interface).
inline Color fresnel_colour(float cos_i, float eta, const Color& cspec0) {
    float f0 = dielectric_fresnel(1.0f, eta);
    float fh = (dielectric_fresnel(cos_i, eta) - f0) * (1.0f / (1.0f - f0));
    return cspec0 * (1.0f - fh) + Color(fh);
}

// One bounce of the dielectric walk off microfacet wm for a ray arriving from `back` (back.wm = cos_i) at
// relative IOR rel, u uniform in [0, 1): reflection with the Fresnel probability, else refraction, the
// refracted direction mirrored onto the other side (Cycles' mf_sample_phase_glass, then wr = -wr). True
// when it reflected.
inline bool glass_bounce(const Vec3& back, const Vec3& wm, float cos_i, float rel, float u, Vec3* dir) {
    if (u < dielectric_fresnel(cos_i, rel)) {
        *dir = wm * (2.0f * cos_i) - back;
        return true;
    }
    float inv = 1.0f / rel;
    float cos_t = -safe_sqrt(1.0f - (1.0f - cos_i * cos_i) * inv * inv);
    *dir = -normalize(wm * (cos_i * inv + cos_t) - back * inv);
    return false;
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
        float cos_i = dot(back, wm);
        bool reflected = glass_bounce(back, wm, cos_i, outside ? eta : 1.0f / eta, rand(), &s.dir);
        on_bounce(std::fabs(cos_i), !reflected);
        if (!reflected) {
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

// ---------------------------------------------------------------------------------------------
// Cycles' own estimator of the glossy closure, for the setting multiscatter_cycles_walk
// (lobes/multiscatter_walk.h): its light-sample evaluation (mf_eval) and its MIS density (mf_pdf).

// The GGX normal distribution of the two microsurfaces, with Cycles' floor on the denominator
// (bsdf_microfacet_multi.h's D_ggx, D_ggx_aniso).
inline float distribution(const Vec3& wm, float alpha) {
    float z2 = wm.z * wm.z, a2 = alpha * alpha;
    float t = (1.0f - z2) + a2 * z2;
    return a2 / std::max(kPi * t * t, 1e-7f);
}
inline float distribution(const Vec3& wm, float ax, float ay) {
    float sx = -wm.x / ax, sy = -wm.y / ay;
    float t = wm.z * wm.z + sx * sx + sy * sy;
    return 1.0f / std::max(kPi * t * t * ax * ay, 1e-7f);
}
inline float distribution(const Vec3& wm, const Isotropic& s) { return distribution(wm, s.alpha); }
inline float distribution(const Vec3& wm, const Anisotropic& s) { return distribution(wm, s.ax, s.ay); }

// The density that a ray travelling along w (height CDF and Lambda of the walk) reflects towards
// `out` at its next microfacet, before the shadowing of `out` (Heitz et al. 2016, eq. 32: D_w(wm) / (4 |w.wm|)
// with the visible-normal density of the moving ray; Cycles' mf_eval_phase_glossy).
template <class Surface>
float phase_towards(const Vec3& w, float lam, const Vec3& out, const Surface& surface) {
    if (w.z > 0.9999f) return 0.0f;
    Vec3 wh = normalize(out - w);
    if (wh.z < 0.0f) return 0.0f;
    float projected_area = w.z < -0.9999f ? 1.0f : lam * w.z;
    float cos_h = dot(-w, wh);
    if (cos_h < 0.0f) return 0.0f;
    return cos_h * 0.25f / std::max(projected_area * cos_h, 1e-7f) * distribution(wh, surface);
}

// Cycles' colours of the glossy walk: the Glossy / Anisotropic BSDF's colour at every bounce after the
// first, or (fresnel, the Principled BSDF's one reflection closure MICROFACET_MULTI_GGX_FRESNEL) the
// interpolated Fresnel colour of cspec0 at the specular IOR eta at every bounce.
struct GlossyColours {
    Color colour{1.0f};
    bool fresnel = false;
    Color cspec0{1.0f};
    float eta = 1.5f;
};

// Cycles' light-sample evaluation of its Multiscatter GGX glossy closure (mf_eval, glossy
// phase function, colours): f(view, light) cos(light) per channel, without the closure's weight. A
// stochastic estimate, rand() uniform in [0, 1) (Cycles: its shading point's LCG). As Cycles:
//  * it walks from the shallower of the two directions (light and view swapped where the light is
//    steeper), scaling the result by cos(light) / cos(view) there; the walk is not reciprocal, so
//    where the view is the shallower this is the sampled walk's BSDF (Heitz et al. 2016, sec. 5: next-event
//    estimation of the phase function towards the exit at every bounce after the first, times the
//    exit's shadowing from the current height) and elsewhere it is not;
//  * the single scattering (order 0) analytically: D G2 / (4 cos_start), G2 height-correlated;
//  * each further bounce's term is the phase times the throughput, times the throughput again
//    (Cycles' `phase = ... * throughput; eval += throughput * phase * G1`): c^(2k) after k bounces, where
//    its sampled walk has c^k;
//  * at most kMaxBounces heights, the last bounce not reflected.
//
// With Fresnel colours (Cycles' use_fresnel) the throughput starts at the Fresnel colour at the half
// vector of view and light, which also colours the order-0 term; the first bounce keeps it, each
// further bounce multiplies the Fresnel colour at its microfacet; no colour.
template <class Surface, class Rand>
Color cycles_eval(Vec3 view, Vec3 light, const Surface& surface, const GlossyColours& colours, Rand&& rand) {
    const bool swapped = light.z < view.z;
    if (swapped) std::swap(view, light);
    if (view.z < 1e-5f || light.z < 1e-5f) return Color(0.0f);
    const float lam_out = surface.lam(light);
    State s;
    s.dir = -view;
    s.lam = surface.lam(s.dir);
    const float g2 = 1.0f / (1.0f - (s.lam + 1.0f) + lam_out);  // 1 / (1 + Lambda(view) + Lambda(light))
    const Vec3 wh = normalize(view + light);
    Color eval(g2 * 0.25f / view.z * distribution(wh, surface));
    Color throughput(1.0f);
    if (colours.fresnel) {
        throughput = fresnel_colour(dot(view, wh), colours.eta, colours.cspec0);
        eval *= throughput;
    }
    for (int order = 0; order < kMaxBounces; ++order) {
        if (!next_height(&s, rand())) break;
        float uy = rand(), ux = rand();
        Vec3 back = -s.dir;
        Vec3 wm = surface.normal(back, ux, uy);
        if (order > 0)
            eval += throughput * throughput *
                    (phase_towards(s.dir, s.lam, light, surface) * escape_probability(light, s.cdf, lam_out));
        if (order + 1 < kMaxBounces) {
            float cos_i = dot(back, wm);
            if (colours.fresnel && order > 0) throughput *= fresnel_colour(cos_i, colours.eta, colours.cspec0);
            s.dir = wm * (2.0f * cos_i) - back;
            s.lam = surface.lam(s.dir);
            s.escape = escape_probability(s.dir, s.cdf, s.lam);
            if (!colours.fresnel) throughput *= colours.colour;
        }
    }
    if (swapped) eval *= view.z / light.z;  // view and light are swapped here: cos(light) / cos(view)
    return eval;
}
template <class Surface, class Rand>
Color cycles_eval(Vec3 view, Vec3 light, const Surface& surface, const Color& c, Rand&& rand) {
    GlossyColours colours;
    colours.colour = c;
    return cycles_eval(view, light, surface, colours, rand);
}

// Cycles' fit of the single-scattering GGX albedo at alpha r (mf_ggx_albedo): the share of its MIS
// density given to the single scattering.
inline float cycles_single_albedo(float r) {
    float a = 0.806495f * std::exp(-1.98712f * r * r) + 0.199531f;
    a -= ((((((1.76741f * r - 8.43891f) * r + 15.784f) * r - 14.398f) * r + 6.45221f) * r - 1.19722f) * r +
          0.027803f) * r + 0.00568739f;
    return clampf(a, 0.0f, 1.0f);
}

// Cycles' MIS density of the closure (mf_ggx_pdf, mf_ggx_aniso_pdf): not the density its walk samples,
// an approximation, the single scattering's visible-normal density weighted by the fitted albedo and
// a cosine lobe for the rest.
template <class Surface>
float cycles_pdf(const Vec3& view, const Vec3& light, const Surface& surface, float fit_alpha) {
    if (!(view.z > 0.0f) || !(light.z > 0.0f)) return 0.0f;
    float d = distribution(normalize(view + light), surface);
    float single = 0.25f * d / std::max((1.0f + surface.lam(view)) * view.z, 1e-7f);
    float a = cycles_single_albedo(fit_alpha);
    return a * single + (1.0f - a) * light.z * kInvPi;
}

}  // namespace smis::ggx_walk
