// Cycles' own estimator of its Multiscatter GGX glass closure (Blender 3.4's bsdf_microfacet_multi.h
// and bsdf_microfacet_multi_impl.h with the glass phase function), for the setting
// multiscatter_cycles_walk (lobes/multi_glass_walk.h): its light-sample evaluation (mf_eval_glass),
// its MIS density (mf_glass_pdf) and the colours its sampled walk (ggx_walk::glass_walk, mf_sample_glass)
// carries. Written from the algorithm (Heitz, Hanika, d'Eon and Dachsbacher 2016 with the dielectric
// phase function), on the same walk state as the glossy estimator (scene/ggx_walk.h).
//
// Cycles' eval is not its sampled walk (README, the material table):
//  * it walks from the shallower direction: for a transmission where the light is the shallower it
//    swaps view and light through the interface (view' = -light, light' = -view) but keeps the IOR
//    (the walk then starts inside with the outside's IOR), scaling by |cos light / cos view|;
//  * its order 0 is analytic: the phase function towards the light times the height-averaged
//    shadowing, -Lambda_v / (Lambda_l - Lambda_v) for a reflection (the height-correlated G2 / G1) and
//    -Lambda_v B(-Lambda_v, 1 + Lambda_l) for a refraction (the shadowing of the far side's mirrored
//    height, Heitz et al. 2016, supplemental); the refraction phase has no (1 / eta)^2;
//  * it mirrors the height's CDF at every refraction (its walk, mf_sample, does not);
//  * colours: without Fresnel colours (the Glass BSDF; every refraction of the Principled glass'
//    eval) the colour multiplies the throughput after every bounce; with them (the Principled
//    glass' reflections) the order-0 term and the first bounce carry the interpolated Fresnel colour
//    at the half vector of view and light, the order-0 term is replaced by a one-sample estimate at
//    the first height, and each further reflection multiplies the Fresnel colour at its microfacet,
//    each refraction the base.
#pragma once
#include <cmath>

#include "scene/ggx_walk.h"

namespace smis::ggx_walk {

// The Beta function B(x, y) (Cycles' beta(): from lgamma).
inline float beta_function(float x, float y) { return std::exp(std::lgamma(x) + std::lgamma(y) - std::lgamma(x + y)); }

// The density that a ray travelling along w (Lambda lam, from the side it is on) scatters towards
// `out` at its next microfacet, reflected (out_outside: `out` on w's side) or refracted at relative
// IOR eta, before the shadowing of `out` (Cycles' mf_eval_phase_glass): the visible-normal density times
// the Fresnel term and the Jacobian of the event, without the refraction's (1 / eta)^2.
inline float glass_phase_towards(const Vec3& w, float lam, const Vec3& out, bool out_outside, float alpha, float eta) {
    if (w.z > 0.9999f) return 0.0f;
    float projected_area = w.z < -0.9999f ? 1.0f : lam * w.z;
    float v;
    if (out_outside) {
        Vec3 wh = normalize(out - w);
        if (wh.z < 0.0f) return 0.0f;
        float cos_h = dot(-w, wh);
        v = dielectric_fresnel(cos_h, eta) * std::max(0.0f, cos_h) * distribution(wh, alpha) * 0.25f /
            (projected_area * cos_h);
    } else {
        Vec3 wh = normalize(out * eta - w);
        if (wh.z < 0.0f) wh = -wh;
        float cos_h = dot(-w, wh), cos_out = dot(out, wh);
        if (cos_h < 0.0f) return 0.0f;
        float t = cos_h + eta * cos_out;
        v = (1.0f - dielectric_fresnel(cos_h, eta)) * std::max(0.0f, cos_h) * std::max(0.0f, -cos_out) *
            distribution(wh, alpha) / (projected_area * t * t);
    }
    return std::isfinite(v) ? v : 0.0f;
}

// Cycles' colours of the glass walk: `colour` (the Glass BSDF's colour, the Principled base) and, when
// `fresnel`, the Principled reflections' interpolated Fresnel colour of cspec0 at the closure's IOR eta.
struct GlassColours {
    Color colour{1.0f};
    bool fresnel = false;
    Color cspec0{1.0f};
    float eta = 1.5f;
};

// Cycles' mf_eval_glass: f(view, light) |cos light| per channel, without the closure's weight, for
// `light` on view's side (reflection) or through the interface (z < 0), view.z > 0, relative IOR eta
// (the far side over view's). A stochastic estimate, rand() uniform in [0, 1). The caller passes
// colours.fresnel only for reflections (Cycles: use_fresnel is off for transmission).
template <class Rand>
Color cycles_glass_eval(Vec3 view, Vec3 light, float alpha, float eta, const GlassColours& colours, Rand&& rand) {
    const bool light_outside = light.z > 0.0f;
    bool swapped = false;
    if (!light_outside) {
        if (-light.z < view.z) {
            swapped = true;
            Vec3 t = -light;
            light = -view;
            view = t;
        }
    } else if (light.z < view.z) {
        swapped = true;
        std::swap(view, light);
    }
    if (view.z < 1e-5f || (light.z < 1e-5f && light_outside) || (light.z > -1e-5f && !light_outside))
        return Color(0.0f);
    const Vec3 light_up = light_outside ? light : -light;
    const float lam_out = lambda(light_up, alpha);
    State s;
    s.dir = -view;
    s.lam = lambda(s.dir, alpha);
    // Order 0: the phase function with the height-averaged shadowing of the light.
    float single = glass_phase_towards(s.dir, s.lam, light, light_outside, alpha, eta);
    single *= light_outside ? -s.lam / (lam_out - s.lam) : -s.lam * beta_function(-s.lam, lam_out + 1.0f);
    Color eval(std::isfinite(single) ? single : 0.0f);
    Color throughput(1.0f);
    if (colours.fresnel) {
        throughput = fresnel_colour(dot(view, normalize(view + light)), colours.eta, colours.cspec0);
        eval *= throughput;
    }
    bool outside = true;
    float height = 1.0f;  // Cycles' hr: mirrored with the walk at every refraction
    for (int order = 0; order < kMaxBounces; ++order) {
        if (!next_height(&s, rand())) break;
        height = height_of_cdf(s.cdf);
        float uy = rand(), ux = rand();
        Vec3 back = -s.dir;
        Vec3 wm = visible_normal(back, alpha, ux, uy);
        if (order > 0 || colours.fresnel) {
            // Next-event estimation towards the light from this microfacet, shadowed from its height on
            // the light's side.
            float phase = outside ? glass_phase_towards(s.dir, s.lam, light, light_outside, alpha, eta)
                                  : glass_phase_towards(s.dir, s.lam, -light, !light_outside, alpha, 1.0f / eta);
            float shadow = escape_probability(light_up, height_cdf(outside == light_outside ? height : -height), lam_out);
            Color term = throughput * (phase * shadow);
            if (order == 0) eval = term;  // the Fresnel-coloured order 0: one sample at the first height
            else eval += term;
        }
        if (order + 1 < kMaxBounces) {
            float cos_i = dot(back, wm);
            bool reflected = glass_bounce(back, wm, cos_i, outside ? eta : 1.0f / eta, rand(), &s.dir);
            if (!reflected) {
                outside = !outside;
                height = -height;
            }
            if (colours.fresnel && !reflected) throughput *= colours.colour;
            else if (colours.fresnel && order > 0) throughput *= fresnel_colour(cos_i, colours.eta, colours.cspec0);
            s.lam = lambda(s.dir, alpha);
            if (!colours.fresnel) throughput *= colours.colour;
            s.cdf = height_cdf(height);
            s.escape = escape_probability(s.dir, s.cdf, s.lam);
        }
    }
    if (swapped) eval *= std::fabs(view.z / light.z);
    return eval;
}

// The colour Cycles' sampled walk (mf_sample_glass) carries for one bounce, its microfacet cosine cos_i
// and whether it refracted; `first`: the walk's first bounce (the Glass BSDF's colour is in the weight
// there, the Fresnel colours start from white).
inline Color walk_bounce_colour(const GlassColours& colours, float cos_i, bool refracted, bool first) {
    if (!colours.fresnel) return first ? Color(1.0f) : colours.colour;
    return refracted ? colours.colour : fresnel_colour(cos_i, colours.eta, colours.cspec0);
}

// Cycles' fit of the single-scattering GGX glass' transmitted albedo (mf_ggx_transmission_albedo).
inline float cycles_transmission_albedo(float a, float ior) {
    if (ior < 1.0f) ior = 1.0f / ior;
    a = clampf(a, 0.0f, 1.0f);
    ior = clampf(ior, 1.0f, 3.0f);
    float i1 = 0.0476898f * std::exp(-0.978352f * (ior - 0.65657f) * (ior - 0.65657f)) - 0.033756f * ior + 0.993261f;
    float r1 = (((0.116991f * a - 0.270369f) * a + 0.0501366f) * a - 0.00411511f) * a + 1.00008f;
    float i2 = (((-2.08704f * ior + 26.3298f) * ior - 127.906f) * ior + 292.958f) * ior - 287.946f +
               199.803f / (ior * ior) - 101.668f / (ior * ior * ior);
    float r2 = ((((5.3725f * a - 24.9307f) * a + 22.7437f) * a - 3.40751f) * a + 0.0986325f) * a + 0.00493504f;
    return clampf(1.0f + i2 * r2 * 0.0019127f - (1.0f - i1) * (1.0f - r1) * 9.3205f, 0.0f, 1.0f);
}

// Cycles' MIS density of the glass closure (mf_glass_pdf): the Fresnel term at the half vector picks
// reflection or refraction, each the single scattering's visible-normal density weighted by a fitted
// albedo plus a cosine lobe for the rest. Not the density its walk samples.
inline float cycles_glass_pdf(const Vec3& view, const Vec3& light, float alpha, float eta) {
    const bool reflective = view.z * light.z > 0.0f;
    Vec3 h = view + (reflective ? light : light * eta);
    float len = length(h);
    if (!(len > 0.0f)) return 0.0f;
    Vec3 wh = h / len;
    if (wh.z < 0.0f) wh = -wh;
    Vec3 r_view = view.z < 0.0f ? -view : view;
    float lam = lambda(r_view, alpha);
    float d = distribution(wh, alpha);
    float f = dielectric_fresnel(dot(r_view, wh), eta);
    float multiple = std::fabs(light.z * kInvPi);
    float pdf;
    if (reflective) {
        float single = 0.25f * d / std::max((1.0f + lam) * r_view.z, 1e-7f);
        float a = cycles_single_albedo(alpha);
        pdf = f * (a * single + (1.0f - a) * multiple);
    } else {
        float single = std::fabs(dot(r_view, wh) * dot(light, wh) * d * eta * eta /
                                 std::max((1.0f + lam) * r_view.z * len * len, 1e-7f));
        float a = cycles_transmission_albedo(alpha, eta);
        pdf = (1.0f - f) * (a * single + (1.0f - a) * multiple);
    }
    return std::isfinite(pdf) ? std::max(pdf, 0.0f) : 0.0f;
}

}  // namespace smis::ggx_walk
