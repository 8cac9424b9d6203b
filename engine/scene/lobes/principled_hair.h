// Cycles 3.4's Principled Hair BSDF (bsdf_hair_principled.h; Chiang, Bitterli, Tappan and Burley
// 2016, "A Practical and Controllable Hair and Fur Model for Production Path Tracing", after d'Eon et
// al. 2011 and pbrt-v3): light reflected at the fibre's surface (R), transmitted through it (TT),
// reflected once inside (TRT), and the rest (TRRT+), each a lobe
//   f_p cos = A_p(wo) M_p(theta_i, theta_o) N_p(phi),
// M_p d'Eon's longitudinal lobe of variance v_p (R: the Coat's m0, TT: v / 4, TRT and TRRT+: 4 v),
// tilted by the cuticle angle (R: -2 alpha, TT: +alpha, TRT: +4 alpha; TRRT+: none), N_p the
// logistic of scale s trimmed to one turn about the azimuth of Chiang's eq. (9) (TRRT+: uniform),
// A_p the Fresnel and absorption of path p (Chiang's eq. (3)).
//
// A_p depends on wo only (the offset h = sin gamma_o across the fibre and theta_o), so the closure op
// (shader_program.cpp) computes it at the hit and multiplies it into each lobe's weight: every lobe
// here is then weight x (M_p N_p), one scalar, and the Bsdf picks a lobe by its weight as Cycles picks
// p by A_p's grey value. The frame is the hair hit's (Scene::program_bsdf): x the tangent, z the
// tube's normal N; Cycles' frame (X = T, Y = T x wo, Z = X x Y) and h = (N x X) . Z = -wo_y / |wo_yz|
// follow from wo.
//
// Sampling is Cycles' (d'Eon's exact M_p sampling, the trimmed logistic's inverse CDF, the tilt
// applied after), and pdf() is the density of that sampler: a tilted theta is folded back at the
// poles, and the tilt changes the density by cos(theta') / cos(theta_i) (Cycles returns M_p N_p
// for both, which is the density of its sampler only without the tilt), so value / pdf =
// weight cos(theta_i) / cos(theta'). value is Cycles' eval exactly. Under hair_cycles_sampling
// (kBounceLcg) pdf() is Cycles' M_p N_p too, so the estimator is Cycles' (biased with the tilt).
//
// Lobe::alpha is v_p (after Cycles' remapping), alpha_y the logistic scale s, eta the IOR, f0.x the
// tilt of theta (radians).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

namespace principled_hair {

inline float cos_from_sin(float s) { return safe_sqrt(1.0f - s * s); }

// The two numbers Cycles 3.4 draws for the longitudinal sample (bsdf_principled_hair_sample's u[1])
// at the vertex `depth` bounces along a path: from the shading point's LCG (sample/lcg.h), seeded in
// shade_surface.h with rng_hash + rng_offset + sample * 0xb4bc3953, whose rng_offset grows by
// PRNG_BOUNCE_NUM = 16 per bounce (16 at the camera's hit). Seeds 16 apart give numbers a fixed step
// apart (mod 1): the longitudinal samples along a path are correlated, which makes Cycles' light
// bounced two or more times between strands brighter than the independent sampling's (the converged
// integral): sun-lit strands of reflectance 0.8 at 8 bounces +17%, the Principled Hair test scene
// +25%. Matching Cycles needs the same correlation: `key` stands for Cycles' per-path rng_hash +
// sample * scramble (ShaderRay::path_key).
inline Point2 cycles_bounce_lcg(uint32_t key, int depth) {
    auto step = [](uint32_t& x) { return x = 1103515245u * x + 12345u; };
    uint32_t x = key + 16u * uint32_t(depth + 1);
    step(x);  // lcg_init
    constexpr float kScale = 1.0f / float(0xFFFFFFFFu), kBelowOne = 0x1.fffffep-1f;
    float u0 = float(step(x)) * kScale, u1 = float(step(x)) * kScale;
    return {std::min(u0, kBelowOne), std::min(u1, kBelowOne)};
}

// d'Eon et al.'s longitudinal lobe M_p at variance v (Cycles' longitudinal_scattering), in log space
// for small v, where I0 and exp overflow. Normalised: integral M cos(theta_i) dtheta_i = 1.
inline float bessel_i0(float x) {
    x = x * x;
    float val = 1.0f + 0.25f * x, pow_x = x * x;
    double fac2 = 1.0;
    float pow4 = 16.0f;
    for (int i = 2; i < 10; ++i) {
        fac2 *= double(i) * i;
        float next = val + float(pow_x / (pow4 * fac2));
        if (next == val) return val;
        val = next;
        pow_x *= x;
        pow4 *= 4.0f;
    }
    return val;
}
inline float log_bessel_i0(float x) {
    if (x > 12.0f) return x + 0.5f * (1.0f / (8.0f * x) - std::log(2.0f * kPi) - std::log(x));
    return std::log(bessel_i0(x));
}
inline float longitudinal(float sin_i, float cos_i, float sin_o, float cos_o, float v) {
    float inv_v = 1.0f / v;
    float cos_arg = cos_i * cos_o * inv_v, sin_arg = sin_i * sin_o * inv_v;
    if (v <= 0.1f) return std::exp(log_bessel_i0(cos_arg) - sin_arg - inv_v + 0.6931f + std::log(0.5f * inv_v));
    return std::exp(-sin_arg) * bessel_i0(cos_arg) / (std::sinh(inv_v) * 2.0f * v);
}

inline float logistic(float x, float s) {
    float e = std::exp(-std::fabs(x) / s);
    return e / (s * sqr(1.0f + e));
}
inline float logistic_cdf(float x, float s) {
    float arg = -x / s;
    return arg > 88.0f ? 0.0f : 1.0f / (1.0f + std::exp(arg));
}
inline float trimmed_logistic(float x, float s) {
    float scale = 1.0f - 2.0f * logistic_cdf(-kPi, s);
    return scale > 0.0f ? logistic(x, s) / scale : 0.0f;
}
inline float sample_trimmed_logistic(float u, float s) {
    float cdf_minus_pi = logistic_cdf(-kPi, s);
    float x = -s * std::log(1.0f / (u * (1.0f - 2.0f * cdf_minus_pi) + cdf_minus_pi) - 1.0f);
    return clampf(x, -kPi, kPi);
}
inline float wrap_angle(float a) { return (a + kPi) - 2.0f * kPi * std::floor((a + kPi) / (2.0f * kPi)) - kPi; }

// What every lobe needs of wo: theta_o, Cycles' azimuth frame, gamma_o and gamma_t.
struct Outgoing {
    float sin_o, cos_o;
    Vec3 y, z;  // Cycles' Y and Z in the local frame
    float gamma_o, gamma_t;
};
inline bool outgoing(const Vec3& wo, float eta, Outgoing* o) {
    float l = std::sqrt(wo.y * wo.y + wo.z * wo.z);
    if (!(l > 0.0f)) return false;
    o->sin_o = clampf(wo.x, -1.0f, 1.0f);
    o->cos_o = cos_from_sin(o->sin_o);
    o->y = Vec3(0.0f, -wo.z / l, wo.y / l);
    o->z = Vec3(0.0f, -wo.y / l, -wo.z / l);
    float h = clampf(-wo.y / l, -1.0f, 1.0f);
    o->gamma_o = std::asin(h);
    float sin_gamma_t = h * o->cos_o / std::sqrt(eta * eta - o->sin_o * o->sin_o);
    o->gamma_t = std::asin(clampf(sin_gamma_t, -1.0f, 1.0f));
    return std::isfinite(o->gamma_t);
}

// Chiang's eq. (9): the azimuth of path p's exit, relative to wo's.
inline float delta_phi(int p, float gamma_o, float gamma_t) { return 2.0f * p * gamma_t - 2.0f * gamma_o + p * kPi; }

// A_p of the four paths at wo (Chiang's eq. (3) with Cycles' closed TRRT+ sum), for the closure op.
// sigma: the absorption coefficient.
struct Attenuation {
    Color a[4];
};
inline Attenuation attenuation(float sin_o, float abs_h, float eta, const Color& sigma) {
    float cos_o = cos_from_sin(sin_o);
    float sin_t = sin_o / eta, cos_t = cos_from_sin(sin_t);
    float cos_gamma_o = cos_from_sin(abs_h);
    float sin_gamma_t = abs_h * cos_o / std::sqrt(eta * eta - sin_o * sin_o);
    float cos_gamma_t = cos_from_sin(sin_gamma_t);
    float path = 2.0f * cos_gamma_t / cos_t;
    Color tr(std::exp(-sigma.x * path), std::exp(-sigma.y * path), std::exp(-sigma.z * path));
    float f = fresnel_dielectric(cos_o * cos_gamma_o, eta);
    Attenuation at;
    at.a[0] = Color(f);
    at.a[1] = tr * sqr(1.0f - f);
    at.a[2] = at.a[1] * tr * f;
    Color tf = tr * f, rest;
    for (int c = 0; c < 3; ++c) rest[c] = tf[c] < 1.0f ? tf[c] / (1.0f - tf[c]) : 0.0f;
    at.a[3] = at.a[2] * rest;
    return at;
}

}  // namespace principled_hair

// Path P (0 R, 1 TT, 2 TRT, 3 TRRT+) of the Principled Hair BSDF.
template <int P>
struct PrincipledHairLobe : LobeDefaults<PrincipledHairLobe<P>> {
    static constexpr LobeKind kKind = LobeKind(int(LobeKind::PrincipledHairR) + P);
    static constexpr const char* kName = P == 0 ? "principled_hair_r"
                                         : P == 1 ? "principled_hair_tt"
                                         : P == 2 ? "principled_hair_trt"
                                                  : "principled_hair_trrt";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    // Lobe::variant: the longitudinal sample takes Cycles' per-bounce LCG numbers in kind_colour.x, y
    // (cycles_bounce_lcg) instead of the path's own.
    static constexpr uint8_t kBounceLcg = 1;

    static bool is_delta(const Lobe&) { return false; }

    // The density of the sampler's theta_i (the tilted, folded d'Eon lobe) over cos(theta_i), and
    // Cycles' M_p at theta_i (its value).
    static void theta_terms(const principled_hair::Outgoing& o, float sin_i, float cos_i, float v, float tilt,
                            float* density, float* value) {
        using namespace principled_hair;
        float theta_i = std::atan2(sin_i, cos_i);
        float t0 = theta_i - tilt;
        *value = longitudinal(std::sin(t0), std::fabs(std::cos(t0)), o.sin_o, o.cos_o, v);
        // Preimages of theta_i under theta' -> fold(theta' + tilt): theta_i - tilt, and its mirror
        // images about either pole.
        float sum = 0.0f;
        for (float t : {t0, kPi - theta_i - tilt, -kPi - theta_i - tilt})
            if (std::fabs(t) <= 0.5f * kPi) sum += longitudinal(std::sin(t), std::cos(t), o.sin_o, o.cos_o, v) * std::cos(t);
        *density = cos_i > 0.0f ? sum / cos_i : 0.0f;
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        using namespace principled_hair;
        Outgoing o;
        if (!outgoing(wo, lobe.eta, &o)) return {};
        float sin_i = clampf(wi.x, -1.0f, 1.0f), cos_i = cos_from_sin(sin_i);
        float density, value;
        theta_terms(o, sin_i, cos_i, lobe.alpha, P < 3 ? lobe.f0.x : 0.0f, &density, &value);
        float phi = std::atan2(dot(wi, o.z), dot(wi, o.y)) + 0.5f * kPi;  // phi_i - phi_o, phi_o = -pi/2
        float np = P < 3 ? trimmed_logistic(wrap_angle(phi - delta_phi(P, o.gamma_o, o.gamma_t)), lobe.alpha_y)
                         : 0.5f * kInvPi;
        LobeTerms t;
        t.geom = value * np;
        // Cycles' sampler (kBounceLcg, hair_cycles_sampling) returns M_p N_p, its eval, as its pdf
        // (bsdf_principled_hair_sample's F_energy), so its value / pdf is the lobe's weight whatever
        // the tilt, and the same pdf weighs its MIS; with the tilt that is not its sampler's density
        // (Cycles' bias, which the setting copies: principled_color 0.8% darker than with density).
        t.pdf = (lobe.variant == kBounceLcg ? value : density) * np;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        using namespace principled_hair;
        Outgoing o;
        if (!outgoing(wo, lobe.eta, &o)) return {};
        // d'Eon's exact sampling of M_p about theta_o, then the tilt (folded at the poles as Cycles'
        // |cos|), then the azimuth. u_event drives theta's second dimension; both of theta's numbers
        // are Cycles' per-bounce LCG's where the closure set them (kBounceLcg).
        float v = lobe.alpha;
        if (lobe.variant == kBounceLcg) {
            u.x = lobe.kind_colour.x;
            u_event = lobe.kind_colour.y;
        }
        float u0 = std::max(u.x, 1e-5f);
        float fac = 1.0f + v * std::log(u0 + (1.0f - u0) * std::exp(-2.0f / v));
        float sin_t = -fac * o.sin_o + cos_from_sin(fac) * std::cos(2.0f * kPi * u_event) * o.cos_o;
        float theta = std::asin(clampf(sin_t, -1.0f, 1.0f)) + (P < 3 ? lobe.f0.x : 0.0f);
        float sin_i = std::sin(theta), cos_i = std::fabs(std::cos(theta));
        float phi = P < 3 ? delta_phi(P, o.gamma_o, o.gamma_t) + sample_trimmed_logistic(u.y, lobe.alpha_y)
                          : 2.0f * kPi * u.y;
        float phi_i = phi - 0.5f * kPi;
        Vec3 wi = Vec3(sin_i, 0.0f, 0.0f) + o.y * (cos_i * std::cos(phi_i)) + o.z * (cos_i * std::sin(phi_i));
        return lobe_sample_at<PrincipledHairLobe>(lobe, wo, normalize(wi), wi.z < 0.0f, 1.0f);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

using PrincipledHairRLobe = PrincipledHairLobe<0>;
using PrincipledHairTTLobe = PrincipledHairLobe<1>;
using PrincipledHairTRTLobe = PrincipledHairLobe<2>;
using PrincipledHairTRRTLobe = PrincipledHairLobe<3>;

}  // namespace smis
