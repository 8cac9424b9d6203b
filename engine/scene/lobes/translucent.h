// Translucent (Cycles 3.4's Translucent BSDF, bsdf_diffuse.h): Lambertian transmission to the other
// side, f cos_i = color |cos_i| / pi for wi below the surface, cosine sampled about -z. No refraction
// (eta 1). Labelled diffuse (and transmission, from the sampled direction), as in Cycles.
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct TranslucentLobe : LobeDefaults<TranslucentLobe> {
    static constexpr LobeKind kKind = LobeKind::Translucent;
    static constexpr const char* kName = "translucent";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::General;  // transmission: not in the reflection model
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe&, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z < 0.0f)) return {};
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(-wi.z);
        t.geom = -wi.z * kInvPi;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        Vec3 wi = sample_cosine_hemisphere(u);
        if (!(wi.z > 0.0f)) return {};
        return lobe_sample_at<TranslucentLobe>(lobe, wo, -wi, true, 1.0f);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
