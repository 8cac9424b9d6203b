// Principled clearcoat (Cycles 3.4's CLOSURE_BSDF_MICROFACET_GGX_CLEARCOAT_ID, Burley 2012 appendix
// B.2): f cos_i = F(wi.wm) D_GTR1(wm) G1(wo) G1(wi) / (4 cos_o), alpha = roughness^2, G1 GGX-Smith
// with alpha 0.25 whatever the coat roughness, exact dielectric Fresnel at `eta` (1.5) inside
// terms().geom. Sampled by D_GTR1(wm) cos(theta_m) (Burley's eq. 2/5), so pdf = D cos_m / (4 wo.wm)
// after the reflection Jacobian.
#pragma once
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"

namespace smis {

// The clearcoat's masking-shadowing roughness, fixed by Cycles 3.4 whatever the coat roughness.
constexpr float kClearcoatShadowAlpha = 0.25f;

struct ClearcoatLobe : LobeDefaults<ClearcoatLobe> {
    static constexpr LobeKind kKind = LobeKind::Clearcoat;
    static constexpr const char* kName = "clearcoat";
    static constexpr bool kEnabled = kWithPrincipledExtras;
    static constexpr const char* kFeature = "principled_extras";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    // The coat's Fresnel (fixed IOR) is the same at every wavelength.
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Fixed;

    static bool is_delta(const Lobe& lobe) { return !(lobe.alpha >= kDeltaAlpha); }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 h = wo + wi;
        float len2 = length_sq(h);
        if (!(len2 > kMinHalfLenSq)) return {};
        Vec3 wm = h / std::sqrt(len2);
        float cos_om = dot(wo, wm);
        if (!(cos_om > 0.0f)) return {};
        float d = gtr1_D(wm.z, lobe.alpha);
        float g = ggx_G1(wo, kClearcoatShadowAlpha) * ggx_G1(wi, kClearcoatShadowAlpha);
        LobeTerms t;
        t.pdf = d * wm.z / (4.0f * cos_om);
        t.geom = fresnel_dielectric(cos_om, lobe.eta) * d * g / (4.0f * wo.z);
        t.cos_d = cos_om;
        return t;
    }

    // Burley 2012 eq. 2: cos^2(theta_m) = (1 - alpha^(2 (1 - u))) / (1 - alpha^2) samples D_GTR1 cos(theta_m).
    static Vec3 sample_normal(float alpha, Point2 u) {
        float a2 = alpha * alpha;
        float cos2 = a2 >= 1.0f - 1e-4f ? 1.0f - u.x : (1.0f - std::exp((1.0f - u.x) * std::log(a2))) / (1.0f - a2);
        cos2 = clampf(cos2, 0.0f, 1.0f);
        float sin_t = std::sqrt(1.0f - cos2), phi = 2.0f * kPi * u.y;
        return Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), std::sqrt(cos2));
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        // As Cycles' specular case: the Fresnel-weighted mirror, no shadowing.
        if (is_delta(lobe)) return lobe_detail::mirror_sample(wo, lobe.weight * fresnel_dielectric(wo.z, lobe.eta));
        Vec3 wm = sample_normal(lobe.alpha, u);
        if (!(dot(wo, wm) > 0.0f)) return {};  // back-facing normal: the reflection would leave the hemisphere
        return MicrofacetLobe::reflect_about<ClearcoatLobe>(lobe, wo, wm);
    }

    // Reflectance at normal incidence: the coat's F0.
    static Color albedo(const Lobe& lobe) { return lobe.weight * sqr((lobe.eta - 1.0f) / (lobe.eta + 1.0f)); }
};

}  // namespace smis
