// Beckmann reflection (Cycles 3.4's Glossy BSDF with the Beckmann distribution,
// bsdf_microfacet.h): f cos_i = D G1(wo) G1(wi) / (4 cos_o) with
//   D(m) = exp(-tan^2(theta_m) / alpha^2) / (pi alpha^2 cos^4(theta_m)),  alpha = roughness^2,
// and Smith G1 in Walter et al. 2007's rational approximation (eq. 27), which Cycles uses:
//   a = 1 / (alpha tan theta);  G1 = 1 for a >= 1.6, else (3.535 a + 2.181 a^2) / (1 + 2.276 a + 2.577 a^2).
// Sampled by D(m) cos(theta_m) (Walter eq. 28: tan^2 theta_m = -alpha^2 log(1 - u)), so
// pdf = D cos_m / (4 |wo.m|) after the reflection Jacobian; Cycles samples the visible normals
// instead (same image, less noise at grazing angles). No Fresnel: the colour is the weight.
#pragma once
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"

namespace smis {

struct BeckmannLobe : LobeDefaults<BeckmannLobe> {
    static constexpr LobeKind kKind = LobeKind::Beckmann;
    static constexpr const char* kName = "beckmann";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe& lobe) { return !(lobe.alpha >= kDeltaAlpha); }

    static float D(float cos_m, float alpha) {
        if (!(cos_m > 0.0f)) return 0.0f;
        float a2 = alpha * alpha, c2 = cos_m * cos_m;
        float tan2 = (1.0f - c2) / c2;
        float d = std::exp(-tan2 / a2) / (kPi * a2 * c2 * c2);
        return std::isfinite(d) ? d : 0.0f;
    }
    static float G1(float cos_n, float alpha) {
        float c2 = cos_n * cos_n;
        if (!(c2 > 0.0f)) return 0.0f;
        float alpha_tan = alpha * safe_sqrt((1.0f - c2) / c2);
        if (alpha_tan < 0.625f) return 1.0f;  // a = 1 / (alpha tan) > 1.6
        float a = 1.0f / alpha_tan;
        return ((2.181f * a + 3.535f) * a) / ((2.577f * a + 2.276f) * a + 1.0f);
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 h = wo + wi;
        float len2 = length_sq(h);
        if (!(len2 > kMinHalfLenSq)) return {};
        Vec3 wm = h / std::sqrt(len2);
        float cos_om = dot(wo, wm);
        if (!(cos_om > 0.0f)) return {};
        float d = D(wm.z, lobe.alpha);
        LobeTerms t;
        t.pdf = d * wm.z / (4.0f * cos_om);
        t.geom = d * G1(wo.z, lobe.alpha) * G1(wi.z, lobe.alpha) / (4.0f * wo.z);
        t.cos_d = cos_om;
        return t;
    }

    static Vec3 sample_normal(float alpha, Point2 u) {
        float tan2 = -alpha * alpha * std::log(std::max(1.0f - u.x, 1e-30f));
        float cos_t = 1.0f / std::sqrt(1.0f + tan2);
        float sin_t = safe_sqrt(1.0f - cos_t * cos_t), phi = 2.0f * kPi * u.y;
        return Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight);
        Vec3 wm = sample_normal(lobe.alpha, u);
        if (!(dot(wo, wm) > 0.0f)) return {};
        return MicrofacetLobe::reflect_about<BeckmannLobe>(lobe, wo, wm);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
