// Cycles 3.4's principled diffuse (Burley 2012 with retro-reflection), cosine sampled:
// f cos = cos_i / pi [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))], F = (1 - cos)^5,
// RR = roughness (1 + wi.wo) with roughness = sqrt(alpha) (the Principled Roughness input).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

// The principled diffuse's two parts without cos_i / pi, given FV and FL; subsurface scattering
// uses them apart (principled_part.h).
namespace principled_diffuse {
inline float lambert_part(float fv, float fl) { return (1.0f - 0.5f * fv) * (1.0f - 0.5f * fl); }
inline float retro_part(const Lobe& lobe, const Vec3& wo, const Vec3& wi, float fv, float fl) {
    float rr = std::sqrt(lobe.alpha) * (1.0f + dot(wi, wo));
    return rr * (fl + fv + fl * fv * (rr - 1.0f));
}
}  // namespace principled_diffuse

struct PrincipledDiffuseLobe : LobeDefaults<PrincipledDiffuseLobe> {
    static constexpr LobeKind kKind = LobeKind::PrincipledDiffuse;
    static constexpr const char* kName = "principled_diffuse";
    static constexpr bool kEnabled = kWithPrincipledExtras;
    static constexpr const char* kFeature = "principled_extras";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        float fv = schlick_weight(wo.z), fl = schlick_weight(wi.z);
        float f = principled_diffuse::lambert_part(fv, fl) + principled_diffuse::retro_part(lobe, wo, wi, fv, fl);
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(wi.z);
        t.geom = wi.z * kInvPi * f;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<PrincipledDiffuseLobe>(lobe, wo, u);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
