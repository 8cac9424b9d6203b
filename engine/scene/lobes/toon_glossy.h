// Toon glossy (Cycles 3.4's Toon BSDF, component Glossy, bsdf_toon.h): the toon intensity of
// lobes/toon_diffuse.h measured from the mirror direction R of wo instead of the normal, over the
// upper hemisphere; sampled uniformly in the cone about R (directions under the surface are
// dropped, as in Cycles). Cycles' eval reports the cone's density for directions outside the cone
// too (where its value is 0); our pdf is the true density, 0 there. Size in `alpha`, Smooth in `f0.x`.
#pragma once
#include "scene/lobes/lobe.h"
#include "scene/lobes/toon_diffuse.h"

namespace smis {

struct ToonGlossyLobe : LobeDefaults<ToonGlossyLobe> {
    static constexpr LobeKind kKind = LobeKind::ToonGlossy;
    static constexpr const char* kName = "toon_glossy";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 r(-wo.x, -wo.y, wo.z);
        return toon::cone_terms(toon::cone_of(lobe), dot(r, wi));
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        toon::Cone c = toon::cone_of(lobe);
        if (!(c.one_minus_cos > 0.0f)) return {};
        Frame around_r(normalize(Vec3(-wo.x, -wo.y, wo.z)));
        Vec3 wi = around_r.to_world(sample_uniform_cone(u, c.one_minus_cos));
        if (!(wi.z > 0.0f)) return {};
        return lobe_sample_at<ToonGlossyLobe>(lobe, wo, wi);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
