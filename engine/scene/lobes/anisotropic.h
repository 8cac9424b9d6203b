// Anisotropic GGX and Beckmann reflection (the Anisotropic BSDF; the Principled BSDF's Anisotropic),
// Cycles 3.4's single-scattering closures with alpha_x along the tangent and alpha_y across it
// (bsdf_microfacet.h): each lobe has its own tangent within the Bsdf's shading frame (kOwnTangent,
// lobe_detail::to_lobe_tangent: the first anisotropic closure's tangent is the frame's s axis, Scene::
// program_bsdf), and in the lobe's frame x is along its tangent, y = n x tangent, as Cycles'
// make_orthonormals_tangent. Lobe::alpha is alpha_x, Lobe::alpha_y alpha_y.
//
//  * GGX: D(m) = 1 / (pi ax ay (m_x^2 / ax^2 + m_y^2 / ay^2 + m_z^2)^2) and the separable Smith
//    G1(w) = 2 / (1 + sqrt(1 + (ax^2 w_x^2 + ay^2 w_y^2) / w_z^2)) (Heitz 2014, "Understanding the
//    Masking-Shadowing Function", eqs. 85-86), sampled by the visible normals of the stretched
//    configuration (Heitz 2018), so eval / pdf = F G1(wi), as the isotropic lobe (microfacet.h), whose
//    Fresnel modes it shares (the Principled metal and specular layer).
//  * Beckmann: D(m) = exp(-(m_x^2 / ax^2 + m_y^2 / ay^2) / m_z^2) / (pi ax ay m_z^4) and Walter et al.'s
//    rational G1 at the direction's own alpha, sqrt(ax^2 cos^2 phi + ay^2 sin^2 phi) (Cycles'
//    bsdf_beckmann_aniso_G1); sampled by D cos (the isotropic Beckmann slopes stretched by ax, ay).
//    Variant kCyclesSampler (the setting beckmann_cycles_sampling): Cycles' own estimator, biased. Cycles
//    3.4's bsdf_microfacet_beckmann_sample draws the visible normal with microfacet_sample_stretched(...,
//    alpha_x, alpha_x, ...), the isotropic Beckmann of roughness ax, and returns as its pdf the
//    anisotropic D (G1 of the view, exact Smith at ax, from that sampler) D(m) / (4 cos_o), as its value
//    that times the rational G1 of the light direction: so a sample's weight is G1(wi) where the normal's
//    density is not D's (biased wherever ax != ay). Its eval (light samples) is the lobe's own BRDF with
//    the anisotropic visible-normal pdf G1(wo) D / (4 cos_o) for MIS, which pdf() returns under the variant.
#pragma once
#include "scene/lobes/beckmann.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"

namespace smis {

namespace lobe_detail {

// Cycles treats a closure with alpha_x alpha_y <= 1e-7 as a mirror.
inline bool aniso_is_delta(const Lobe& lobe) { return !(lobe.alpha * lobe.alpha_y > 1e-7f); }

// (alpha(phi) tan theta)^2 of a direction: ax^2 w_x^2 + ay^2 w_y^2 over w_z^2.
inline float aniso_alpha_tan2(const Vec3& w, float ax, float ay) {
    return (sqr(ax * w.x) + sqr(ay * w.y)) / (w.z * w.z);
}

}  // namespace lobe_detail

struct AnisoGgxLobe : LobeDefaults<AnisoGgxLobe> {
    static constexpr LobeKind kKind = LobeKind::AnisoGgx;
    static constexpr const char* kName = "aniso_ggx";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;
    static constexpr bool kOwnTangent = true;

    static bool is_delta(const Lobe& lobe) { return lobe_detail::aniso_is_delta(lobe); }
    static Color fresnel(const Lobe& lobe, float cos_d) { return MicrofacetLobe::fresnel(lobe, cos_d); }

    static float D(const Vec3& m, float ax, float ay) {
        if (!(m.z > 0.0f)) return 0.0f;
        float t = sqr(m.x / ax) + sqr(m.y / ay) + m.z * m.z;
        float d = 1.0f / (kPi * ax * ay * t * t);
        return std::isfinite(d) ? d : 0.0f;
    }
    static float G1(const Vec3& w, float ax, float ay) {
        if (!(w.z != 0.0f)) return 0.0f;
        float g = 2.0f / (1.0f + std::sqrt(1.0f + lobe_detail::aniso_alpha_tan2(w, ax, ay)));
        return std::isfinite(g) ? g : 0.0f;
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo_frame, const Vec3& wi_frame) {
        Vec3 wo = lobe_detail::to_lobe_tangent(lobe, wo_frame), wi = lobe_detail::to_lobe_tangent(lobe, wi_frame), wm;
        if (!lobe_detail::reflection_half_vector(wo, wi, &wm)) return {};
        float ax = lobe_detail::sanitize_alpha(lobe.alpha), ay = lobe_detail::sanitize_alpha(lobe.alpha_y);
        float common = D(wm, ax, ay) * G1(wo, ax, ay) / (4.0f * wo.z);
        LobeTerms t;
        t.pdf = common;
        t.geom = common * G1(wi, ax, ay);
        t.cos_d = dot(wi, wm);
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return sample_visible_normal<AnisoGgxLobe>(lobe, wo, u);
    }
    // A visible normal of the anisotropic GGX about the lobe's own tangent, reflected and valued by
    // Kind's terms (Kind: this lobe, or the multiscatter lobe's single scattering, whose terms differ).
    template <class Kind>
    static BsdfSample sample_visible_normal(const Lobe& lobe, const Vec3& wo, Point2 u) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight * fresnel(lobe, wo.z));
        Vec3 wm = ggx_sample_visible_normal(lobe_detail::to_lobe_tangent(lobe, wo), lobe.alpha, lobe.alpha_y, u);
        return MicrofacetLobe::reflect_about<Kind>(lobe, wo, lobe_detail::from_lobe_tangent(lobe, wm));
    }

    static Color albedo(const Lobe& lobe) { return MicrofacetLobe::albedo(lobe); }
};

struct AnisoBeckmannLobe : LobeDefaults<AnisoBeckmannLobe> {
    static constexpr LobeKind kKind = LobeKind::AnisoBeckmann;
    static constexpr const char* kName = "aniso_beckmann";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kOwnTangent = true;

    static constexpr uint8_t kCyclesSampler = 1;

    static bool is_delta(const Lobe& lobe) { return lobe_detail::aniso_is_delta(lobe); }

    static float D(const Vec3& m, float ax, float ay) {
        if (!(m.z > 0.0f)) return 0.0f;
        float c2 = m.z * m.z;
        float d = std::exp(-(sqr(m.x / ax) + sqr(m.y / ay)) / c2) / (kPi * ax * ay * c2 * c2);
        return std::isfinite(d) ? d : 0.0f;
    }
    // Walter's rational G1 (beckmann.h) at alpha(phi) tan theta.
    static float G1(const Vec3& w, float ax, float ay) {
        if (!(w.z != 0.0f)) return 0.0f;
        float alpha_tan = std::sqrt(lobe_detail::aniso_alpha_tan2(w, ax, ay));
        if (alpha_tan < 0.625f) return 1.0f;
        float a = 1.0f / alpha_tan;
        return ((2.181f * a + 3.535f) * a) / ((2.577f * a + 2.276f) * a + 1.0f);
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo_frame, const Vec3& wi_frame) {
        Vec3 wo = lobe_detail::to_lobe_tangent(lobe, wo_frame), wi = lobe_detail::to_lobe_tangent(lobe, wi_frame), wm;
        if (!lobe_detail::reflection_half_vector(wo, wi, &wm)) return {};
        float cos_om = dot(wo, wm);
        if (!(cos_om > 0.0f)) return {};
        float ax = lobe_detail::sanitize_alpha(lobe.alpha), ay = lobe_detail::sanitize_alpha(lobe.alpha_y);
        float d = D(wm, ax, ay);
        const float g1o = G1(wo, ax, ay);
        LobeTerms t;
        t.pdf = lobe.variant == kCyclesSampler ? d * g1o / (4.0f * wo.z) : d * wm.z / (4.0f * cos_om);
        t.geom = d * g1o * G1(wi, ax, ay) / (4.0f * wo.z);
        t.cos_d = cos_om;
        return t;
    }

    // The isotropic unit-alpha Beckmann slopes, stretched: the normal's density is D(m) cos theta_m.
    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight);
        if (lobe.variant == kCyclesSampler) return cycles_sample(lobe, wo, u);
        float r = std::sqrt(-std::log(std::max(1.0f - u.x, 1e-30f))), phi = 2.0f * kPi * u.y;
        Vec3 wm = lobe_detail::from_lobe_tangent(
            lobe, normalize(Vec3(lobe.alpha * r * std::cos(phi), lobe.alpha_y * r * std::sin(phi), 1.0f)));
        if (!(dot(wo, wm) > 0.0f)) return {};
        return MicrofacetLobe::reflect_about<AnisoBeckmannLobe>(lobe, wo, wm);
    }

    // Cycles' sample (kCyclesSampler): a visible normal of the isotropic Beckmann of roughness ax, valued
    // and weighed as if it were the anisotropic one's (see the top).
    static BsdfSample cycles_sample(const Lobe& lobe, const Vec3& wo_frame, Point2 u) {
        const Vec3 wo = lobe_detail::to_lobe_tangent(lobe, wo_frame);
        const float ax = lobe_detail::sanitize_alpha(lobe.alpha), ay = lobe_detail::sanitize_alpha(lobe.alpha_y);
        const Vec3 wm = beckmann_sample_visible_normal(wo, ax, u);
        const float cos_om = dot(wo, wm);
        if (!(cos_om > 0.0f)) return {};
        const Vec3 wi = normalize(reflect(wo, wm));
        if (!(wi.z > 0.0f)) return {};
        BsdfSample s;
        s.pdf = beckmann_smith_G1(wo, ax) * D(wm, ax, ay) / (4.0f * wo.z);
        s.value = lobe.weight * (s.pdf * G1(wi, ax, ay));
        if (!(s.pdf > 0.0f) || !std::isfinite(s.pdf) || !is_finite(s.value)) return {};
        s.wi = lobe_detail::from_lobe_tangent(lobe, wi);
        return s;
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
