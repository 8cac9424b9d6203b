// Multiscatter GGX (Glossy and Anisotropic BSDF) as Cycles 3.4 estimates it, one lobe for the whole
// closure, on request (the setting multiscatter_cycles_walk; off by default, where the consistent pair
// of lobes/multiscatter_ggx.h and multiscatter_aniso_ggx.h renders it). Cycles' estimator is not one
// BSDF (README, the material table): its sampled walk (mf_sample) and its light-sample evaluation
// (mf_eval) disagree, so its image depends on which technique carries the light. This lobe copies all
// three pieces (Heitz et al. 2016's random walk, scene/ggx_walk.h):
//  * sample: the walk from the view (ggx_walk::walk), value = throughput x pdf as Cycles' *eval *= *pdf,
//    so the sampled weight is the walk's throughput c^(bounces - 1) whatever the density says;
//  * eval: Cycles' stochastic estimate (ggx_walk::cycles_eval: from the shallower direction, next-event
//    estimation of the phase function at every further bounce, each tinted twice);
//  * pdf: Cycles' approximate MIS density (ggx_walk::cycles_pdf), not the walk's.
// So sample(), eval() and pdf() do not agree, by design: the lobe is Cycles' image, not a BSDF, and
// takes no part in the chi-square and agreement tests. The random numbers are drawn from a hash of
// the directions (eval) or of the sample's numbers (sample), so an image does not depend on the
// thread count. The closure's colour c is in f0 (FresnelMode::None: f0 is free), its weight c x mix
// in weight; alpha / alpha_y along / across its own tangent (kOwnTangent; equal for the Glossy BSDF).
// Spectral rendering reads the eval at the colour's channel mean (kSpectral None: weight x geom).
#pragma once
#include <cstring>
#include <initializer_list>

#include "core/rng.h"
#include "scene/ggx_walk.h"
#include "scene/lobes/anisotropic.h"
#include "scene/lobes/lobe.h"

namespace smis {

namespace walk_lobe_detail {

// Uniform numbers in [0, 1) from a 64-bit key (splitmix64 steps).
struct HashRand {
    uint64_t state;
    float operator()() {
        state = mix64(state);
        return float(uint32_t(state >> 40)) * 0x1p-24f;
    }
};
inline uint64_t key_of(std::initializer_list<float> values) {
    uint64_t h = 0x243f6a8885a308d3ull;
    for (float f : values) {
        uint32_t b;
        std::memcpy(&b, &f, sizeof b);
        h = mix64(h ^ b);
    }
    return h;
}

// Cycles' walk lobes (L: pdf() its MIS density, walk_eval() its stochastic eval for a colour): eval and
// pdf, and the spectral tracer's terms (the eval at the colour's channel mean).
template <class L>
EvalPdf eval_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    EvalPdf r;
    r.pdf = L::pdf(lobe, wo, wi);
    if (!(r.pdf > 0.0f)) return {};
    r.value = lobe.weight * L::walk_eval(lobe, wo, wi, lobe.f0);
    return r;
}
template <class L>
LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    LobeTerms t;
    t.pdf = L::pdf(lobe, wo, wi);
    if (!(t.pdf > 0.0f)) return {};
    t.geom = L::walk_eval(lobe, wo, wi, Color(average(lobe.f0))).x;
    return t;
}

}  // namespace walk_lobe_detail

struct MultiGgxWalkLobe : LobeDefaults<MultiGgxWalkLobe> {
    static constexpr LobeKind kKind = LobeKind::MultiGgxWalk;
    static constexpr const char* kName = "multi_ggx_walk";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kOwnTangent = true;
    static constexpr bool kColourEval = true;  // eval_pdf: a colour no product weight x geom gives
    static constexpr uint8_t kFresnel = 2;     // variant: the Principled BSDF's reflection (f0 = cspec0)

    static bool is_delta(const Lobe& lobe) { return lobe_detail::aniso_is_delta(lobe); }

    static ggx_walk::Anisotropic surface(const Lobe& lobe) {
        return {lobe_detail::sanitize_alpha(lobe.alpha), lobe_detail::sanitize_alpha(lobe.alpha_y)};
    }
    // Cycles' density for MIS (mf_ggx_pdf / mf_ggx_aniso_pdf at sqrt(alpha_x alpha_y)).
    static float pdf(const Lobe& lobe, const Vec3& wo_frame, const Vec3& wi_frame) {
        if (is_delta(lobe)) return 0.0f;
        ggx_walk::Anisotropic s = surface(lobe);
        return ggx_walk::cycles_pdf(lobe_detail::to_lobe_tangent(lobe, wo_frame),
                                    lobe_detail::to_lobe_tangent(lobe, wi_frame), s, std::sqrt(s.ax * s.ay));
    }
    // Cycles' colours: c at every further bounce, or the Principled's Fresnel colours of cspec0 = c.
    static ggx_walk::GlossyColours colours(const Lobe& lobe, const Color& c) {
        ggx_walk::GlossyColours k;
        k.fresnel = lobe.variant == kFresnel;
        (k.fresnel ? k.cspec0 : k.colour) = c;
        k.eta = lobe.eta;
        return k;
    }
    // Cycles' stochastic eval for colour c, its numbers from the two directions.
    static Color walk_eval(const Lobe& lobe, const Vec3& wo_frame, const Vec3& wi_frame, const Color& c) {
        walk_lobe_detail::HashRand rand{walk_lobe_detail::key_of(
            {wo_frame.x, wo_frame.y, wo_frame.z, wi_frame.x, wi_frame.y, wi_frame.z, lobe.alpha, lobe.alpha_y})};
        return ggx_walk::cycles_eval(lobe_detail::to_lobe_tangent(lobe, wo_frame),
                                     lobe_detail::to_lobe_tangent(lobe, wi_frame), surface(lobe), colours(lobe, c),
                                     rand);
    }
    static EvalPdf eval_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::eval_pdf<MultiGgxWalkLobe>(lobe, wo, wi);
    }
    // The spectral tracer's terms: the eval at the colour's channel mean.
    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::terms<MultiGgxWalkLobe>(lobe, wo, wi);
    }

    // Cycles' mf_sample: the walk from the view, its colour c at every bounce after the first (or the
    // Fresnel colour at every bounce's microfacet).
    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo_frame, Point2 u, float u_event) {
        BsdfSample out;
        Vec3 wo = lobe_detail::to_lobe_tangent(lobe, wo_frame);
        if (!(wo.z > 0.0f) || is_delta(lobe)) return out;
        walk_lobe_detail::HashRand rand{walk_lobe_detail::key_of({u.x, u.y, u_event, wo.x, wo.y, wo.z})};
        ggx_walk::Anisotropic s = surface(lobe);
        Color throughput(1.0f);
        ggx_walk::Exit e;
        if (lobe.variant == kFresnel) {
            e = ggx_walk::walk_on(wo, s, rand, [&](float cos_i) { throughput *= ggx_walk::fresnel_colour(cos_i, lobe.eta, lobe.f0); });
        } else {
            e = ggx_walk::walk_on(wo, s, rand);
            for (int k = 1; k < e.bounces; ++k) throughput *= lobe.f0;
        }
        if (e.bounces == 0 || !(e.dir.z > 0.0f)) return out;  // the walk died (Cycles: no sample)
        out.wi = lobe_detail::from_lobe_tangent(lobe, e.dir);
        out.pdf = pdf(lobe, wo_frame, out.wi);
        out.value = lobe.weight * throughput * out.pdf;
        return out;
    }

    // Glossy: the closure's colour; the Principled reflection: its colour at normal incidence.
    static Color albedo(const Lobe& lobe) { return lobe.variant == kFresnel ? lobe.weight * lobe.f0 : lobe.weight; }
};

// The pair of a Glossy or Anisotropic BSDF's Multiscatter GGX (lobes/multiscatter_ggx.h,
// multiscatter_aniso_ggx.h), marked by the compiler with this variant and the closure's colour in f0,
// so that the setting multiscatter_cycles_walk can put Cycles' estimator in its place at a shading
// point (path_tracing.h, cycles_multiscatter_lobes).
// The Principled BSDF's specular layer and metal with Multiscatter GGX are one closure in Cycles
// (MICROFACET_MULTI_GGX_FRESNEL: weight W = Principled weight x (1 - transmission), the interpolated
// Fresnel colour of cspec0 at the specular IOR at every bounce): the compiler marks the lobe that
// carries it (kCyclesPrincipled: the specular layer with f0 = cspec0, or the metal of Metallic 1, whose
// f0 is cspec0, with eta the specular IOR; both fields unused by those lobes) with W in kind_colour.z,
// and the other lobes of the pair kCyclesPrincipledPart; without a carrier (Specular 0 under a partial
// metal) nothing is marked and the lobes stay.
constexpr uint8_t kCyclesWalkable = 1;
constexpr uint8_t kCyclesPrincipled = MultiGgxWalkLobe::kFresnel;
constexpr uint8_t kCyclesPrincipledPart = 3;
inline void mark_cycles_walkable(Lobe* single, const Color& c) {
    single->variant = kCyclesWalkable;
    single->f0 = vmin(vmax(c, Color(0.0f)), Color(1.0f));  // Cycles saturates the closure's colour
}
inline void mark_cycles_principled(Lobe* carrier, const Color& cspec0, float weight) {
    carrier->variant = kCyclesPrincipled;
    carrier->f0 = vmin(vmax(cspec0, Color(0.0f)), Color(1.0f));  // Cycles saturates cspec0
    carrier->kind_colour.z = weight;
}
inline bool is_multiscatter_reflection(LobeKind k) {
    return k == LobeKind::MultiGgx || k == LobeKind::MultiAnisoGgx || k == LobeKind::GgxMultiple ||
           k == LobeKind::AnisoGgxMultiple;
}
inline bool replaced_by_cycles_walk(const Lobe& l) {
    return ((l.kind == LobeKind::GgxMultiple || l.kind == LobeKind::AnisoGgxMultiple) && l.variant == kCyclesWalkable) ||
           (is_multiscatter_reflection(l.kind) && l.variant == kCyclesPrincipledPart);
}
inline void to_cycles_walk(Lobe& l) {
    if ((l.kind != LobeKind::MultiGgx && l.kind != LobeKind::MultiAnisoGgx) ||
        (l.variant != kCyclesWalkable && l.variant != kCyclesPrincipled))
        return;
    if (l.kind == LobeKind::MultiGgx) l.alpha_y = l.alpha;  // its own tangent: kind_colour 0, the frame's
    if (lobe_detail::aniso_is_delta(l)) return;  // Cycles' mirror below alpha_x alpha_y 1e-7, as the lobes'
    l.kind = LobeKind::MultiGgxWalk;
    if (l.variant == kCyclesPrincipled) {
        l.weight = Color(l.kind_colour.z);
        l.kind_colour.z = 0.0f;
        l.fresnel = FresnelMode::None;
    }
}

}  // namespace smis
