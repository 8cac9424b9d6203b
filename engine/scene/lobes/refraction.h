// Refraction BSDF (Cycles 3.4's CLOSURE_BSDF_REFRACTION_ID / MICROFACET_GGX_REFRACTION_ID): the
// transmitted half of glass without its Fresnel factor. Sharp: every ray not totally reflected goes
// through with the full weight; GGX-rough: Walter et al. 2007's transmission term with the
// visible-normal sampling of lobes/dielectric.h, f cos_i = D G |i.m| |o.m| / (|h|^2 cos_o) (radiance
// scaled by (eta_i/eta_t)^2 like the glass lobe; on a closed object the two crossings cancel, as
// in Cycles, whose kernel leaves the scaling out). A microfacet that totally reflects the ray
// contributes nothing (Cycles drops those samples too). eta = inside / outside, alpha = roughness^2.
// Variant kBeckmannDistribution: Beckmann's D and G1 sampled by D cos_m, as the Beckmann glass.
#pragma once
#include "scene/lobes/dielectric.h"
#include "scene/lobes/lobe.h"

namespace smis {

struct RefractionLobe : LobeDefaults<RefractionLobe> {
    static constexpr LobeKind kKind = LobeKind::Refraction;
    static constexpr const char* kName = "refraction";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kDispersive = true;
    static constexpr bool kBackfaceInvertsEta = true;

    static bool is_delta(const Lobe& lobe) { return DielectricLobe::is_delta(lobe); }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z * wi.z < 0.0f)) return {};  // transmission only (also rejects NaN and the plane)
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        Vec3 o = wo * side, i = wi * side;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        Vec3 h = o + i * etap;
        float len2 = length_sq(h);
        if (!(len2 > kMinHalfLenSq)) return {};
        Vec3 wm = h / std::sqrt(len2);
        if (wm.z < 0.0f) wm = -wm;
        float cos_om = dot(o, wm), cos_im = dot(i, wm);
        if (!(cos_om > 0.0f) || !(cos_im < 0.0f)) return {};
        if (lobe.variant == kBeckmannDistribution) {
            LobeTerms r;
            return DielectricLobe::beckmann_terms(o, i, wm, lobe.alpha, etap, len2, 0.0f, 0.0f, false, r);
        }
        float d = ggx_D(wm, lobe.alpha);
        float g1o = ggx_G1(o, lobe.alpha), g1i = ggx_G1(i, lobe.alpha);
        float dwm_dwi = std::fabs(cos_im) / (len2 / (etap * etap));  // see DielectricLobe::terms
        float visible = g1o * d * cos_om / o.z;
        LobeTerms r;
        r.pdf = visible * dwm_dwi;
        r.geom = visible * dwm_dwi * g1i / (etap * etap);
        return r;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z != 0.0f)) return {};
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        Vec3 o = wo * side, i;
        if (is_delta(lobe)) {
            if (!lobe_detail::refract_dir(o, Vec3(0, 0, 1), etap, &i)) return {};  // total internal reflection
            BsdfSample s;
            s.wi = i * side;
            s.value = lobe.weight / (etap * etap);
            s.pdf = 1.0f;
            s.delta = true;
            s.transmission = true;
            s.eta = etap;
            return s;
        }
        Vec3 wm = lobe.variant == kBeckmannDistribution ? BeckmannLobe::sample_normal(lobe.alpha, u)
                                                        : ggx_sample_visible_normal(o, lobe.alpha, u);
        if (!(dot(o, wm) > 0.0f)) return {};
        if (!lobe_detail::refract_dir(o, wm, etap, &i) || !(i.z < 0.0f)) return {};
        return lobe_sample_at<RefractionLobe>(lobe, wo, i * side, true, etap);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
