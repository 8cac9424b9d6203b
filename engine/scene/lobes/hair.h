// Cycles 3.4's Hair BSDF (bsdf_hair.h): a Marschner-style fibre lobe pair, reflection (R) and
// transmission (TT), each its own closure in Cycles and its own kind here. The shading frame of a
// hair hit (Scene::program_bsdf) has the fibre's tangent T as x and the tube's normal N as z.
//
// Both lobes live in the fibre's longitudinal angle theta (asin of a direction's component along
// T) and its azimuth phi about T, measured from wo's projection across the fibre (Cycles' locy).
// With theta_r of wo, r1 = Roughness U, r2 = Roughness V (both clamped to [0.001, 1] as Cycles) and
// Offset o (the cuticle tilt, radians):
//   theta part  t = (theta_i + theta_r) / 2 - o is Cauchy-distributed with scale r1, restricted so
//               theta_i stays in [-pi/2, pi/2]: p(theta_i) = r1 / (2 (t^2 + r1^2) (A - B)),
//               A, B = atan(((+-pi/2 + theta_r) / 2 - o) / r1);
//   R azimuth   phi = 2 r2 asin(1 - 2u), p(phi) = cos(phi / (2 r2)) / (4 r2) for |phi| < pi r2;
//   TT azimuth  Cauchy about phi = pi with scale r2.
// A solid-angle density is p(theta_i) p(phi) / cos(theta_i). Cycles' closures are "their own
// density": eval = pdf. Cycles' sampling and evaluation disagree, though, and since it samples with
// one and lights with the other its image mixes the two; ours is one consistent BSDF, Cycles' eval
// (what its light samples, the image's direct light, see):
//  * R: eval is zero for wi below N and for wi on the far half of the azimuth (cos phi < 0); Cycles'
//    sampler produces such directions and counts them with value/pdf = 1 (the path goes on). Ours
//    samples the same density and values them 0, so value/pdf is 1 or 0.
//  * TT: eval is zero for wi above N and its azimuth term is the Cauchy density normalised over
//    |phi - pi| <= pi/2, c = 2 atan(pi / (2 r2)), but evaluated for any |phi - pi| <= pi, where
//    Cycles' sampler never goes: eval holds up to 26% more than the sampler reaches (r2 = 1). Ours
//    samples the Cauchy over the whole |phi - pi| <= pi (c' = 2 atan(pi / r2)), so every direction
//    eval lights is sampled; value/pdf is c' / c or 0.
// Labelled glossy, as in Cycles. A sample is a transmission when it leaves through the fibre (wi
// below N, eta 1), whichever lobe drew it (the other side's samples carry 0).
// Lobe::alpha is r1, Lobe::alpha_y r2, Lobe::f0.x the Offset in radians.
// Variant kCyclesSampler (the setting hair_cycles_sampling): Cycles' own estimator, inconsistent as
// above and so biased, to reproduce its image: the sampled lobe's value is its sampler's density
// (value/pdf = 1 wherever it goes, bsdf_hair_*_sample), TT sampled over |phi - pi| <= pi/2 only,
// while eval and pdf (light samples, the other lobe's share, MIS) stay Cycles' eval.
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

namespace hair_detail {

// Cycles' clamp of both roughnesses.
inline float clamp_roughness(float r) { return clampf(std::isfinite(r) ? r : 0.0f, 1e-3f, 1.0f); }

// The fibre angles of wo and wi in the frame x = T: theta of each, and cos of the azimuth between
// their projections across the fibre. False where a projection vanishes (a direction along T).
struct FibreAngles {
    float theta_r, theta_i, cos_phi;
};
inline bool fibre_angles(const Vec3& wo, const Vec3& wi, FibreAngles* a) {
    float lo = wo.y * wo.y + wo.z * wo.z, li = wi.y * wi.y + wi.z * wi.z;
    if (!(lo > 0.0f) || !(li > 0.0f)) return false;
    a->theta_r = std::asin(clampf(wo.x, -1.0f, 1.0f));
    a->theta_i = std::asin(clampf(wi.x, -1.0f, 1.0f));
    a->cos_phi = clampf((wo.y * wi.y + wo.z * wi.z) / std::sqrt(lo * li), -1.0f, 1.0f);
    return true;
}

// The theta part shared by R and TT: the Cauchy bounds A - B and the density of theta_i over
// cos(theta_i) (the solid-angle factor); 0 within 0.001 of the fibre's axis, as Cycles.
struct ThetaLobe {
    float a, b;  // A and B
};
inline ThetaLobe theta_lobe(float theta_r, float r1, float offset) {
    return {std::atan(((kPi * 0.5f + theta_r) * 0.5f - offset) / r1),
            std::atan(((-kPi * 0.5f + theta_r) * 0.5f - offset) / r1)};
}
inline float theta_density(const ThetaLobe& l, float theta_r, float theta_i, float r1, float offset) {
    if (kPi * 0.5f - std::fabs(theta_i) < 1e-3f) return 0.0f;
    float t = (theta_i + theta_r) * 0.5f - offset;
    return r1 / (2.0f * (t * t + r1 * r1) * (l.a - l.b) * std::cos(theta_i));
}
// theta_i from a uniform number (the inverse of theta_density's CDF).
inline float sample_theta(const ThetaLobe& l, float theta_r, float r1, float offset, float u) {
    float t = r1 * std::tan(u * (l.a - l.b) + l.b);
    return 2.0f * (t + offset) - theta_r;
}

// The direction at (theta_i, phi) with phi measured from wo's projection across the fibre.
inline bool fibre_direction(const Vec3& wo, float theta_i, float phi, Vec3* wi) {
    float lo = std::sqrt(wo.y * wo.y + wo.z * wo.z);
    if (!(lo > 0.0f)) return false;
    Vec3 locy(0.0f, wo.y / lo, wo.z / lo);
    Vec3 locx = cross(locy, Vec3(1.0f, 0.0f, 0.0f));
    float ct = std::cos(theta_i), st = std::sin(theta_i);
    *wi = locy * (std::cos(phi) * ct) - locx * (std::sin(phi) * ct) + Vec3(st, 0.0f, 0.0f);
    return true;
}

}  // namespace hair_detail

struct HairReflectionLobe : LobeDefaults<HairReflectionLobe> {
    static constexpr LobeKind kKind = LobeKind::HairReflection;
    static constexpr const char* kName = "hair_reflection";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static constexpr uint8_t kCyclesSampler = 1;

    static bool is_delta(const Lobe&) { return false; }

    // The azimuth density of the R sampler at |phi|.
    static float phi_density(float phi, float r2) {
        float x = std::fabs(phi) / r2;
        return x < kPi ? std::cos(0.5f * x) * 0.25f / r2 : 0.0f;
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        using namespace hair_detail;
        FibreAngles a;
        if (!fibre_angles(wo, wi, &a)) return {};
        float r1 = clamp_roughness(lobe.alpha), r2 = clamp_roughness(lobe.alpha_y), offset = lobe.f0.x;
        ThetaLobe l = theta_lobe(a.theta_r, r1, offset);
        LobeTerms t;
        t.pdf = theta_density(l, a.theta_r, a.theta_i, r1, offset) * phi_density(std::acos(a.cos_phi), r2);
        t.geom = wi.z >= 0.0f && a.cos_phi >= 0.0f ? t.pdf : 0.0f;
        if (lobe.variant == kCyclesSampler) t.pdf = t.geom;  // Cycles' eval is its pdf
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        using namespace hair_detail;
        float r1 = clamp_roughness(lobe.alpha), r2 = clamp_roughness(lobe.alpha_y), offset = lobe.f0.x;
        float theta_r = std::asin(clampf(wo.x, -1.0f, 1.0f));
        float theta_i = sample_theta(theta_lobe(theta_r, r1, offset), theta_r, r1, offset, u.x);
        float phi = 2.0f * std::asin(clampf(1.0f - 2.0f * u.y, -1.0f, 1.0f)) * r2;
        Vec3 wi;
        if (!fibre_direction(wo, theta_i, phi, &wi)) return {};
        if (lobe.variant == kCyclesSampler) {
            float pdf = theta_density(theta_lobe(theta_r, r1, offset), theta_r, theta_i, r1, offset) *
                        phi_density(phi, r2);
            return cycles_sample(lobe, wi, pdf);
        }
        return lobe_sample_at<HairReflectionLobe>(lobe, wo, wi, wi.z < 0.0f, 1.0f);
    }

    // Cycles' sample of either hair closure: value = weight x its sampler's density.
    static BsdfSample cycles_sample(const Lobe& lobe, const Vec3& wi, float pdf) {
        BsdfSample s;
        if (!(pdf > 0.0f) || !std::isfinite(pdf)) return s;
        s.wi = wi;
        s.value = lobe.weight * pdf;
        s.pdf = pdf;
        s.transmission = wi.z < 0.0f;
        s.eta = 1.0f;
        return s;
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

struct HairTransmissionLobe : LobeDefaults<HairTransmissionLobe> {
    static constexpr LobeKind kKind = LobeKind::HairTransmission;
    static constexpr const char* kName = "hair_transmission";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    // The Cauchy of scale r2 about phi = pi, normalised over |p| <= half_width (p = phi - pi).
    static float cauchy(float p, float r2, float half_width) {
        return r2 / (2.0f * std::atan(half_width / r2) * (p * p + r2 * r2));
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        using namespace hair_detail;
        FibreAngles a;
        if (!fibre_angles(wo, wi, &a)) return {};
        float r1 = clamp_roughness(lobe.alpha), r2 = clamp_roughness(lobe.alpha_y), offset = lobe.f0.x;
        float theta = theta_density(theta_lobe(a.theta_r, r1, offset), a.theta_r, a.theta_i, r1, offset);
        float p = kPi - std::acos(a.cos_phi);
        LobeTerms t;
        t.pdf = theta * cauchy(p, r2, kPi);
        t.geom = wi.z < 0.0f ? theta * cauchy(p, r2, 0.5f * kPi) : 0.0f;  // Cycles' eval
        if (lobe.variant == HairReflectionLobe::kCyclesSampler) t.pdf = t.geom;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        using namespace hair_detail;
        float r1 = clamp_roughness(lobe.alpha), r2 = clamp_roughness(lobe.alpha_y), offset = lobe.f0.x;
        float theta_r = std::asin(clampf(wo.x, -1.0f, 1.0f));
        float theta_i = sample_theta(theta_lobe(theta_r, r1, offset), theta_r, r1, offset, u.x);
        const bool cycles = lobe.variant == HairReflectionLobe::kCyclesSampler;
        float half_width = cycles ? 0.5f * kPi : kPi;  // Cycles' c_TT covers |phi - pi| <= pi/2
        float p = r2 * std::tan(2.0f * std::atan(half_width / r2) * (u.y - 0.5f));
        Vec3 wi;
        if (!fibre_direction(wo, theta_i, kPi + p, &wi)) return {};
        if (cycles) {
            float pdf = theta_density(theta_lobe(theta_r, r1, offset), theta_r, theta_i, r1, offset) *
                        cauchy(p, r2, half_width);
            return HairReflectionLobe::cycles_sample(lobe, wi, pdf);
        }
        return lobe_sample_at<HairTransmissionLobe>(lobe, wo, wi, wi.z < 0.0f, 1.0f);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
