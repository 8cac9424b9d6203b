// Oren-Nayar diffuse (Cycles 3.4's Diffuse BSDF with Roughness > 0, bsdf_oren_nayar.h): the "qualitative"
// model of Oren and Nayar 1994 in Fujii's form, as Cycles evaluates it:
//   f cos_i = cos_i (A + B s),  s = wi.wo - cos_i cos_o, divided by max(cos_i, cos_o) when s > 0,
//   A = 1 / (pi + (3 pi - 4) sigma / 6),  B = sigma A,  sigma = roughness in [0, 1] (kept in `alpha`).
// Cycles samples it uniformly over the hemisphere; we sample the cosine instead (same expectation,
// less noise, and path-space filtering's cosine density model covers it).
#pragma once
#include <cfloat>

#include "scene/lobes/lobe.h"

namespace smis {

struct OrenNayarLobe : LobeDefaults<OrenNayarLobe> {
    static constexpr LobeKind kKind = LobeKind::OrenNayar;
    static constexpr const char* kName = "oren_nayar";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::Cosine;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return false; }

    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
        float sigma = clampf(lobe.alpha, 0.0f, 1.0f);
        float a = 1.0f / (kPi + ((3.0f * kPi - 4.0f) / 6.0f) * sigma);
        float b = sigma * a;
        float s = dot(wi, wo) - wi.z * wo.z;
        if (s > 0.0f) s /= std::max(wi.z, wo.z) + FLT_MIN;
        LobeTerms t;
        t.pdf = cosine_hemisphere_pdf(wi.z);
        t.geom = wi.z * (a + b * s);
        return t;
    }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float) {
        return cosine_sample_of<OrenNayarLobe>(lobe, wo, u);
    }

    static Color albedo(const Lobe& lobe) { return lobe.weight; }
};

}  // namespace smis
