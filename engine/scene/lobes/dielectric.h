// Glass (Glass BSDF, Principled transmission): Fresnel-weighted reflection and refraction, smooth
// (Dirac) or GGX-rough with Walter et al. 2007's microfacet reflection and refraction, "Microfacet
// Models for Refraction through Rough Surfaces" (EGSR), weighted as Cycles 3.4 weights its pair of
// closures: by the Fresnel term at the shading normal, which also chooses the sampled event, so it
// cancels in value / pdf. Two-sided: +z is the outside, eta = inside / outside.
// Refraction scales radiance by (eta_i / eta_t)^2, so value / pdf of a refracted sample is the
// radiance throughput, not the energy fraction.
// With variant kBeckmannDistribution (Cycles' Glass BSDF with the Beckmann distribution), the rough
// events use Beckmann's D and rational Smith G1 (lobes/beckmann.h) and sample D(m) cos(theta_m)
// (Walter eq. 28): the pdf of the normal is D cos_m, not the visible-normal density.
#pragma once
#include "scene/lobes/beckmann.h"
#include "scene/lobes/lobe.h"

namespace smis {

// Lobe::variant of the Dielectric and Refraction kinds: the microfacet distribution of rough events.
constexpr uint8_t kGgxDistribution = 0, kBeckmannDistribution = 1;

struct DielectricLobe : LobeDefaults<DielectricLobe> {
    static constexpr LobeKind kKind = LobeKind::Dielectric;
    static constexpr const char* kName = "dielectric";
    static constexpr bool kEnabled = true;
    static constexpr const char* kFeature = nullptr;
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    // Its Fresnel is the Dirac event's probability; only Dirac refraction disperses: a rough lobe's
    // sampling density would depend on the wavelength, which the path's MIS over wavelengths does
    // not model, so it keeps its IOR.
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kDispersive = true;
    // Glass only: the Principled specular layer keeps its IOR on the back face (Cycles 3.4).
    static constexpr bool kBackfaceInvertsEta = true;

    // The probability of sampling the reflection event given F, the Fresnel term at the shading
    // normal: F for Cycles' pair of closures, 1 or 0 when a caustics toggle left one of them out
    // (its weight stays F or 1 - F: only the choice of event changes).
    static float reflection_probability(const Lobe& lobe, float F) {
        return lobe.glass_events == kGlassBoth ? F : lobe.glass_events == kGlassReflection ? 1.0f : 0.0f;
    }

    static bool is_delta(const Lobe& lobe) {
        return !(lobe.alpha >= kDeltaAlpha) || !(std::fabs(lobe.eta - 1.0f) >= kIndexMatchedEps);
    }

    // Out of line, as the extra kinds': the Bsdf loops inline the common Lambert and GGX cases only.
    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return rough_terms(lobe, wo, wi, lobe.alpha, lobe.alpha, lobe.variant == kBeckmannDistribution);
    }

    // The rough terms with the reflection at alpha_r and the refraction at alpha_t (the Principled
    // transmission's differ, principled_glass.h); cos_d = wi.wm, negative for a refraction.
    // A pair of directions of a rough glass lobe, mirrored so that wo is in the upper hemisphere (+z
    // stays "wo's side"), with the microfacet normal that joins them.
    struct Configuration {
        Vec3 o, i, wm;
        float etap, len2, cos_om, cos_im;  // etap = eta_t / eta_i seen from wo; len2 = |h|^2 of the unnormalised wm
        bool reflect;
    };
    // False where no microfacet joins wo and wi.
    static bool configuration(const Lobe& lobe, const Vec3& wo, const Vec3& wi, Configuration* c) {
        if (!(wo.z != 0.0f) || !(wi.z != 0.0f)) return false;  // also rejects NaN
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        c->o = wo * side;
        c->i = wi * side;
        // eta_t / eta_i seen from wo's medium: +z is the outside, eta = inside / outside.
        c->etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(c->etap > 0.0f) || !std::isfinite(c->etap)) return false;
        c->reflect = c->i.z > 0.0f;
        // (Generalised) half vector: Walter eq. 13 / 16, h_t ~ -(eta_i o + eta_t i).
        Vec3 h = c->reflect ? c->o + c->i : c->o + c->i * c->etap;
        c->len2 = length_sq(h);
        if (!(c->len2 > kMinHalfLenSq)) return false;
        c->wm = h / std::sqrt(c->len2);
        if (c->wm.z < 0.0f) c->wm = -c->wm;
        c->cos_om = dot(c->o, c->wm);
        c->cos_im = dot(c->i, c->wm);
        // Microfacets must be seen from the front by o, and i must lie on the same side of the
        // microfacet as of the macro-surface (the chi+ factors of Walter's G1).
        if (!(c->cos_om > 0.0f)) return false;
        return c->reflect ? c->cos_im > 0.0f : c->cos_im < 0.0f;
    }

    static LobeTerms rough_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi, float alpha_r, float alpha_t,
                                 bool beckmann = false) {
        Configuration c;
        if (!configuration(lobe, wo, wi, &c)) return {};
        const Vec3 &o = c.o, &i = c.i, &wm = c.wm;
        const float etap = c.etap, len2 = c.len2, cos_om = c.cos_om, cos_im = c.cos_im;
        const bool reflect = c.reflect;

        float alpha = reflect ? alpha_r : alpha_t;
        float F = fresnel_dielectric(o.z, etap);  // at the shading normal: see sample()
        if (!(lobe.glass_events & (reflect ? kGlassReflection : kGlassRefraction))) return {};
        const float p_reflect = reflection_probability(lobe, F);
        LobeTerms r;
        r.cos_d = cos_im;
        if (beckmann) return beckmann_terms(o, i, wm, alpha, etap, len2, F, p_reflect, reflect, r);
        float d = ggx_D(wm, alpha);
        float g1o = ggx_G1(o, alpha), g1i = ggx_G1(i, alpha);
        if (reflect) {
            float common = d * g1o / (4.0f * o.z);
            r.pdf = p_reflect * common;
            r.geom = F * common * g1i;
        } else {
            // Jacobian of the refraction mapping (Walter eq. 17, divided through by eta_t^2):
            // |dwm/dwi| = |i.wm| / (i.wm + o.wm / etap)^2, and (i.wm + o.wm/etap)^2 = |h|^2 / etap^2
            // exactly, which is bounded away from 0 once index-matched interfaces are excluded.
            float denom = len2 / (etap * etap);
            float dwm_dwi = std::fabs(cos_im) / denom;
            // D_wo(wm) = G1(o) D cos_om / cos_o (Heitz 2018 eq. 3).
            float visible = g1o * d * cos_om / o.z;
            r.pdf = (1.0f - p_reflect) * visible * dwm_dwi;
            // f cos_i = (1-F) D G |i.wm| |o.wm| / (denom cos_o); radiance is scaled by (eta_i/eta_t)^2.
            r.geom = (1.0f - F) * visible * dwm_dwi * g1i / (etap * etap);
        }
        return r;
    }

    // rough_terms' Beckmann events: as the GGX ones, with the normal's pdf D cos_m in place of the
    // visible-normal density G1(o) D cos_om / cos_o.
    static LobeTerms beckmann_terms(const Vec3& o, const Vec3& i, const Vec3& wm, float alpha, float etap, float len2,
                                    float F, float p_reflect, bool reflect, LobeTerms r) {
        float d = BeckmannLobe::D(wm.z, alpha);
        float g = BeckmannLobe::G1(o.z, alpha) * BeckmannLobe::G1(i.z, alpha);
        if (reflect) {
            r.pdf = p_reflect * d * wm.z / (4.0f * dot(o, wm));
            r.geom = F * d * g / (4.0f * o.z);
        } else {
            float dwm_dwi = std::fabs(dot(i, wm)) / (len2 / (etap * etap));
            r.pdf = (1.0f - p_reflect) * d * wm.z * dwm_dwi;
            r.geom = (1.0f - F) * d * g * dot(o, wm) / o.z * dwm_dwi / (etap * etap);
        }
        return r;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        if (is_delta(lobe)) return smooth_sample(lobe, wo, u_event, lobe.weight, lobe.weight);

        // Rough: Cycles 3.4 splits its Glass (and the Principled GGX transmission) into a GGX
        // reflection weighted by the Fresnel term at the shading normal and a GGX refraction weighted
        // by 1 - that term (svm/closure.h), not by each microfacet's Fresnel term (Walter et al.):
        // the event is chosen with that probability, and terms() weights each side by it.
        return rough_sample<DielectricLobe>(lobe, wo, u, u_event, lobe.alpha, lobe.alpha,
                                            lobe.variant == kBeckmannDistribution);
    }

    // Smooth interface: the event chosen with its exact Fresnel probability; value / pdf is the
    // throughput multiplier: the reflection's colour, or the refraction's times (eta_i / eta_t)^2.
    static BsdfSample smooth_sample(const Lobe& lobe, const Vec3& wo, float u_event, const Color& reflection,
                                    const Color& refraction) {
        BsdfSample s;
        if (!(wo.z != 0.0f)) return s;
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;  // eta_t / eta_i
        if (!(etap > 0.0f) || !std::isfinite(etap)) return s;
        float F = fresnel_dielectric(std::fabs(wo.z), etap);
        const float p_reflect = reflection_probability(lobe, F);  // or the one event a caustics toggle left
        if (u_event < p_reflect) {
            s.wi = Vec3(-wo.x, -wo.y, wo.z);
            s.value = reflection * F;
            s.pdf = p_reflect;
        } else {
            Vec3 wt;
            if (!lobe_detail::refract_dir(wo * side, Vec3(0, 0, 1), etap, &wt)) return BsdfSample{};
            s.wi = wt * side;
            s.value = refraction * ((1.0f - F) / (etap * etap));
            s.pdf = 1.0f - p_reflect;
            s.eta = etap;
            s.transmission = true;
        }
        s.delta = true;
        if (!s.valid()) return BsdfSample{};
        return s;
    }

    // A rough sample valued by kind L's eval/pdf (rough_terms with the same alphas): the event by the
    // Fresnel term at the shading normal, then the visible normal at that event's alpha.
    template <class L>
    static BsdfSample rough_sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event, float alpha_r,
                                   float alpha_t, bool beckmann = false) {
        if (!(wo.z != 0.0f)) return {};
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;  // eta_t / eta_i
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        Vec3 o = wo * side;
        float F = fresnel_dielectric(o.z, etap);
        bool transmission = !(u_event < reflection_probability(lobe, F));  // F = 1 under total internal reflection
        const float alpha = transmission ? alpha_t : alpha_r;
        Vec3 wm = beckmann ? BeckmannLobe::sample_normal(alpha, u) : ggx_sample_visible_normal(o, alpha, u);
        float cos_om = dot(o, wm);
        if (!(cos_om > 0.0f)) return {};
        Vec3 i;
        if (!transmission) {
            i = reflect(o, wm);
            if (!(i.z > 0.0f)) return {};
            i = normalize(i);
        } else {
            if (!lobe_detail::refract_dir(o, wm, etap, &i) || !(i.z < 0.0f)) return {};
        }
        return lobe_sample_at<L>(lobe, wo, i * side, transmission, transmission ? etap : 1.0f);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
