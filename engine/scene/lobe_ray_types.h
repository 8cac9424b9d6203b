// Which of Cycles' closure classes a lobe belongs to, for the settings that act on closures by
// class: a light's Ray Visibility (surface_shader.h: a light hidden from diffuse rays is not
// sampled for diffuse closures) and the caustics toggles (svm/closure.h: with Reflective or
// Refractive Caustics off, a surface reached by a diffuse ray builds no glossy reflection or no
// refraction closures).
#pragma once
#include "scene/bsdf.h"
#include "scene/ray_visibility.h"

namespace smis {

// kRayDiffuse, kRayGlossy and / or kRayTransmission as Cycles' CLOSURE_IS_BSDF_DIFFUSE / _GLOSSY /
// _TRANSMISSION classify the closure (Translucent is both diffuse and transmission; glass and
// refraction are transmission, their reflection included; the Transparent BSDF is none).
inline uint32_t lobe_ray_types(const Lobe& lobe) {
    switch (lobe.kind) {
        case LobeKind::Translucent: return kRayDiffuse | kRayTransmission;
        case LobeKind::Dielectric:
        case LobeKind::MultiGlass:
        case LobeKind::GlassMultiple:
        case LobeKind::MultiGlassWalk:
        case LobeKind::Refraction:
        case LobeKind::HairTransmission:
        case LobeKind::PrincipledHairTT:
        case LobeKind::PrincipledHairTRT:
        case LobeKind::PrincipledHairTRRT: return kRayTransmission;
        case LobeKind::Transparent: return 0;
        default: return lobe_label(lobe) == RayLabel::Diffuse ? kRayDiffuse : kRayGlossy;
    }
}

// The lobes of `bsdf` whose class shares no bit with `hidden` (the types a light is hidden from).
inline Bsdf lobes_not_of(const Bsdf& bsdf, uint32_t hidden) {
    return bsdf.only([&](const Lobe& l) { return !(lobe_ray_types(l) & hidden); });
}

// Cycles' caustics toggles: the closures a surface reached by a diffuse ray leaves out when
// Reflective Caustics are off (Glossy BSDF, Principled specular and clearcoat) or Refractive
// Caustics are off (Refraction BSDF). Glass and Principled transmission are one lobe here, Cycles'
// pair of closures (reflection weighted by F, refraction by 1 - F): it is left out when both toggles
// are off, and keeps the other half when one is (glass_half_left). Multiscatter glass is one closure
// in Cycles too: whole unless both toggles are off.
inline bool lobe_is_caustic(const Lobe& lobe, bool reflective_off, bool refractive_off) {
    switch (lobe.kind) {
        case LobeKind::Microfacet:
        case LobeKind::Beckmann:
        case LobeKind::MultiGgx:
        case LobeKind::GgxMultiple:
        case LobeKind::AnisoGgx:
        case LobeKind::AnisoBeckmann:
        case LobeKind::AshikhminShirley:
        case LobeKind::MultiAnisoGgx:
        case LobeKind::AnisoGgxMultiple:
        case LobeKind::MultiGgxWalk:
        case LobeKind::Clearcoat: return reflective_off;
        case LobeKind::Refraction: return refractive_off;
        case LobeKind::Dielectric:
        case LobeKind::PrincipledGlass:
        case LobeKind::MultiGlass:
        case LobeKind::GlassMultiple:
        case LobeKind::MultiGlassWalk: return reflective_off && refractive_off;
        default: return false;
    }
}
// The glass lobe with one caustics toggle off: its refraction (Reflective off) or its reflection
// (Refractive off) alone, as Cycles builds only the other closure of the pair (svm/closure.h, Glass
// and the single-scattering GGX Principled glass).
inline void glass_half_left(Lobe& lobe, bool reflective_off, bool refractive_off) {
    if (lobe.kind != LobeKind::Dielectric && lobe.kind != LobeKind::PrincipledGlass) return;
    if (reflective_off) lobe.glass_events &= uint8_t(~kGlassReflection);
    if (refractive_off) lobe.glass_events &= uint8_t(~kGlassRefraction);
}

// Cycles' Filter Glossy (bsdf_blur): the microfacet closures' alpha raised to at least `alpha`
// (GGX and Beckmann reflection, refraction and glass, multiscatter GGX, clearcoat, both axes of the
// anisotropic ones); the other closures keep theirs. Multiscatter GGX's multiple-scattering lobe
// keeps the energy of its own roughness (its weight was set from it with the material's colour).
inline void blur_lobe(Lobe& lobe, float alpha) {
    switch (lobe.kind) {
        case LobeKind::Microfacet:
        case LobeKind::Beckmann:
        case LobeKind::MultiGgx:
        case LobeKind::GgxMultiple:
        case LobeKind::Clearcoat:
        case LobeKind::Dielectric:
        case LobeKind::MultiGlass:
        case LobeKind::GlassMultiple:  // its alpha_y is not an alpha (glass_multiple.h)
        case LobeKind::MultiGlassWalk:  // Cycles re-walks at the new alpha
        case LobeKind::Refraction: lobe.alpha = std::max(lobe.alpha, alpha); break;
        case LobeKind::AnisoGgx:
        case LobeKind::AnisoBeckmann:
        case LobeKind::AshikhminShirley:
        case LobeKind::MultiAnisoGgx:
        case LobeKind::AnisoGgxMultiple:  // keeps its energy, as GgxMultiple
        case LobeKind::MultiGgxWalk:      // Cycles re-walks at the new alphas
        case LobeKind::PrincipledGlass:  // alpha_y: its refraction's alpha
            lobe.alpha = std::max(lobe.alpha, alpha);
            lobe.alpha_y = std::max(lobe.alpha_y, alpha);
            break;
        default: break;
    }
}

}  // namespace smis
