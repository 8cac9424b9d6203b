// Toon diffuse (Cycles 3.4's Toon BSDF, component Diffuse, bsdf_toon.h): full intensity within Size x
// 90 degrees of the normal, fading linearly to 0 over a further Smooth x 90 degrees:
//   f cos_i = I(theta_i) / (2 pi (1 - cos theta_s)),  theta_s = min((Size + Smooth) 90deg, 90deg),
// i.e. the uniform density of the cone theta_s times the intensity (Cycles' expression; no cosine).
// Sampled uniformly in that cone. Cycles' sampler values a sample by the intensity at u x theta_s
// instead of its true angle; we use the true angle, so eval, pdf and sample agree (identical to
// Cycles for Smooth 0, the node's default). Size is kept in `alpha`, Smooth in `f0.x` (both [0, 1]).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

namespace toon {
// Cycles' bsdf_toon_get_intensity: 1 inside max_angle, a linear ramp over `smooth`, 0 beyond.
inline float intensity(float max_angle, float smooth, float angle) {
    if (angle < max_angle) return 1.0f;
    if (smooth != 0.0f && angle < max_angle + smooth) return 1.0f - (angle - max_angle) / smooth;
    return 0.0f;
}
struct Cone {
    float max_angle, smooth, sample_angle, one_minus_cos;
};
inline Cone cone_of(const Lobe& lobe) {
    Cone c;
    c.max_angle = clampf(lobe.alpha, 0.0f, 1.0f) * 0.5f * kPi;
    c.smooth = clampf(lobe.f0.x, 0.0f, 1.0f) * 0.5f * kPi;
    c.sample_angle = std::min(c.max_angle + c.smooth, 0.5f * kPi);
    c.one_minus_cos = 1.0f - std::cos(c.sample_angle);
    return c;
}
// f cos and pdf for a direction at `cos_axis` from the cone's axis.
inline LobeTerms cone_terms(const Cone& c, float cos_axis) {
    if (!(c.one_minus_cos > 0.0f)) return {};
    float angle = std::acos(clampf(cos_axis, -1.0f, 1.0f));
    if (!(angle < c.sample_angle)) return {};
    LobeTerms t;
    t.pdf = uniform_cone_pdf(c.one_minus_cos);
    t.geom = t.pdf * intensity(c.max_angle, c.smooth, angle);
    return t;
}
}  // namespace toon

struct ToonDiffuseLobe : LobeDefaults<ToonDiffuseLobe> {
    static constexpr LobeKind kKind = LobeKind::ToonDiffuse;
    static constexpr const char* kName = "toon_diffuse";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        return toon::cone_terms(toon::cone_of(lobe), wi.z);
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        toon::Cone c = toon::cone_of(lobe);
        if (!(c.one_minus_cos > 0.0f)) return {};
        Vec3 wi = sample_uniform_cone(u, c.one_minus_cos);
        if (!(wi.z > 0.0f)) return {};
        return lobe_sample_at<ToonDiffuseLobe>(lobe, wo, wi);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
