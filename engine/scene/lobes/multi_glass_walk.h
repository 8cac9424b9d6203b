// Multiscatter GGX glass (Glass BSDF, and the Principled BSDF's rough transmission, with Multiscatter
// GGX) as Cycles 3.4 estimates it, one lobe for the whole closure, on request (the setting
// multiscatter_cycles_walk; off by default, where the consistent pair lobes/multi_glass.h and
// glass_multiple.h renders it). As lobes/multiscatter_walk.h for the glossy closure, it copies Cycles'
// three pieces, which do not agree with each other (scene/ggx_glass_walk.h):
//  * sample: the dielectric walk from the view (ggx_walk::glass_walk, Cycles' mf_sample_glass), value =
//    throughput x pdf as Cycles' *eval *= *pdf, so the sampled weight is the walk's colour product;
//  * eval: Cycles' stochastic estimate (ggx_walk::cycles_glass_eval);
//  * pdf: Cycles' approximate MIS density (ggx_walk::cycles_glass_pdf).
// Fields: weight the closure's weight (the Glass BSDF's colour x mix; the Principled glass weight), f0
// the walk's colour (the Glass BSDF's colour; the Principled base), variant kFresnel for the Principled
// glass, whose reflections carry the interpolated Fresnel colour of cspec0 = base x Specular Tint +
// 1 - Specular Tint (kind_colour.x the Specular Tint), alpha, eta (inside over outside; two-sided as the
// other glass lobes: +z the outside). Random numbers from a hash of the directions (eval) or of the
// sample's numbers (sample): an image does not depend on the thread count.
#pragma once
#include "scene/ggx_glass_walk.h"
#include "scene/lobes/dielectric.h"
#include "scene/lobes/glass_multiple.h"
#include "scene/lobes/lobe.h"
#include "scene/lobes/multiscatter_walk.h"

namespace smis {

struct MultiGlassWalkLobe : LobeDefaults<MultiGlassWalkLobe> {
    static constexpr LobeKind kKind = LobeKind::MultiGlassWalk;
    static constexpr const char* kName = "multi_glass_walk";
    static constexpr bool kEnabled = kWithClosures;
    static constexpr const char* kFeature = "closures";
    static constexpr RayLabel kLabel = RayLabel::Glossy;
    static constexpr DensityModel kDensity = DensityModel::General;
    static constexpr SpectralFresnel kSpectral = SpectralFresnel::None;
    static constexpr bool kBackfaceInvertsEta = true;
    static constexpr bool kColourEval = true;  // eval_pdf: Cycles' colours per bounce
    static constexpr uint8_t kFresnel = GlassMultipleLobe::kPerRefraction;  // variant: the Principled glass

    // Cycles treats alpha_x alpha_y below 1e-7 as smooth glass; those lobes are not converted.
    static bool is_delta(const Lobe& lobe) { return !(lobe.alpha * lobe.alpha >= 1e-7f); }

    // The view mirrored above (o.z > 0), with the relative IOR of the far side.
    struct Side {
        float sign;
        float etap;
    };
    static bool side_of(const Lobe& lobe, const Vec3& wo, Side* s) {
        if (!(wo.z != 0.0f)) return false;
        s->sign = wo.z > 0.0f ? 1.0f : -1.0f;
        s->etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
        return s->etap > 0.0f && std::isfinite(s->etap);
    }
    // Cycles' colours of the closure at relative IOR etap; Fresnel colours only where asked.
    static ggx_walk::GlassColours colours(const Lobe& lobe, float etap, bool fresnel, const Color& colour) {
        ggx_walk::GlassColours c;
        c.colour = colour;
        c.fresnel = fresnel && lobe.variant == kFresnel;
        float tint = clampf(lobe.kind_colour.x, 0.0f, 1.0f);
        c.cspec0 = vmin(vmax(colour * tint + Color(1.0f - tint), Color(0.0f)), Color(1.0f));
        c.eta = etap;
        return c;
    }

    static float pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        Side s;
        if (is_delta(lobe) || !side_of(lobe, wo, &s)) return 0.0f;
        return ggx_walk::cycles_glass_pdf(wo * s.sign, wi * s.sign, lobe.alpha, s.etap);
    }
    // Cycles' stochastic eval for walk colour c (its Fresnel colours on reflections only).
    static Color walk_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, const Color& c) {
        Side s;
        if (!side_of(lobe, wo, &s)) return Color(0.0f);
        Vec3 o = wo * s.sign, i = wi * s.sign;
        walk_lobe_detail::HashRand rand{
            walk_lobe_detail::key_of({wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, lobe.alpha, lobe.eta})};
        return ggx_walk::cycles_glass_eval(o, i, lobe.alpha, s.etap, colours(lobe, s.etap, i.z > 0.0f, c), rand);
    }
    static EvalPdf eval_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::eval_pdf<MultiGlassWalkLobe>(lobe, wo, wi);
    }
    // The spectral tracer's terms: the eval at the colour's channel mean.
    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::terms<MultiGlassWalkLobe>(lobe, wo, wi);
    }

    // Cycles' mf_sample_glass: the walk from the view, its colours per bounce.
    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        BsdfSample out;
        Side s;
        if (is_delta(lobe) || !side_of(lobe, wo, &s)) return out;
        Vec3 o = wo * s.sign;
        walk_lobe_detail::HashRand rand{walk_lobe_detail::key_of({u.x, u.y, u_event, o.x, o.y, o.z})};
        const ggx_walk::GlassColours c = colours(lobe, s.etap, true, lobe.f0);
        Color throughput(1.0f);
        bool first = true;
        ggx_walk::GlassExit e = ggx_walk::glass_walk(o, lobe.alpha, s.etap, rand, [&](float cos_i, bool refracted) {
            throughput *= ggx_walk::walk_bounce_colour(c, cos_i, refracted, first);
            first = false;
        });
        if (e.bounces == 0 || !(e.dir.z != 0.0f)) return out;  // the walk died (Cycles: no light)
        out.pdf = ggx_walk::cycles_glass_pdf(o, e.dir, lobe.alpha, s.etap);
        out.wi = e.dir * s.sign;
        out.value = lobe.weight * throughput * out.pdf;
        out.transmission = e.dir.z < 0.0f;
        out.eta = out.transmission ? s.etap : 1.0f;
        return out;
    }

    // As the other glass lobes: the transmitted colour.
    static Color albedo(const Lobe& lobe) { return lobe.weight * (lobe.variant == kFresnel ? lobe.f0 : Color(1.0f)); }
};

// The setting multiscatter_cycles_walk on a shading point's lobes (path_tracing.h): a MultiGlass lobe
// becomes Cycles' estimator, its walk colour that of the GlassMultiple lobe the compiler put right after
// it (the Glass BSDF's colour; shader_program.cpp, multiscatter_glass), which is then dropped
// (replaced_by_cycles_glass_walk). Without one (roughness below ~0.15, where the walks of more than one
// bounce carry under 1e-4 of the light) the Glass BSDF's walk is white. `converted` carries the last
// converted lobe from one call to the next (change_lobes visits the lobes in order).
constexpr uint8_t kReplacedByGlassWalk = 0xff;  // a GlassMultiple lobe's variant once its walk took over
inline void to_cycles_glass_walk(Lobe& l, Lobe** converted) {
    if (l.kind == LobeKind::GlassMultiple) {
        if (*converted) {
            (*converted)->f0 = l.f0;
            l.variant = kReplacedByGlassWalk;
        }
        *converted = nullptr;
        return;
    }
    *converted = nullptr;
    if (l.kind != LobeKind::MultiGlass || MultiGlassWalkLobe::is_delta(l) ||
        !(std::fabs(l.eta - 1.0f) >= kIndexMatchedEps))
        return;
    l.kind = LobeKind::MultiGlassWalk;
    *converted = &l;
}
inline bool replaced_by_cycles_glass_walk(const Lobe& l) {
    return l.kind == LobeKind::GlassMultiple && l.variant == kReplacedByGlassWalk;
}

}  // namespace smis
