// One component of Cycles 3.4's principled diffuse (bsdf_principled_diffuse.h), which subsurface
// scattering splits apart (Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated
// Subsurface Scattering", section 2.3): lobe.variant chooses
//   kLambert  (1 - FV/2)(1 - FL/2)   the diffuse part, where a BSSRDF renders as diffuse (after a
//                                    diffuse bounce, or a channel whose radius is 0);
//   kExit     (1 - FL/2)             the closure at a subsurface walk's exit point (the entry's
//                                    (1 - FV/2) is not applied, as in Cycles);
//   kRetro    RR (FL + FV + FL FV (RR - 1))  the retro-reflection kept at the entry point,
// each times cos_i / pi, with F = (1 - cos)^5 and RR = roughness (1 + wi.wo), roughness = sqrt(alpha).
// Lambert + Retro is PrincipledDiffuseLobe exactly. Cosine sampled.
#pragma once
#include "scene/lobes/lobe.h"
#include "scene/lobes/principled_diffuse.h"

namespace smis {

struct PrincipledPartLobe : LobeDefaults<PrincipledPartLobe> {
    static constexpr LobeKind kKind = LobeKind::PrincipledPart;
    static constexpr const char* kName = "principled_part";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    enum Variant : uint8_t { kLambert = 0, kExit = 1, kRetro = 2 };

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        float fv = schlick_weight(wo.z), fl = schlick_weight(wi.z);
        float f = lobe.variant == kLambert ? principled_diffuse::lambert_part(fv, fl)
                  : lobe.variant == kExit  ? 1.0f - 0.5f * fl
                                           : principled_diffuse::retro_part(lobe, wo, wi, fv, fl);
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(wi.z);
        t.geom = wi.z * kInvPi * f;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<PrincipledPartLobe>(lobe, wo, u);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
