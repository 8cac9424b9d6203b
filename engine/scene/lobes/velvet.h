// Ashikhmin velvet (Cycles 3.4's Velvet BSDF, bsdf_ashikhmin_velvet.h; Ashikhmin, Premoze and Shirley
// 2000, "A Microfacet-based BRDF Generator"): an inverted-Gaussian distribution of fibre normals
//   D(h) = exp(-cot^2(theta_h) / sigma^2) / (pi sigma^2 sin^4(theta_h)),  sigma = max(Sigma, 0.01),
// with Cycles' shadowing G = min(1, 2 cos_h cos_o / (wo.h), 2 cos_h cos_i / (wo.h)) and
//   f cos_i = D G / (4 cos_o)
// (Cycles' expression, which already carries the cosine). Sampled uniformly over the hemisphere, as
// Cycles does: the lobe is brightest at grazing angles, where cosine sampling would starve it.
// Sigma is kept in `alpha`. Labelled diffuse, as in Cycles.
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct VelvetLobe : LobeDefaults<VelvetLobe> {
    static constexpr LobeKind kKind = LobeKind::Velvet;
    static constexpr const char* kName = "velvet";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::General;  // uniform, not cosine
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr float kMinSigma = 0.01f;  // Cycles' clamp

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        Vec3 hsum = wo + wi;
        float len2 = length_sq(hsum);
        if (!(len2 > kMinHalfLenSq)) return {};
        Vec3 h = hsum / std::sqrt(len2);
        float cos_h = h.z, cos_ho = std::fabs(dot(wo, h));
        // Normal-incidence half vectors have cot = inf (D -> 0); Cycles cuts both ends the same way.
        if (!(std::fabs(cos_h) < 1.0f - 1e-5f && cos_ho > 1e-5f)) return {};
        float sigma = std::max(lobe.alpha, kMinSigma);
        float inv_sigma2 = 1.0f / (sigma * sigma);
        float ratio = std::max(cos_h / cos_ho, 1e-5f);
        float g = std::min(1.0f, std::min(2.0f * ratio * wo.z, 2.0f * ratio * wi.z));
        float sin2 = 1.0f - cos_h * cos_h;
        float cot2 = cos_h * cos_h / sin2;
        float d = std::exp(-cot2 * inv_sigma2) * inv_sigma2 * kInvPi / (sin2 * sin2);
        LobeTerms t;
        t.pdf = uniform_hemisphere_pdf();
        t.geom = 0.25f * d * g / wo.z;
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        if (!(wo.z > 0.0f)) return {};
        Vec3 wi = sample_uniform_hemisphere(u);
        if (!(wi.z > 0.0f)) return {};
        return lobe_sample_at<VelvetLobe>(lobe, wo, wi);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
