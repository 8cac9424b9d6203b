#include "scene/subsurface_closure.h"

namespace smis {

namespace {

// Below this radius a channel is diffuse (Cycles' BSSRDF_MIN_RADIUS).
constexpr float kMinRadius = 1e-8f;

// Diffuse reflectance of the dipole for single-scattering albedo a' (Jensen et al. 2001, eq. 15
// with A from Fdr): Rd = a'/2 (1 + exp(-4/3 A s)) exp(-s), s = sqrt(3 (1 - a')).
float dipole_reflectance(float alpha_prime, float four_thirds_a) {
    const float s = std::sqrt(3.0f * (1.0f - alpha_prime));
    return 0.5f * alpha_prime * (1.0f + std::exp(-four_thirds_a * s)) * std::exp(-s);
}

}  // namespace

float random_walk_radius_scale(float albedo, float ior) {
    const float inv = 1.0f / ior;
    // Egan and Hilgeman's fit of the diffuse Fresnel reflectance Fdr, as Cycles uses it.
    const float fdr = inv * (-1.440f * inv + 0.710f) + 0.668f + 0.0636f * ior;
    const float four_thirds_a = (4.0f / 3.0f) * (1.0f + fdr) / (1.0f - fdr);
    float alpha_prime;
    if (albedo < 1e-4f) {
        alpha_prime = 0.0f;
    } else if (albedo >= 0.995f) {
        alpha_prime = 0.999999f;
    } else {  // Rd grows with a': bisection, 12 steps as Cycles (its last midpoint)
        float lo = 0.0f, hi = 1.0f, mid = 0.5f;
        for (int i = 0; i < 12; ++i) {
            mid = 0.5f * (lo + hi);
            if (dipole_reflectance(mid, four_thirds_a) < albedo) lo = mid;
            else hi = mid;
        }
        alpha_prime = mid;
    }
    return std::sqrt(3.0f * (1.0f - alpha_prime));
}

int subsurface_lobes(const SubsurfaceClosure& c, Lobe* out) {
    int n = 0;
    auto base = [&](LobeKind kind, const Color& weight) {
        Lobe l;
        l.kind = kind;
        l.weight = vmax(weight, Color(0.0f));
        l.index = c.index;
        return l;
    };
    const float roughness = clampf(std::isfinite(c.roughness) ? c.roughness : 0.0f, 0.0f, 1.0f);
    if (c.principled) {
        Lobe retro = base(LobeKind::PrincipledPart, c.weight);
        retro.variant = PrincipledPartLobe::kRetro;
        retro.alpha = roughness * roughness;
        retro.index = uint8_t(c.index + 1);
        out[n++] = retro;
    }
    Color sss_weight = c.weight, diffuse_weight(0.0f), radius = vmax(c.radius, Color(0.0f));
    for (int k = 0; k < 3; ++k) {
        if (radius[k] >= kMinRadius && std::isfinite(radius[k])) continue;
        diffuse_weight[k] = sss_weight[k];
        sss_weight[k] = 0.0f;
        radius[k] = 0.0f;
    }
    if (max_component(diffuse_weight) > 0.0f) {
        Lobe d = base(c.principled ? LobeKind::PrincipledPart : LobeKind::Diffuse, diffuse_weight);
        d.variant = PrincipledPartLobe::kLambert;
        out[n++] = d;
    }
    if (!(max_component(sss_weight) > 0.0f)) return n;
    const float ior = clampf(std::isfinite(c.ior) ? c.ior : 1.4f, 1.01f, 3.8f);
    if (c.method == SubsurfaceMethod::RandomWalk) {
        for (int k = 0; k < 3; ++k) radius[k] *= random_walk_radius_scale(c.albedo[k], ior);
    } else {  // Fixed Radius and Christensen-Burley: Cycles' 1 / (4 pi) mean free path
        radius = radius * (0.25f * kInvPi);
    }
    Lobe s = base(LobeKind::Subsurface, sss_weight);
    s.f0 = vmax(c.albedo, Color(0.0f));
    s.kind_colour = radius;
    s.alpha = clampf(std::isfinite(c.anisotropy) ? c.anisotropy : 0.0f, 0.0f, 0.9f);
    s.eta = ior;
    s.variant = uint8_t((c.principled ? SubsurfaceLobe::kPrincipledExit : 0) |
                        (c.method == SubsurfaceMethod::ChristensenBurley ? SubsurfaceLobe::kDisk : 0));
    out[n++] = s;
    return n;
}

}  // namespace smis
