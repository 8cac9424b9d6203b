// BSDF closures and the per-hit mixture built from a material.
//
// Conventions (shared by every lobe and by the integrators):
//  * Lobes work in the local shading frame: +z is the shading normal, wo points away from the surface
//    (towards the previous vertex), wi is the sampled / queried direction, also pointing away.
//  * eval() returns f(wo, wi) * |cos theta_i|  (the BSDF times the foreshortening of wi), like Mitsuba.
//  * pdf() is the solid-angle density of sample() producing wi; sample() returns the same value as
//    eval()/pdf() for non-delta lobes (value = eval, pdf = pdf), so sample(), eval() and pdf() agree.
//  * Delta lobes (smooth mirror, smooth glass) return delta = true from sample(); pdf is the
//    probability of the discrete event chosen (e.g. F for reflection off glass) and value/pdf is the
//    throughput multiplier of that event; eval()/pdf() return 0 for them.
//  * Radiance transport: refraction from IOR eta_i into eta_t scales radiance by (eta_i/eta_t)^2.
#pragma once
#include "core/features.h"
#include "core/math.h"
#include "core/sampling.h"

namespace smis {

enum class LobeKind : uint8_t {
    Diffuse,      // Lambert: color / pi
    Microfacet,   // GGX reflection (Glossy BSDF, metals, Principled specular); fresnel selects the tint
    Dielectric,   // glass: Fresnel-weighted reflection + refraction, smooth (alpha = 0) or GGX-rough
    // Principled v1 extras (Cycles 3.4). Kept after the three base kinds so that code treating
    // "everything but Diffuse/Microfacet" generically tests one ordering (kind >= Dielectric).
    Clearcoat,    // Disney/Cycles clearcoat: GTR1 normals (alpha = roughness^2), Smith G with fixed alpha
                  // 0.25, exact dielectric Fresnel at `eta` (1.5); the Fresnel is inside LobeTerms::geom
    Sheen,        // Disney/Cycles principled sheen: f cos = (1 - wi.h)^5 cos_i (no 1/pi), cosine sampled
    Transparent,  // Transparent BSDF's coloured part: a Dirac straight through (wi = -wo), value = weight
    // Cycles 3.4's principled diffuse (Burley 2012 with retro-reflection), cosine sampled:
    // f cos = cos_i / pi [(1 - FV/2)(1 - FL/2) + RR (FL + FV + FL FV (RR - 1))], F = (1 - cos)^5,
    // RR = roughness (1 + wi.wo) with roughness = sqrt(alpha) (the Principled Roughness input).
    PrincipledDiffuse,
};

enum class FresnelMode : uint8_t {
    None,        // F = 1: Cycles' Glossy BSDF (the colour is the weight)
    Schlick,     // F = f0 + (1 - f0)(1 - cos)^5 with coloured f0: Principled metallic
    Dielectric,  // exact dielectric Fresnel with `eta`: Principled specular layer on top of diffuse
};

struct Lobe {
    LobeKind kind = LobeKind::Diffuse;
    FresnelMode fresnel = FresnelMode::None;
    uint8_t index = 0;   // position in the material's lobe list (set by Scene::add_material; spectral data)
    Color weight{1.0f};  // closure weight (colour x mix factors)
    Color f0{1.0f};      // Schlick reflectance at normal incidence (FresnelMode::Schlick)
    float alpha = 0.0f;  // GGX alpha = roughness^2 (Blender's convention); below kDeltaAlpha -> delta
    float eta = 1.5f;    // IOR of the inside over the outside (Dielectric lobe / FresnelMode::Dielectric)
};

// Schlick's (1 - cos)^5, shared by the RGB and spectral Fresnel of FresnelMode::Schlick.
inline float schlick_weight(float cos_d) {
    float m = clampf(1.0f - std::fabs(cos_d), 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}

// Roughness under which a microfacet lobe is treated as a perfect (delta) reflector/refractor,
// as Cycles does; evaluating GGX with smaller alpha only produces fireflies.
constexpr float kDeltaAlpha = 1e-4f;

struct BsdfSample {
    Vec3 wi;                 // sampled direction (local frame for Lobe, world frame for Bsdf)
    Color value{0.0f};       // eval(wo, wi) for non-delta, Dirac weight for delta lobes
    float pdf = 0.0f;        // solid-angle pdf (non-delta); probability of the discrete event (delta)
    float eta = 1.0f;        // relative IOR crossed by wi (1 for reflection), for Russian roulette
    bool delta = false;
    bool transmission = false;
    int8_t lobe = -1;        // the Bsdf's lobe that was sampled (Bsdf::sample only)
    bool valid() const { return pdf > 0.0f && std::isfinite(pdf) && is_finite(value); }
};

// Per-lobe routines, local frame. Implemented in bsdf.cpp.
Color lobe_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float lobe_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
BsdfSample lobe_sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event);
// eval() factored as weight * fresnel(cos_d) * geom, where only the Microfacet lobe has a Fresnel
// factor (FresnelMode, at the angle cos_d between wi and the microfacet normal; the dielectric
// lobe's Fresnel is inside geom). Spectral rendering evaluates weight and Fresnel per wavelength on
// top of the wavelength-independent geom; pdf is the same as lobe_pdf(). Zero for Dirac lobes.
struct LobeTerms {
    float geom = 0.0f, cos_d = 1.0f, pdf = 0.0f;
};
LobeTerms lobe_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi);

// A rough dielectric whose |eta - 1| is below this is an index-matched interface: the transmission
// lobe collapses onto -wo whatever the roughness and the Walter Jacobian becomes singular
// (the generalised half vector wo + eta wi vanishes), so it is treated as the smooth (delta) case.
constexpr float kIndexMatchedEps = 1e-3f;
// The kinds after Dielectric (bsdf.cpp, out of line so the base kinds' dispatch stays small).
bool extra_is_delta(const Lobe& lobe);
// Inline: the path tracer asks at every vertex (through Bsdf::is_delta and the pdf routines).
inline bool lobe_is_delta(const Lobe& lobe) {
    switch (lobe.kind) {
        case LobeKind::Diffuse: return false;
        case LobeKind::Microfacet: return !(lobe.alpha >= kDeltaAlpha);
        case LobeKind::Dielectric:
            return !(lobe.alpha >= kDeltaAlpha) || !(std::fabs(lobe.eta - 1.0f) >= kIndexMatchedEps);
        default: return kWithPrincipledExtras && extra_is_delta(lobe);
    }
}

// Rough scalar estimate of the lobe's albedo, only used to choose which lobe to sample.
float lobe_sample_weight(const Lobe& lobe, const Vec3& wo);

// Burley 2012's GTR1 (gamma = 1) normal distribution of the clearcoat, normalised so that
// integral D(m) cos(theta_m) dm = 1; alpha >= 1 is the uniform-in-cosine limit 1/pi.
float gtr1_D(float cos_m, float alpha);
// The clearcoat's masking-shadowing roughness, fixed by Cycles 3.4 whatever the coat roughness.
constexpr float kClearcoatShadowAlpha = 0.25f;

// GGX helpers, exposed for tests and for the path-space filtering integrator.
float ggx_D(const Vec3& wm, float alpha);
float ggx_G1(const Vec3& w, float alpha);
Vec3 ggx_sample_visible_normal(const Vec3& wo, float alpha, Point2 u);
float fresnel_dielectric(float cos_i, float eta);

// The mixture of lobes at one hit point: Cycles' flattened closure list.
class Bsdf {
public:
    static constexpr int kMaxLobes = 8;
    Bsdf() = default;
    Bsdf(const Frame& shading, const Vec3& ng) : frame_(shading), ng_(ng) {}
    // The lobes of `lobes` (already added, so already sanitised) at another shading frame.
    Bsdf(const Frame& shading, const Vec3& ng, const Bsdf& lobes)
        : frame_(shading), ng_(ng), count_(lobes.count_), delta_count_(lobes.delta_count_) {
        for (int i = 0; i < count_; ++i) lobes_[i] = lobes.lobes_[i];
    }
    void add(const Lobe& lobe);
    int lobe_count() const { return count_; }
    const Lobe& lobe(int i) const { return lobes_[i]; }
    bool empty() const { return count_ == 0; }
    // True when every lobe is a Dirac: NEE is pointless there. Counted in add(), since every
    // vertex of every path asks.
    bool is_delta() const { return count_ > 0 && delta_count_ == count_; }

    // World-space interface; wo, wi point away from the surface.
    Color eval(const Vec3& wo, const Vec3& wi) const;
    // eval() per lobe, factored (see LobeTerms) for spectral evaluation; false when wo, wi are on
    // inconsistent sides (eval() would return 0). terms has lobe_count() entries.
    bool eval_terms(const Vec3& wo, const Vec3& wi, LobeTerms* terms) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    // The pdf for many wi with one wo (path-space filtering evaluates every technique's density for
    // every gathered sample): the wo-dependent work (local frame, lobe selection) is done once.
    // Per lobe, the wo-only factor of its pdf is precomputed too: 1/pi for Lambert (cosine
    // sampling), G1(wo) / (4 cos_o) for GGX reflection (visible normals: pdf = D(wm) G1(wo) / (4 cos_o)).
    struct FixedWo {
        Vec3 wo, wo_local;
        float probs[kMaxLobes];
        float pdf_scale[kMaxLobes];
    };
    FixedWo fix_wo(const Vec3& wo) const;
    float pdf(const FixedWo& fixed, const Vec3& wi) const;
    BsdfSample sample(const Vec3& wo, Point2 u, float u_lobe) const;
    // Sum of lobe weights (colour), used for albedo passes and furnace tests.
    Color albedo_weight() const;
    const Frame& frame() const { return frame_; }
    const Vec3& ng() const { return ng_; }
    // A node tree bent the shading normal (Bump, Normal Map) away from the surface's own smooth
    // normal `base`: diffuse lobes are then darkened towards the terminator by Cycles' bump
    // shadowing term (Chiang, Li and Burley 2019, "Taming the Shadow Terminator"), in eval() and
    // sample() alike, as Cycles 3.4 does; pdfs are unchanged.
    void set_bump_base(const Vec3& base) {
        bump_base_ = base;
        bumped_ = true;
    }

private:
    float bump_shadowing(const Vec3& wi) const;
    // Out of line, so the common (unbent) path of eval() and sample() keeps its inlining.
    [[gnu::noinline]] Color eval_bumped(const Vec3& wi, const Vec3& wo_l, const Vec3& wi_l) const;
    [[gnu::noinline]] void shadow_diffuse_terms(const Vec3& wi, LobeTerms* terms) const;
    static bool diffuse_labelled(const Lobe& lobe) {
        return lobe.kind == LobeKind::Diffuse || lobe.kind == LobeKind::PrincipledDiffuse || lobe.kind == LobeKind::Sheen;
    }
    void selection_probabilities(const Vec3& wo_local, float* probs) const;
    Frame frame_;
    Vec3 ng_{0, 0, 1};
    Lobe lobes_[kMaxLobes];
    int count_ = 0;
    int delta_count_ = 0;
    bool bumped_ = false;
    Vec3 bump_base_;
};

}  // namespace smis
