// The Principled BSDF's transmission (Blender 3.4's Principled v1 with Transmission > 0), one lobe for
// the pair of closures Cycles 3.4 allocates (svm/closure.h, CLOSURE_BSDF_PRINCIPLED_ID, the
// single-scatter GGX branch):
//
//  * a GGX reflection of weight g F(cos_o) at the roughness alpha = roughness^2, coloured by Cycles'
//    interpolated Fresnel colour (bsdf_util.h's interpolate_fresnel_color): with F0 = F(1, eta) and
//    FH = (F(wi.wm, eta) - F0) / (1 - F0), the colour cspec0 (1 - FH) + FH, where
//    cspec0 = base Specular Tint + (1 - Specular Tint); untinted glass reflects white;
//  * a GGX refraction of weight base g (1 - F(cos_o)) at its own roughness, for the GGX distribution
//    1 - (1 - roughness)(1 - Transmission Roughness), squared (Walter et al. 2007's refraction, as
//    lobes/dielectric.h).
//
// F(cos_o) is the dielectric Fresnel term at the shading normal (Cycles' `fresnel`), and chooses the
// sampled event as the Glass lobe does (dielectric.h), so it cancels in value / pdf. Lobe fields:
// weight = g (the glass weight), f0 = the base colour (the refraction's colour), kind_colour.x = Specular
// Tint, alpha = the reflection's alpha, alpha_y = the refraction's, eta = the IOR (inverted on the back
// face, as Cycles). kTinted: eval = weight x fresnel(cos_d) x geom, where cos_d = wi.wm is negative
// for the refraction, whose colour is the base. Dirac only when both roughnesses are: with one of them
// smooth, that side is a GGX lobe at alpha kDeltaAlpha (Cycles treats alpha below 3.2e-4 as a mirror:
// the same image).
#pragma once
#include "scene/lobes/dielectric.h"
#include "scene/lobes/lobe.h"

namespace smis {

struct PrincipledGlassLobe : LobeDefaults<PrincipledGlassLobe> {
    static constexpr LobeKind kKind = LobeKind::PrincipledGlass;
    static constexpr const char* kName = "principled_glass";
    static constexpr bool kEnabled = true;
    static constexpr const char* kFeature = nullptr;
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    // The colour (base for the refraction, Cycles' Fresnel colour for the reflection) is per
    // wavelength (spectral_fresnel); the Fresnel term at the shading normal stays in geom.
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::Tinted;
    static constexpr bool kTinted = true;
    static constexpr bool kBackfaceInvertsEta = true;

    static bool is_delta(const Lobe& lobe) {
        return (!(lobe.alpha >= kDeltaAlpha) && !(lobe.alpha_y >= kDeltaAlpha)) ||
               !(std::fabs(lobe.eta - 1.0f) >= kIndexMatchedEps);
    }

    // Cycles' interpolated Fresnel colour of the reflection at cos_d = wi.wm (> 0), one channel of
    // cspec0 = base tint + 1 - tint: the spectral tracer calls it per wavelength.
    static float reflection_colour(float base, float tint, float eta, float cos_d) {
        float f0 = fresnel_dielectric(1.0f, eta);
        float fh = f0 < 1.0f ? clampf((fresnel_dielectric(cos_d, eta) - f0) / (1.0f - f0), 0.0f, 1.0f) : 1.0f;
        float cspec0 = base * tint + (1.0f - tint);
        return cspec0 * (1.0f - fh) + fh;
    }
    // The colour of a direction: the base for the refraction (cos_d < 0), Cycles' Fresnel colour for
    // the reflection.
    static float colour(float base, const Lobe& lobe, float cos_d) {
        return cos_d < 0.0f ? base : reflection_colour(base, lobe.kind_colour.x, lobe.eta, cos_d);
    }
    static Color fresnel(const Lobe& lobe, float cos_d) {
        return Color(colour(lobe.f0.x, lobe, cos_d), colour(lobe.f0.y, lobe, cos_d), colour(lobe.f0.z, lobe, cos_d));
    }

    // Spectral: the base is a colour, no measured metal, the colour per wavelength.
    static bool colour_f0(const Lobe&) { return true; }
    static bool measured_metal(const Lobe&) { return false; }
    template <class F0At>
    static float spectral_colour(const Lobe& lobe, F0At&& f0_at, float cos_d) {
        return colour(f0_at(), lobe, cos_d);
    }

    // The event's alpha: its own, or the sharpest GGX lobe where only the other side is rough.
    static float reflection_alpha(const Lobe& lobe) { return std::fmax(lobe.alpha, kDeltaAlpha); }
    static float refraction_alpha(const Lobe& lobe) { return std::fmax(lobe.alpha_y, kDeltaAlpha); }

    // The Glass lobe's terms and sampling (dielectric.h) at the two alphas.
    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return DielectricLobe::rough_terms(lobe, wo, wi, reflection_alpha(lobe), refraction_alpha(lobe));
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        if (!is_delta(lobe)) {
            return DielectricLobe::rough_sample<PrincipledGlassLobe>(lobe, wo, u, u_event, reflection_alpha(lobe),
                                                                     refraction_alpha(lobe));
        }
        // Smooth: value / pdf is the weight times the event's colour (and a refraction's radiance scaling).
        return DielectricLobe::smooth_sample(lobe, wo, u_event, lobe.weight * fresnel(lobe, std::fabs(wo.z)),
                                             lobe.weight * lobe.f0);
    }

    // As the glass lobe before it: the transmitted colour.
    static Color albedo(const Lobe& lobe) { return lobe.weight * lobe.f0; }
};

}  // namespace smis
