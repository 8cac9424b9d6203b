// Lambert (Cycles' Diffuse BSDF at Roughness 0): f cos_i = color cos_i / pi, cosine sampled.
// One-sided like Cycles' closures, which see a normal already flipped towards the viewer.
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct DiffuseLobe : LobeDefaults<DiffuseLobe> {
    static constexpr LobeKind kKind = LobeKind::Diffuse;
    static constexpr const char* kName = "diffuse";
    static constexpr bool kEnabled = true;
    static constexpr const char* kFeature = nullptr;
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }
    static LobeTerms terms(const Lobe&, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(wi.z);
        t.geom = wi.z * kInvPi;
        return t;
    }
    // Inlined into the dispatch: as a call, every Lambert sample paid for returning its BsdfSample
    // through memory (+0.5% instructions).
    [[gnu::always_inline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return lobe_detail::sample_cosine(lobe, wo, u);
    }
    // Cosine sampling: pdf = cos_i / pi, whose wo-only factor is 1/pi.
    static float fixed_wo_scale(const Lobe&, const Vec3& wo) { return wo.z > 0.0f ? kInvPi : 0.0f; }
    static float fixed_wo_pdf(const Lobe&, float scale, const Vec3&, const Vec3& wi) {
        return scale > 0.0f && wi.z > 0.0f ? wi.z * scale : 0.0f;
    }
    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
