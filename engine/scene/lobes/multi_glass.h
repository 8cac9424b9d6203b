// Multiscatter GGX glass, its single scattering (Glass BSDF "Multiscatter GGX"; the Principled BSDF's
// transmission with Multiscatter GGX above Roughness 0.05): one closure for reflection and refraction,
// as Cycles 3.4's CLOSURE_BSDF_MICROFACET_MULTI_GGX_GLASS(_FRESNEL)_ID, whose light scattered once is
// its random walk's first bounce (scene/ggx_walk.h, glass_walk; bsdf_microfacet_multi_impl.h):
//
//  * the visible normal wm of wo, then reflection with the Fresnel term at wm, F(wo.wm) (not at the
//    shading normal, as Cycles' pair of GGX glass closures), else refraction;
//  * escape with the height-correlated masking-shadowing G2 = 1 / (1 + Lambda(wo) + Lambda(wi)) on
//    both sides: Cycles' sampled walk (mf_sample) goes on from the same height CDF after a refraction
//    (its eval, mf_eval, mirrors it and gets Beta(1 + Lambda_o, 1 + Lambda_i) for the refraction;
//    the two disagree, ours is the sampled walk, as for the glossy lobe, multiscatter_ggx.h);
//  * f cos_i = F D G2 / (4 cos_o) for the reflection, (1 - F) D G2 |wo.wm| |wi.wm| / (cos_o
//    (wo.wm + eta wi.wm)^2) for the refraction (Walter et al. 2007 with the radiance scaled by
//    (eta_i / eta_t)^2, as lobes/dielectric.h), sampled with pdf D_wo(wm) F / (4 wo.wm), resp.
//    D_wo(wm) (1 - F) eta^2 |wi.wm| / (wo.wm + eta wi.wm)^2, so eval / pdf = G2 / G1(wo) (over eta^2).
//
// Colours (kTinted, the Principled glass' own, principled_glass.h): f0 is the refraction's colour (the
// Principled base; white for the Glass BSDF, whose colour is the weight), kind_colour.x the Principled
// Specular Tint of the reflection's interpolated Fresnel colour. Its multiple scattering is the
// GlassMultiple lobe (glass_multiple.h). Two-sided: +z is the outside, eta = inside / outside.
#pragma once
#include "scene/lobes/dielectric.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/multiscatter_ggx.h"
#include "scene/lobes/principled_glass.h"

namespace smis {

struct MultiGlassLobe : LobeDefaults<MultiGlassLobe> {
    static constexpr LobeKind kKind = LobeKind::MultiGlass;
    static constexpr const char* kName = "multi_glass";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;
    static constexpr bool kBackfaceInvertsEta = true;

    static bool is_delta(const Lobe& lobe) { return DielectricLobe::is_delta(lobe); }

    static Color fresnel(const Lobe& lobe, float cos_d) { return PrincipledGlassLobe::fresnel(lobe, cos_d); }
    static bool colour_f0(const Lobe&) { return true; }
    static bool measured_metal(const Lobe&) { return false; }
    template <class F0At>
    static float spectral_colour(const Lobe& lobe, F0At&& f0_at, float cos_d) {
        return PrincipledGlassLobe::colour(f0_at(), lobe, cos_d);
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        DielectricLobe::Configuration c;  // the directions mirrored so that wo is above, and wm
        if (!DielectricLobe::configuration(lobe, wo, wi, &c)) return {};
        const float etap = c.etap, cos_om = c.cos_om, cos_im = c.cos_im;
        float alpha = lobe.alpha;
        float d = ggx_D(c.wm, alpha);
        float lo = ggx_lambda(c.o, alpha), li = ggx_lambda(c.i, alpha);
        float F = fresnel_dielectric(cos_om, etap);
        float visible = d * cos_om / (c.o.z * (1.0f + lo));  // D_wo(wm) = G1(o) D wo.wm / cos_o
        float g2_over_g1 = (1.0f + lo) / (1.0f + lo + li);
        LobeTerms t;
        t.cos_d = cos_im;
        if (c.reflect) {
            t.pdf = F * visible / (4.0f * cos_om);
            t.geom = t.pdf * g2_over_g1;
        } else {
            float dwm_dwi = etap * etap * std::fabs(cos_im) / c.len2;  // |o + eta i|^2 = (wo.wm + eta wi.wm)^2
            t.pdf = (1.0f - F) * visible * dwm_dwi;
            t.geom = t.pdf * g2_over_g1 / (etap * etap);
        }
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        if (is_delta(lobe)) {
            // Smooth (Cycles: alpha below ~3e-4): the Fresnel term at the normal picks the event.
            float cos_o = std::fabs(wo.z);
            return DielectricLobe::smooth_sample(lobe, wo, u_event, lobe.weight * fresnel(lobe, cos_o),
                                                 lobe.weight * fresnel(lobe, -cos_o));
        }
        if (!(wo.z != 0.0f)) return {};
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        Vec3 o = wo * side;
        Vec3 wm = ggx_sample_visible_normal(o, lobe.alpha, u);
        float cos_om = dot(o, wm);
        if (!(cos_om > 0.0f)) return {};
        bool transmission = !(u_event < fresnel_dielectric(cos_om, etap));  // F = 1 under total internal reflection
        Vec3 i;
        if (!transmission) {
            i = reflect(o, wm);
            if (!(i.z > 0.0f)) return {};
            i = normalize(i);
        } else if (!lobe_detail::refract_dir(o, wm, etap, &i) || !(i.z < 0.0f)) {
            return {};
        }
        return lobe_sample_at<MultiGlassLobe>(lobe, wo, i * side, transmission, transmission ? etap : 1.0f);
    }

    // As the other glass lobes: the transmitted colour.
    static Color albedo(const Lobe& lobe) { return lobe.weight * lobe.f0; }
};

}  // namespace smis
