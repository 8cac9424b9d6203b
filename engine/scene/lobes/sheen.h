// Principled sheen (Cycles 3.4 bsdf_principled_sheen.h): f cos_i = (1 - wi.h)^5 cos_i (no 1/pi),
// reflection only, cosine sampled.
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct SheenLobe : LobeDefaults<SheenLobe> {
    static constexpr LobeKind kKind = LobeKind::Sheen;
    static constexpr const char* kName = "sheen";
    static constexpr bool kEnabled = kWithPrincipledExtras;
    static constexpr const char* kFeature = "principled_extras";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe&, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 h = wo + wi;
        float len2 = length_sq(h);
        if (!(len2 > kMinHalfLenSq)) return {};
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(wi.z);
        t.geom = schlick_weight(dot(wi, h) / std::sqrt(len2)) * wi.z;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<SheenLobe>(lobe, wo, u);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
