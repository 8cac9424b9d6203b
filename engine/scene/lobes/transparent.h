// The Transparent BSDF's coloured part: a Dirac straight through (wi = -wo), value = weight. No
// refraction: same medium on both sides, no radiance scaling (eta 1).
#pragma once
#include "scene/lobes/lobe.h"

namespace smis {

struct TransparentLobe : LobeDefaults<TransparentLobe> {
    static constexpr LobeKind kKind = LobeKind::Transparent;
    static constexpr const char* kName = "transparent";
    static constexpr bool kEnabled = kWithPrincipledExtras;
    static constexpr const char* kFeature = "principled_extras";
    static constexpr RayLabel kLabel = RayLabel::Transparent;
    static constexpr DensityModel kDensity = DensityModel::General;  // a Dirac: never asked
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;

    static bool is_delta(const Lobe&) { return true; }
    static LobeTerms terms(const Lobe&, const Vec3&, const Vec3&) { return {}; }

    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2, float) {
        BsdfSample s;
        s.wi = -wo;
        s.value = lobe.weight;
        s.pdf = 1.0f;
        s.delta = true;
        s.transmission = true;
        return s;
    }

    // See-through is not reflectance.
    static Color albedo(const Lobe&) { return Color(0.0f); }
};

}  // namespace smis
