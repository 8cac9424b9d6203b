// The one place that maps a LobeKind to its lobe struct (lobes/<kind>.h). Every per-lobe question
// the engine asks (Bsdf, the spectral tracer, the passes, path-space filtering, the feature gate,
// the bindings) goes through visit_lobe or for_each_lobe_kind, so:
//  * a LobeKind without a case here is a compile error (-Wswitch made an error below, no default);
//  * a struct missing one of lobe.h's pieces is a compile error where the piece is used;
//  * the switch is inlined into each caller: no virtual call, no function pointer per sample.
#pragma once
#include <cstddef>
#include <type_traits>

#include "scene/lobes/anisotropic.h"
#include "scene/lobes/ashikhmin_shirley.h"
#include "scene/lobes/beckmann.h"
#include "scene/lobes/clearcoat.h"
#include "scene/lobes/dielectric.h"
#include "scene/lobes/diffuse.h"
#include "scene/lobes/glass_multiple.h"
#include "scene/lobes/hair.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/microfacet.h"
#include "scene/lobes/multi_glass.h"
#include "scene/lobes/multi_glass_walk.h"
#include "scene/lobes/multiscatter_aniso_ggx.h"
#include "scene/lobes/multiscatter_ggx.h"
#include "scene/lobes/multiscatter_walk.h"
#include "scene/lobes/oren_nayar.h"
#include "scene/lobes/principled_diffuse.h"
#include "scene/lobes/principled_glass.h"
#include "scene/lobes/principled_hair.h"
#include "scene/lobes/principled_part.h"
#include "scene/lobes/refraction.h"
#include "scene/lobes/sheen.h"
#include "scene/lobes/subsurface.h"
#include "scene/lobes/toon_diffuse.h"
#include "scene/lobes/toon_glossy.h"
#include "scene/lobes/translucent.h"
#include "scene/lobes/transparent.h"
#include "scene/lobes/velvet.h"

namespace smis {

template <class... Kinds>
struct LobeKindList {
    static constexpr size_t size = sizeof...(Kinds);
};
// Every lobe kind, in LobeKind order.
using AllLobeKinds = LobeKindList<DiffuseLobe, MicrofacetLobe, DielectricLobe, ClearcoatLobe, SheenLobe,
                                  TransparentLobe, PrincipledDiffuseLobe, OrenNayarLobe, VelvetLobe, TranslucentLobe,
                                  RefractionLobe, BeckmannLobe, ToonDiffuseLobe, ToonGlossyLobe, MultiGgxLobe,
                                  GgxMultipleLobe, AnisoGgxLobe, AnisoBeckmannLobe, PrincipledGlassLobe, SubsurfaceLobe,
                                  PrincipledPartLobe, HairReflectionLobe, HairTransmissionLobe, PrincipledHairRLobe,
                                  PrincipledHairTTLobe, PrincipledHairTRTLobe, PrincipledHairTRRTLobe, MultiGlassLobe,
                                  GlassMultipleLobe, AshikhminShirleyLobe, MultiAnisoGgxLobe,
                                  AnisoGgxMultipleLobe, MultiGgxWalkLobe, MultiGlassWalkLobe>;
static_assert(AllLobeKinds::size == size_t(LobeKind::Count), "every LobeKind needs its struct in AllLobeKinds");

// What a kind compiled out of this build (kEnabled false, core/features.h) dispatches to: nothing to
// evaluate or sample. Scenes that use such a kind are refused when they are loaded (Scene::sanitize).
struct DisabledLobe : LobeDefaults<DisabledLobe> {
    static constexpr LobeKind kKind = LobeKind::Count;
    static constexpr const char* kName = "";
    static constexpr bool kEnabled = false;
    static constexpr const char* kFeature = nullptr;
    static constexpr RayLabel kLabel = RayLabel::Diffuse;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static bool is_delta(const Lobe&) { return false; }
    static LobeTerms terms(const Lobe&, const Vec3&, const Vec3&) { return {}; }
    static BsdfSample sample(const Lobe&, const Vec3&, Point2, float) { return {}; }
    static Color albedo(const Lobe&) { return Color(0.0f); }
};

namespace lobe_detail {
template <class L, bool kGated, class F>
[[gnu::always_inline]] inline decltype(auto) call_kind(F&& f) {
    if constexpr (kGated && !L::kEnabled) return f(DisabledLobe{});
    else return f(L{});
}
}  // namespace lobe_detail

// f(Kind{}) for the struct of `kind` (DisabledLobe for a kind compiled out, unless kGated is false).
// f must return the same type for every kind.
#pragma GCC diagnostic push
#pragma GCC diagnostic error "-Wswitch"
template <bool kGated = true, class F>
[[gnu::always_inline]] inline decltype(auto) visit_lobe(LobeKind kind, F&& f) {
    using lobe_detail::call_kind;
    switch (kind) {
        case DiffuseLobe::kKind: return call_kind<DiffuseLobe, kGated>(f);
        case MicrofacetLobe::kKind: return call_kind<MicrofacetLobe, kGated>(f);
        case DielectricLobe::kKind: return call_kind<DielectricLobe, kGated>(f);
        case ClearcoatLobe::kKind: return call_kind<ClearcoatLobe, kGated>(f);
        case SheenLobe::kKind: return call_kind<SheenLobe, kGated>(f);
        case TransparentLobe::kKind: return call_kind<TransparentLobe, kGated>(f);
        case PrincipledDiffuseLobe::kKind: return call_kind<PrincipledDiffuseLobe, kGated>(f);
        case OrenNayarLobe::kKind: return call_kind<OrenNayarLobe, kGated>(f);
        case VelvetLobe::kKind: return call_kind<VelvetLobe, kGated>(f);
        case TranslucentLobe::kKind: return call_kind<TranslucentLobe, kGated>(f);
        case RefractionLobe::kKind: return call_kind<RefractionLobe, kGated>(f);
        case BeckmannLobe::kKind: return call_kind<BeckmannLobe, kGated>(f);
        case ToonDiffuseLobe::kKind: return call_kind<ToonDiffuseLobe, kGated>(f);
        case ToonGlossyLobe::kKind: return call_kind<ToonGlossyLobe, kGated>(f);
        case MultiGgxLobe::kKind: return call_kind<MultiGgxLobe, kGated>(f);
        case GgxMultipleLobe::kKind: return call_kind<GgxMultipleLobe, kGated>(f);
        case AnisoGgxLobe::kKind: return call_kind<AnisoGgxLobe, kGated>(f);
        case AnisoBeckmannLobe::kKind: return call_kind<AnisoBeckmannLobe, kGated>(f);
        case PrincipledGlassLobe::kKind: return call_kind<PrincipledGlassLobe, kGated>(f);
        case SubsurfaceLobe::kKind: return call_kind<SubsurfaceLobe, kGated>(f);
        case PrincipledPartLobe::kKind: return call_kind<PrincipledPartLobe, kGated>(f);
        case HairReflectionLobe::kKind: return call_kind<HairReflectionLobe, kGated>(f);
        case HairTransmissionLobe::kKind: return call_kind<HairTransmissionLobe, kGated>(f);
        case PrincipledHairRLobe::kKind: return call_kind<PrincipledHairRLobe, kGated>(f);
        case PrincipledHairTTLobe::kKind: return call_kind<PrincipledHairTTLobe, kGated>(f);
        case PrincipledHairTRTLobe::kKind: return call_kind<PrincipledHairTRTLobe, kGated>(f);
        case PrincipledHairTRRTLobe::kKind: return call_kind<PrincipledHairTRRTLobe, kGated>(f);
        case MultiGlassLobe::kKind: return call_kind<MultiGlassLobe, kGated>(f);
        case GlassMultipleLobe::kKind: return call_kind<GlassMultipleLobe, kGated>(f);
        case AshikhminShirleyLobe::kKind: return call_kind<AshikhminShirleyLobe, kGated>(f);
        case MultiAnisoGgxLobe::kKind: return call_kind<MultiAnisoGgxLobe, kGated>(f);
        case AnisoGgxMultipleLobe::kKind: return call_kind<AnisoGgxMultipleLobe, kGated>(f);
        case MultiGgxWalkLobe::kKind: return call_kind<MultiGgxWalkLobe, kGated>(f);
        case MultiGlassWalkLobe::kKind: return call_kind<MultiGlassWalkLobe, kGated>(f);
        case LobeKind::Count: break;
    }
    return f(DisabledLobe{});  // not a kind (a corrupt byte): nothing to evaluate
}
#pragma GCC diagnostic pop

// f(Kind{}) for every kind of AllLobeKinds, in order (gate-independent: for names and features).
template <class F, class... Kinds>
inline void for_each_lobe_kind_in(LobeKindList<Kinds...>, F&& f) {
    (f(Kinds{}), ...);
}
template <class F>
inline void for_each_lobe_kind(F&& f) {
    for_each_lobe_kind_in(AllLobeKinds{}, f);
}

// The kind named `name` (lobe.h's kName); false for an unknown name.
inline bool lobe_kind_from_name(const char* name, LobeKind* kind) {
    bool found = false;
    for_each_lobe_kind([&](auto k) {
        using L = decltype(k);
        if (!found && std::char_traits<char>::compare(name, L::kName, std::char_traits<char>::length(L::kName) + 1) == 0) {
            *kind = L::kKind;
            found = true;
        }
    });
    return found;
}

// Per-lobe properties the integrators ask for.
inline bool lobe_is_delta(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::is_delta(lobe); });
}
inline RayLabel lobe_label(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kLabel; });
}
inline DensityModel lobe_density_model(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kDensity; });
}
inline SpectralFresnel lobe_spectral_fresnel(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kSpectral; });
}
inline bool lobe_dispersive(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kDispersive; });
}
inline bool lobe_backface_inverts_eta(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kBackfaceInvertsEta; });
}
inline bool lobe_has_own_tangent(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [](auto k) { return decltype(k)::kOwnTangent; });
}
inline bool lobe_colour_f0(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::colour_f0(lobe); });
}
inline bool lobe_measured_metal(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::measured_metal(lobe); });
}
// The Fresnel factor of a kTinted lobe at one wavelength, f0_at() the lobe's f0 there.
template <class F0At>
inline float lobe_spectral_colour(const Lobe& lobe, F0At&& f0_at, float cos_d) {
    return visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::spectral_colour(lobe, f0_at, cos_d); });
}
inline Color lobe_albedo(const Lobe& lobe) {
    return visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::albedo(lobe); });
}

}  // namespace smis
