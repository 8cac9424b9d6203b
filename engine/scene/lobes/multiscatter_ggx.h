// Multiscatter GGX (Glossy BSDF "Multiscatter GGX"), as two lobes that together carry Cycles 3.4's
// closure:
//
//  * MultiGgxLobe, the single scattering Cycles' random walk evaluates analytically (the order-0 term of
//    bsdf_microfacet_multi_impl.h's mf_eval): f cos_i = D G2 / (4 cos_o) with the height-correlated
//    Smith masking-shadowing G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) (Heitz 2014, "Understanding the
//    Masking-Shadowing Function", eq. 99), not the separable G1 G1 of the single-scatter lobe
//    (microfacet.h). Sampled by visible normals (Heitz 2018), pdf D G1(wo) / (4 cos_o), so
//    eval / pdf = G2 / G1(wo) <= 1.
//
//  * GgxMultipleLobe, the light that scatters more than once among the microfacets. Cycles follows the
//    random walk of Heitz, Hanika, d'Eon and Dachsbacher 2016 ("Multiple-Scattering Microfacet BSDFs
//    with the Smith Model", SIGGRAPH) at every evaluation, with a stochastic eval and an approximate
//    pdf. We run the same walk (scene/ggx_walk.h) once, at build time, and tabulate where the walks of
//    two or more bounces leave (scene/ggx_multiple.h: 11 roughnesses x 12 incident cosines x 12 x 8
//    leaving cells, 400,000 walks per incident cosine): eval is that table, deterministic, so eval, pdf
//    and the chi-square test agree exactly, and path-space filtering and spectral rendering treat it
//    as any other lobe. Cosine sampled: pdf = cos_i / pi. Kulla and Conty's energy compensation (2017)
//    gives the same energy but spreads it as (1 - E(wo))(1 - E(wi)); at roughness 0.8, where multiple
//    scattering carries up to 45% of the light, that was 3.4% from Cycles on the closure scene.
//    Cycles' walk multiplies the throughput by the colour c again at every further bounce: with the
//    table's albedo ratio h at c = 0.5, a geometric number of further bounces (ratio q = (1 - 2h) /
//    (1 - h)) gives the colour factor c (1 - q) / (1 - c q), per channel (multiscatter_tint): exact
//    at c = 1 and c = 0.5.
//
// The compiler emits the pair for a Multiscatter GGX closure of weight c: MultiGgx with weight c and
// GgxMultiple with weight c x tint x M (M: the table's cosine-averaged albedo), so that lobe
// selection (by weight) picks the multiple scattering about as often as its energy; geom divides M
// out again.
#pragma once
#include "scene/ggx_multiple.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"

namespace smis {

// Smith's Lambda of GGX for a direction above the surface: G1 = 1 / (1 + Lambda).
inline float ggx_lambda(const Vec3& w, float alpha) {
    float cos2 = w.z * w.z;
    if (!(cos2 > 0.0f)) return 0.0f;
    float sin2 = std::max(0.0f, w.x * w.x + w.y * w.y);
    float a2 = sqr(lobe_detail::sanitize_alpha(alpha));
    float l = 0.5f * (std::sqrt(1.0f + a2 * sin2 / cos2) - 1.0f);
    return std::isfinite(l) ? l : 1e30f;
}

// Below this cosine-averaged albedo the multiple scattering is negligible (roughness < ~0.15): no lobe.
constexpr float kMinMultipleEnergy = 1e-4f;

// The colour of the multiple scattering relative to the white walk's, for colour c (see above).
inline Color multiscatter_tint(const Color& c, float half_ratio) {
    float h = clampf(half_ratio, 1e-3f, 0.5f);
    float q = (1.0f - 2.0f * h) / (1.0f - h);
    auto one = [&](float v) {
        v = clampf(v, 0.0f, 1.0f);
        return v * (1.0f - q) / (1.0f - v * q);
    };
    return Color(one(c.x), one(c.y), one(c.z));
}

struct MultiGgxLobe;
// The GgxMultiple lobe that goes with the MultiGgx lobe `single` of colour c (the closure's, without
// its mix weight): false where it would carry next to nothing (smooth, or nearly).
inline bool multiple_scattering_lobe(const Lobe& single, const Color& c, Lobe* multiple);

struct MultiGgxLobe : LobeDefaults<MultiGgxLobe> {
    static constexpr LobeKind kKind = LobeKind::MultiGgx;
    static constexpr const char* kName = "multi_ggx";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    // Its pdf is the GGX lobe's (visible normals), so path-space filtering's GGX model holds.
    static constexpr DensityModel kDensity = DensityModel::Ggx;
    // The GGX lobe's Fresnel modes: None for the Glossy BSDF, the Principled specular layer and metal
    // with Multiscatter GGX (FresnelMode::Dielectric, Schlick) as the single-scatter lobes.
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;

    static bool is_delta(const Lobe& lobe) { return !(lobe.alpha >= kDeltaAlpha); }
    static Color fresnel(const Lobe& lobe, float cos_d) { return MicrofacetLobe::fresnel(lobe, cos_d); }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        Vec3 wm;
        if (!lobe_detail::reflection_half_vector(wo, wi, &wm)) return {};
        float alpha = lobe.alpha;
        float d = ggx_D(wm, alpha);
        float lo = ggx_lambda(wo, alpha), li = ggx_lambda(wi, alpha);
        LobeTerms t;
        t.pdf = d / (4.0f * wo.z * (1.0f + lo));
        t.geom = d / (4.0f * wo.z * (1.0f + lo + li));
        t.cos_d = dot(wi, wm);
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight * fresnel(lobe, wo.z));
        return MicrofacetLobe::reflect_about<MultiGgxLobe>(lobe, wo, ggx_sample_visible_normal(wo, lobe.alpha, u));
    }

    // The same wo-only factor as the GGX lobe's (path-space filtering).
    static float fixed_wo_scale(const Lobe& lobe, const Vec3& wo) { return MicrofacetLobe::fixed_wo_scale(lobe, wo); }
    static float fixed_wo_pdf(const Lobe& lobe, float scale, const Vec3& wo, const Vec3& wi) {
        return MicrofacetLobe::fixed_wo_pdf(lobe, scale, wo, wi);
    }

    static Color albedo(const Lobe& lobe) { return MicrofacetLobe::albedo(lobe); }  // Glossy: the closure's colour
};

struct GgxMultipleLobe : LobeDefaults<GgxMultipleLobe> {
    static constexpr LobeKind kKind = LobeKind::GgxMultiple;
    static constexpr const char* kName = "ggx_multiple";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        float average = ggx_multiple_average(lobe.alpha);
        if (!(average >= kMinMultipleEnergy)) return {};
        LobeTerms t;
        t.pdf = wi.z * kInvPi;
        t.geom = ggx_multiple_brdf(wo, wi, lobe.alpha) * wi.z / average;  // the weight holds M (see above)
        return t;
    }

    static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<GgxMultipleLobe>(lobe, wo, u);
    }

    // Cycles' Albedo pass counts the closure colour once: on MultiGgx.
    static Color albedo(const Lobe&) { return Color(0.0f); }
};

inline bool multiple_scattering_lobe(const Lobe& single, const Color& c, Lobe* multiple) {
    if (MultiGgxLobe::is_delta(single)) return false;
    float average = ggx_multiple_average(single.alpha);
    if (!(average >= kMinMultipleEnergy)) return false;
    *multiple = single;
    multiple->kind = LobeKind::GgxMultiple;
    multiple->weight = single.weight * multiscatter_tint(c, ggx_multiple_half_ratio(single.alpha)) * average;
    multiple->index = uint8_t(single.index + 1);
    return true;
}

}  // namespace smis
