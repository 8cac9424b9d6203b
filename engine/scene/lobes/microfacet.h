// GGX reflection (Glossy BSDF, metals, the Principled specular layer), Cycles 3.4's single-scattering
// closure: f cos_i = F D G1(wo) G1(wi) / (4 cos_o), with the separable Smith masking-shadowing
// G = G1(wo) G1(wi) as Cycles 3.4 uses. Sampled by the distribution of visible normals (Heitz 2018,
// "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), whose pdf
// D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / cos(wo) makes eval / pdf = F G1(wi): the estimator never
// sees D. The Fresnel factor is outside terms().geom (FresnelMode), so the spectral tracer evaluates
// it per wavelength (or a measured metal's in its place).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct MicrofacetLobe : LobeDefaults<MicrofacetLobe> {
    static constexpr LobeKind kKind = LobeKind::Microfacet;
    static constexpr const char* kName = "microfacet";
    static constexpr bool kEnabled = true;
    static constexpr const char* kFeature = nullptr;
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::Ggx;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;

    static bool is_delta(const Lobe& lobe) { return !(lobe.alpha >= kDeltaAlpha); }

    // Fresnel term for the angle cos_d between the light direction and the microfacet normal.
    static Color fresnel(const Lobe& lobe, float cos_d) {
        switch (lobe.fresnel) {
            case FresnelMode::None: return Color(1.0f);
            case FresnelMode::Schlick: return lobe.f0 + (Color(1.0f) - lobe.f0) * schlick_weight(cos_d);
            case FresnelMode::Dielectric: return Color(fresnel_dielectric(std::fabs(cos_d), lobe.eta));
        }
        return Color(1.0f);
    }

    // pdf = D_wo(wm) / (4 wo.wm) = G1(wo) D / (4 cos_o).
    static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 h = wo + wi;
        float len2 = length_sq(h);
        if (!(len2 > kMinHalfLenSq)) return {};
        Vec3 wm = h / std::sqrt(len2);
        float alpha = lobe.alpha;
        float d = ggx_D(wm, alpha);
        float g1o = ggx_G1(wo, alpha), g1i = ggx_G1(wi, alpha);
        // pdf of the visible-normal sample after the reflection Jacobian 1/(4 wo.wm): the wo.wm of
        // D_wo cancels the Jacobian's, so nothing here divides by a possibly tiny wo.wm.
        float common = d * g1o / (4.0f * wo.z);
        LobeTerms t;
        t.pdf = common;
        t.geom = common * g1i;
        t.cos_d = dot(wi, wm);
        return t;
    }

    static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight * fresnel(lobe, wo.z));
        return reflect_about<MicrofacetLobe>(lobe, wo, ggx_sample_visible_normal(wo, lobe.alpha, u));
    }

    // wo reflected about the sampled microfacet normal wm, valued by kind L's eval/pdf.
    template <class L>
    [[gnu::always_inline]] static BsdfSample reflect_about(const Lobe& lobe, const Vec3& wo, const Vec3& wm) {
        Vec3 wi = reflect(wo, wm);
        if (!(wi.z > 0.0f)) return {};  // reflected below the horizon: the single-scatter energy loss
        return lobe_sample_at<L>(lobe, wo, normalize(wi));
    }

    // Visible-normal sampling: the wo-only factor of the pdf D(wm) G1(wo) / (4 cos_o).
    static float fixed_wo_scale(const Lobe& lobe, const Vec3& wo) {
        return wo.z > 0.0f && !is_delta(lobe) ? ggx_G1(wo, lobe.alpha) / (4.0f * wo.z) : 0.0f;
    }
    static float fixed_wo_pdf(const Lobe& lobe, float scale, const Vec3& wo, const Vec3& wi) {
        if (!(scale > 0.0f) || !(wi.z > 0.0f)) return 0.0f;
        Vec3 h = wo + wi;
        float len2 = length_sq(h);
        return len2 > kMinHalfLenSq ? ggx_D(h / std::sqrt(len2), lobe.alpha) * scale : 0.0f;
    }

    // Reflectance at normal incidence: a metal's f0, the dielectric layer's F0, or the colour.
    static Color albedo(const Lobe& lobe) {
        switch (lobe.fresnel) {
            case FresnelMode::Schlick: return lobe.weight * lobe.f0;
            case FresnelMode::Dielectric: return lobe.weight * sqr((lobe.eta - 1.0f) / (lobe.eta + 1.0f));
            case FresnelMode::None: break;
        }
        return lobe.weight;
    }
};

}  // namespace smis
