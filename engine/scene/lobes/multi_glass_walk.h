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

// Cycles 3.4 draws every walk of a shading point (its light samples' mf_eval_glass, its BSDF sample's
// mf_sample_glass) from the point's LCG (sample/lcg.h), seeded in shade_surface.h with rng_hash +
// rng_offset + sample * 0xb4bc3953, where rng_offset grows by PRNG_BOUNCE_NUM = 16 per bounce. Seeds 16
// apart give sequences a fixed step apart (mod 1), so the walks at successive vertices of a path are
// correlated, and Cycles' image of light that crosses a rough glass object is not its walk's: a slab of
// the IOR 2, roughness 1 glass under a uniform World, 3 bounces, 12.3% darker than independent walks
// (the walk itself with these numbers is Cycles' to the last bit). With the setting, the path gives each
// vertex's glass walk lobe the state Cycles would (seed_cycles_glass_walk); the lobe keeps it in
// kind_colour.y (high 16 bits + 1, so 0 = none) and kind_colour.z (low 16 bits), exact in floats.
struct CyclesLcg {
    uint32_t x;
    float operator()() {
        x = 1103515245u * x + 12345u;
        return float(x) * (1.0f / float(0xFFFFFFFFu));  // as Cycles' lcg_step_float (1 possible)
    }
};
inline uint32_t cycles_lcg_state(uint32_t path_key, int depth) {
    uint32_t x = path_key + 16u * uint32_t(depth + 1);  // rng_offset: 16 at the camera ray's hit
    return 1103515245u * x + 12345u;                     // lcg_init's step
}
inline bool cycles_lcg_of(const Lobe& l, uint32_t* state) {
    if (!(l.kind_colour.y >= 1.0f)) return false;
    *state = (uint32_t(l.kind_colour.y - 1.0f) << 16) | uint32_t(l.kind_colour.z);
    return true;
}

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
    // Its numbers from the lobe's Cycles LCG state when the path gave one, else from the two directions.
    static Color walk_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi, const Color& c) {
        uint32_t lcg;
        if (cycles_lcg_of(lobe, &lcg)) {
            CyclesLcg rand{lcg};
            return walk_eval_with(lobe, wo, wi, c, rand);
        }
        walk_lobe_detail::HashRand rand{
            walk_lobe_detail::key_of({wo.x, wo.y, wo.z, wi.x, wi.y, wi.z, lobe.alpha, lobe.eta})};
        return walk_eval_with(lobe, wo, wi, c, rand);
    }
    template <class Rand>
    static Color walk_eval_with(const Lobe& lobe, const Vec3& wo, const Vec3& wi, const Color& c, Rand& rand) {
        Side s;
        if (!side_of(lobe, wo, &s)) return Color(0.0f);
        Vec3 o = wo * s.sign, i = wi * s.sign;
        return ggx_walk::cycles_glass_eval(o, i, lobe.alpha, s.etap, colours(lobe, s.etap, i.z > 0.0f, c), rand);
    }
    static EvalPdf eval_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::eval_pdf<MultiGlassWalkLobe>(lobe, wo, wi);
    }
    // The spectral tracer's terms: the eval at the colour's channel mean.
    [[gnu::noinline]] static LobeTerms terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
        return walk_lobe_detail::terms<MultiGlassWalkLobe>(lobe, wo, wi);
    }

    // Cycles' sampled walk from the view o (o.z > 0) at relative IOR etap: its exit, its colours per bounce.
    template <class Rand>
    static ggx_walk::GlassExit walk(const Lobe& lobe, const Vec3& o, float etap, Rand& rand, Color* throughput) {
        const ggx_walk::GlassColours c = colours(lobe, etap, true, lobe.f0);
        bool first = true;
        return ggx_walk::glass_walk(o, lobe.alpha, etap, rand, [&](float cos_i, bool refracted) {
            *throughput *= ggx_walk::walk_bounce_colour(c, cos_i, refracted, first);
            first = false;
        });
    }

    // Cycles' mf_sample_glass: the walk from the view, its colours per bounce.
    [[gnu::noinline]] static BsdfSample sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
        BsdfSample out;
        Side s;
        if (is_delta(lobe) || !side_of(lobe, wo, &s)) return out;
        Vec3 o = wo * s.sign;
        Color throughput(1.0f);
        uint32_t lcg;
        ggx_walk::GlassExit e;
        if (cycles_lcg_of(lobe, &lcg)) {
            CyclesLcg rand{lcg};
            e = walk(lobe, o, s.etap, rand, &throughput);
        } else {
            walk_lobe_detail::HashRand rand{walk_lobe_detail::key_of({u.x, u.y, u_event, o.x, o.y, o.z})};
            e = walk(lobe, o, s.etap, rand, &throughput);
        }
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
    l.kind_colour.y = l.kind_colour.z = 0.0f;  // no Cycles LCG state until the path gives one
    *converted = &l;
}
inline bool replaced_by_cycles_glass_walk(const Lobe& l) {
    return l.kind == LobeKind::GlassMultiple && l.variant == kReplacedByGlassWalk;
}
// The state of Cycles' LCG at the vertex `depth` bounces along the path whose key stands for Cycles'
// rng_hash + sample * 0xb4bc3953 (a hash of the camera ray), on a glass walk lobe.
inline void set_cycles_lcg(Lobe& l, uint32_t state) {
    l.kind_colour.y = float(state >> 16) + 1.0f;
    l.kind_colour.z = float(state & 0xffffu);
}
inline void seed_cycles_glass_walk(Lobe& l, uint32_t path_key, int depth) {
    if (l.kind == LobeKind::MultiGlassWalk) set_cycles_lcg(l, cycles_lcg_state(path_key, depth));
}


}  // namespace smis
