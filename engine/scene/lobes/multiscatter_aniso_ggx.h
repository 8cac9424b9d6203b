// Anisotropic Multiscatter GGX (Anisotropic / Glossy BSDF "Multiscatter GGX" with Anisotropy != 0,
// Principled BSDF with Multiscatter GGX and Anisotropic > 0), as two lobes that together carry Cycles
// 3.4's closure (bsdf_microfacet_multi.h with alpha_x != alpha_y: the random walk of Heitz et al. 2016 on
// the stretched microsurface), about the closure's own tangent (kOwnTangent, as anisotropic.h):
//
//  * MultiAnisoGgxLobe, the single scattering, the walk's order 0 evaluated analytically: f cos_i =
//    D G2 / (4 cos_o) with the anisotropic GGX D (anisotropic.h) and the height-correlated
//    G2 = 1 / (1 + Lambda(wo) + Lambda(wi)), Lambda at the stretched direction (Heitz 2014, eqs. 86
//    and 99). Sampled by the anisotropic visible normals (Heitz 2018), pdf D G1(wo) / (4 cos_o).
//
//  * AnisoGgxMultipleLobe, the light that scatters more than once: the same walk run at build time
//    and tabulated over both roughnesses and the view's azimuth from the tangent (scene/ggx_aniso.h;
//    scene/tools/ggx_aniso_gen.cpp says why one isotropic alpha cannot stand for the pair), cosine
//    sampled, deterministic: eval, pdf and the chi-square agree exactly. Cycles' colour at every
//    further bounce is multiscatter_tint with this table's half ratio, as for the isotropic pair
//    (multiscatter_ggx.h), whose weight convention it shares: weight c x tint x M, geom / M.
//
// At alpha_x = alpha_y the compiler emits the isotropic pair (its finer table), as Cycles walks the
// isotropic microsurface there.
#pragma once
#include "scene/ggx_aniso.h"
#include "scene/lobes/anisotropic.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"
#include "scene/lobes/multiscatter_ggx.h"

namespace smis {

// Smith's Lambda of the anisotropic GGX for a direction above the surface (lobe frame).
inline float ggx_aniso_lambda(const Vec3& w, float ax, float ay) {
    if (!(w.z > 0.0f)) return 0.0f;
    float l = 0.5f * (std::sqrt(1.0f + lobe_detail::aniso_alpha_tan2(w, ax, ay)) - 1.0f);
    return std::isfinite(l) ? l : 1e30f;
}

struct MultiAnisoGgxLobe : LobeDefaults<MultiAnisoGgxLobe> {
    static constexpr LobeKind kKind = LobeKind::MultiAnisoGgx;
    static constexpr const char* kName = "multi_aniso_ggx";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    // The GGX lobe's Fresnel modes (the Principled metal and specular layer), as AnisoGgx.
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;
    static constexpr bool kOwnTangent = true;

    static bool is_delta(const Lobe& lobe) { return lobe_detail::aniso_is_delta(lobe); }
    static Color fresnel(const Lobe& lobe, float cos_d) { return MicrofacetLobe::fresnel(lobe, cos_d); }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo_frame, const Vec3& wi_frame) {
        Vec3 wo = lobe_detail::to_lobe_tangent(lobe, wo_frame), wi = lobe_detail::to_lobe_tangent(lobe, wi_frame), wm;
        if (!lobe_detail::reflection_half_vector(wo, wi, &wm)) return {};
        float ax = lobe_detail::sanitize_alpha(lobe.alpha), ay = lobe_detail::sanitize_alpha(lobe.alpha_y);
        float d = AnisoGgxLobe::D(wm, ax, ay);
        float lo = ggx_aniso_lambda(wo, ax, ay), li = ggx_aniso_lambda(wi, ax, ay);
        LobeTerms t;
        t.pdf = d / (4.0f * wo.z * (1.0f + lo));
        t.geom = d / (4.0f * wo.z * (1.0f + lo + li));
        t.cos_d = dot(wi, wm);
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return AnisoGgxLobe::sample_visible_normal<MultiAnisoGgxLobe>(lobe, wo, u);
    }

    static Color albedo(const Lobe& lobe) { return MicrofacetLobe::albedo(lobe); }
};

struct AnisoGgxMultipleLobe : LobeDefaults<AnisoGgxMultipleLobe> {
    static constexpr LobeKind kKind = LobeKind::AnisoGgxMultiple;
    static constexpr const char* kName = "aniso_ggx_multiple";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kOwnTangent = true;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        float average = ggx_aniso_average(lobe.alpha, lobe.alpha_y);
        if (!(average >= kMinMultipleEnergy)) return {};
        LobeTerms t;
        t.pdf = wi.z * kInvPi;
        t.geom = ggx_aniso_brdf(lobe_detail::to_lobe_tangent(lobe, wo), lobe_detail::to_lobe_tangent(lobe, wi),
                                lobe.alpha, lobe.alpha_y) *
                 wi.z / average;  // the weight holds M (multiscatter_ggx.h)
        return t;
    }

    static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<AnisoGgxMultipleLobe>(lobe, wo, u);
    }

    // Cycles' Albedo pass counts the closure colour once: on MultiAnisoGgx.
    static Color albedo(const Lobe&) { return Color(0.0f); }
};

// The AnisoGgxMultiple lobe that goes with the MultiAnisoGgx lobe `single` of colour c (the closure's,
// without its mix weight): false where it would carry next to nothing.
inline bool aniso_multiple_scattering_lobe(const Lobe& single, const Color& c, Lobe* multiple) {
    if (MultiAnisoGgxLobe::is_delta(single)) return false;
    float average = ggx_aniso_average(single.alpha, single.alpha_y);
    if (!(average >= kMinMultipleEnergy)) return false;
    *multiple = single;
    multiple->kind = LobeKind::AnisoGgxMultiple;
    multiple->weight =
        single.weight * multiscatter_tint(c, ggx_aniso_half_ratio(single.alpha, single.alpha_y)) * average;
    multiple->index = uint8_t(single.index + 1);
    return true;
}

}  // namespace smis
