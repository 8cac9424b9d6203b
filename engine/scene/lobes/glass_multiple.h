// Multiscatter GGX glass, the light its random walk scatters more than once (Heitz, Hanika, d'Eon and
// Dachsbacher 2016 with the dielectric phase function, as Cycles 3.4's mf_sample: scene/ggx_walk.h,
// glass_walk), on both sides of the interface. Cycles walks at every evaluation (a stochastic eval,
// an approximate pdf); we walk once, at build time, and tabulate where the walks of two or more bounces
// leave (scene/ggx_glass.h: 11 roughnesses x 18 relative IORs (9 nodes on each side of 1) x 12
// incident cosines x 2 sides x 8 x 6 leaving cells, 100,000 walks per incident cosine), so eval is
// deterministic and agrees with pdf. Sampled by the side, in proportion to the table's albedo there
// from wo, then the cosine on that side: pdf = P(side | wo) |cos_i| / pi.
//
// The walk's throughput stays 1 through a refraction (an energy density); as the single scattering
// (multi_glass.h) the transmitted side carries the radiance scaling (eta_i / eta_t)^2 of the one net
// crossing. Colours, as Cycles' walk applies them (kTinted: fresnel() by the side, cos_d > 0 the
// reflection): the Glass BSDF (variant 0) multiplies by its colour c = f0 at every bounce after the
// first (the first is in the weight), the Principled BSDF (variant 1) by its base colour f0 at every
// refraction and by Cycles' interpolated Fresnel colour FH + (1 - FH) cspec0 at every reflection
// (cspec0 = 1 - Specular Tint (1 - base), kind_colour.x the Specular Tint; FH from the Fresnel term at
// that reflection's microfacet): the table holds the shares of the walks by their number of further
// bounces, and the mean coefficients of the Principled colour as a polynomial in the base and cspec0,
// per incident cosine and side, so the colour is exact for any colour and tint (scene/ggx_glass.h).
// (A geometric number of them fitted at c = 0.5, as for the glossy lobe, was 3.5-8% off for the
// Principled colour, and the shares averaged over wo up to 4%.)
//
// The lobe's weight holds the table's albedo averaged over wo and over eta and 1 / eta (M, constant
// when the back face inverts the IOR), so that the lobe selection picks it about as often as its
// energy; alpha_y keeps that M, which geom divides out again (exact also when Filter Glossy raises alpha).
#pragma once
#include "scene/ggx_glass.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/multiscatter_ggx.h"

namespace smis {

struct GlassMultipleLobe : LobeDefaults<GlassMultipleLobe> {
    static constexpr LobeKind kKind = LobeKind::GlassMultiple;
    static constexpr const char* kName = "glass_multiple";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;
    static constexpr bool kBackfaceInvertsEta = true;
    static constexpr uint8_t kPerBounce = 0, kPerRefraction = 1;  // variant: the colour model

    static bool is_delta(const Lobe&) { return false; }

    // One channel's colour factor of the multiple scattering for the walk's colour c (see above).
    // terms() passes cos_d = +-cos_o: its sign the side (+ reflected), its size wo's cosine.
    static float tint(const Lobe& lobe, float c, float cos_d) {
        return ggx_glass_multiple_colour(clampf(c, 0.0f, 1.0f), std::fabs(cos_d), lobe.alpha, lobe.eta,
                                         cos_d > 0.0f ? 0 : 1, lobe.variant,
                                         lobe.variant == kPerRefraction ? clampf(lobe.kind_colour.x, 0.0f, 1.0f) : 0.0f);
    }
    static Color fresnel(const Lobe& lobe, float cos_d) {
        return Color(tint(lobe, lobe.f0.x, cos_d), tint(lobe, lobe.f0.y, cos_d), tint(lobe, lobe.f0.z, cos_d));
    }
    static bool colour_f0(const Lobe&) { return true; }
    static bool measured_metal(const Lobe&) { return false; }
    template <class F0At>
    static float spectral_colour(const Lobe& lobe, F0At&& f0_at, float cos_d) {
        return tint(lobe, f0_at(), cos_d);
    }

    // The probability of leaving on the reflected side from wo (o.z > 0, relative IOR etap).
    static float reflection_share(float cos_o, float alpha, float etap) {
        float r = ggx_glass_multiple_albedo(cos_o, alpha, etap, 0), t = ggx_glass_multiple_albedo(cos_o, alpha, etap, 1);
        return r + t > 0.0f ? r / (r + t) : -1.0f;  // -1: nothing to sample
    }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z != 0.0f) || !(wi.z != 0.0f) || !(lobe.alpha_y > 0.0f)) return {};
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        Vec3 o = wo * side, i = wi * side;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        float share = reflection_share(o.z, lobe.alpha, etap);
        if (!(share >= 0.0f)) return {};
        bool reflect = i.z > 0.0f;
        float cos_i = std::fabs(i.z);
        LobeTerms t;
        t.cos_d = reflect ? o.z : -o.z;
        t.pdf = (reflect ? share : 1.0f - share) * cos_i * kInvPi;
        t.geom = ggx_glass_multiple_bsdf(o, i, lobe.alpha, etap) * cos_i / lobe.alpha_y;
        if (!reflect) t.geom /= etap * etap;
        return t;
    }

    static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        if (!(wo.z != 0.0f)) return {};
        float side = wo.z > 0.0f ? 1.0f : -1.0f;
        float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
        float share = reflection_share(std::fabs(wo.z), lobe.alpha, etap);
        if (!(share >= 0.0f)) return {};
        Vec3 i = sample_cosine_hemisphere(u);
        if (!(i.z > 0.0f)) return {};  // the disk rim maps onto the horizon
        bool transmission = !(u_event < share);
        if (transmission) i.z = -i.z;
        return lobe_sample_at<GlassMultipleLobe>(lobe, wo, i * side, transmission, transmission ? etap : 1.0f);
    }

    // Cycles' Albedo pass counts the closure's colour once: on MultiGlass.
    static Color albedo(const Lobe&) { return Color(0.0f); }
};

// The GlassMultiple lobe that goes with the MultiGlass lobe `single`, of colour model `variant` and
// walk colour c: false where it would carry next to nothing (smooth, or nearly).
inline bool glass_multiple_lobe(const Lobe& single, const Color& c, uint8_t variant, Lobe* multiple) {
    if (!(single.alpha >= kDeltaAlpha) || !(std::fabs(single.eta - 1.0f) >= kIndexMatchedEps)) return false;
    float average = ggx_glass_multiple_average(single.alpha, single.eta);
    if (!(average >= kMinMultipleEnergy)) return false;
    *multiple = single;
    multiple->kind = LobeKind::GlassMultiple;
    multiple->weight = single.weight * average;
    multiple->f0 = c;
    multiple->alpha_y = average;
    multiple->variant = variant;
    multiple->index = uint8_t(single.index + 1);
    return true;
}

}  // namespace smis
