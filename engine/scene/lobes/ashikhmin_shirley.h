// Ashikhmin-Shirley reflection (Glossy BSDF and Anisotropic BSDF with that distribution), Cycles 3.4's
// closure (bsdf_ashikhmin_shirley.h): Ashikhmin & Shirley 2000, "An Anisotropic Phong BRDF Model",
// without its Fresnel factor (the colour is the weight) and with the paper's own "pump":
//
//   f cos_i = cos_i sqrt((n_x + 1)(n_y + 1)) / (8 pi) cos(theta_h)^e(h) / ((wo.h) max(cos_i, cos_o)),
//   e(h)    = (n_x h_x^2 + n_y h_y^2) / (h_x^2 + h_y^2),
//
// with the Phong exponents n = 2 / alpha^2 - 2 of Cycles' alpha_x (along the lobe's own tangent:
// anisotropic.h) and alpha_y, each clamped to [1e-4, 1] as Cycles' setup does; the Glossy BSDF has
// alpha_x = alpha_y = roughness^2, where e is n everywhere. The half vector is sampled by the paper's
// eq. 9 density p_h = sqrt((n_x + 1)(n_y + 1)) / (2 pi) cos(theta_h)^e(h) (phi in the first quadrant
// atan(sqrt((n_x + 1) / (n_y + 1)) tan(pi u / 2)), mirrored into the other three; cos theta_h =
// v^(1 / (n_x cos^2 phi + n_y sin^2 phi + 1))), and pdf = p_h / (4 wo.h); eval / pdf =
// cos_i / max(cos_i, cos_o) <= 1. Half vectors facing away from wo (wo.h < 0) are lost, as the
// reflections they give go below the surface. Cycles treats max(alpha_x, alpha_y) <= 1e-4 as a mirror.
#pragma once
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"

namespace smis {

struct AshikhminShirleyLobe : LobeDefaults<AshikhminShirleyLobe> {
    static constexpr LobeKind kKind = LobeKind::AshikhminShirley;
    static constexpr const char* kName = "ashikhmin_shirley";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kOwnTangent = true;

    static constexpr float kMinAlpha = 1e-4f;  // Cycles' clamp, and its mirror threshold

    static bool is_delta(const Lobe& lobe) { return !(std::fmax(lobe.alpha, lobe.alpha_y) > kMinAlpha); }

    // Cycles' roughness-to-exponent mapping, n = 2 / alpha^2 - 2 (0 at alpha = 1: uniform half vectors).
    static float exponent(float alpha) {
        float a = clampf(alpha, kMinAlpha, 1.0f);
        return 2.0f / (a * a) - 2.0f;
    }

    // The half-vector density p_h(h) (eq. 9) for exponents nx, ny; e(h) from h's own x, y (no
    // 1 - cos^2 cancellation near the normal).
    static float half_density(const Vec3& h, float nx, float ny) {
        if (!(h.z > 0.0f)) return 0.0f;
        float sx = h.x * h.x, sy = h.y * h.y, s = sx + sy;
        float e = s > 0.0f ? (nx * sx + ny * sy) / s : 0.0f;
        float lobe = s > 0.0f ? std::pow(std::fmax(h.z, 1e-6f), e) : 1.0f;
        return std::sqrt((nx + 1.0f) * (ny + 1.0f)) * (0.5f * kInvPi) * lobe;
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        Vec3 h;
        if (!lobe_detail::reflection_half_vector(wo, wi, &h)) return {};
        float cos_oh = std::fmax(std::fabs(dot(wo, h)), 1e-6f);
        float cos_o = std::fmax(wo.z, 1e-6f), cos_i = std::fmax(wi.z, 1e-6f);
        LobeTerms t;
        Vec3 h_lobe = lobe_detail::to_lobe_tangent(lobe, h);
        t.pdf = half_density(h_lobe, exponent(lobe.alpha), exponent(lobe.alpha_y)) / (4.0f * cos_oh);
        t.geom = t.pdf * cos_i / std::fmax(cos_i, cos_o);  // the pump 1 / (wo.h max(cos_i, cos_o))
        t.cos_d = cos_oh;
        return t;
    }

    // The paper's half-vector sample: u.x picks the quadrant and phi in it, u.y cos theta_h.
    static Vec3 sample_half(float nx, float ny, Point2 u) {
        float q = std::fmin(u.x * 4.0f, 3.9999998f);
        int quadrant = int(q);
        float uq = q - float(quadrant);
        if (quadrant & 1) uq = 1.0f - uq;  // mirrored quadrants: keeps the map continuous
        float phi = std::atan(std::sqrt((nx + 1.0f) / (ny + 1.0f)) * std::tan(0.5f * kPi * uq));
        if (quadrant == 1) phi = kPi - phi;
        else if (quadrant == 2) phi = kPi + phi;
        else if (quadrant == 3) phi = 2.0f * kPi - phi;
        float cos_p = std::cos(phi), sin_p = std::sin(phi);
        float cos_t = std::pow(u.y, 1.0f / (nx * cos_p * cos_p + ny * sin_p * sin_p + 1.0f));
        float sin_t = safe_sqrt(1.0f - cos_t * cos_t);
        return Vec3(sin_t * cos_p, sin_t * sin_p, cos_t);
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight);
        Vec3 h = lobe_detail::from_lobe_tangent(lobe, sample_half(exponent(lobe.alpha), exponent(lobe.alpha_y), u));
        if (!(dot(wo, h) > 0.0f)) return {};
        return MicrofacetLobe::reflect_about<AshikhminShirleyLobe>(lobe, wo, h);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
