// The per-hit mixture of BSDF lobes built from a material, and the per-lobe entry points.
//
// The lobes themselves (their parameters, conventions and one struct per kind) are in scene/lobes/:
// lobe.h describes the interface, dispatch.h lists the kinds.
#pragma once
#include "scene/lobes/dispatch.h"

namespace smis {

// Per-lobe routines, local frame, dispatched on the lobe's kind (bsdf.cpp).
Color lobe_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
float lobe_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
BsdfSample lobe_sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event);
LobeTerms lobe_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi);
// Rough scalar estimate of the lobe's albedo, only used to choose which lobe to sample.
float lobe_sample_weight(const Lobe& lobe, const Vec3& wo);

// The mixture of lobes at one hit point: Cycles' flattened closure list.
class Bsdf {
public:
    static constexpr int kMaxLobes = 8;
    Bsdf() = default;
    Bsdf(const Frame& shading, const Vec3& ng) : frame_(shading), ng_(ng) {}
    Bsdf(const Bsdf&) = default;
    // Copies the lobes in use only (lobes past count_ are never read): every shaded hit of a node
    // material assigns the Bsdf its program built, and the implicit one copied all kMaxLobes lobes.
    Bsdf& operator=(const Bsdf& other) {
        frame_ = other.frame_;
        ng_ = other.ng_;
        count_ = other.count_;
        delta_count_ = other.delta_count_;
        bumped_ = other.bumped_;
        bump_base_ = other.bump_base_;
        for (int i = 0; i < count_; ++i) lobes_[i] = other.lobes_[i];
        return *this;
    }
    // The lobes of `lobes` (already added, so already sanitised) at another shading frame.
    Bsdf(const Frame& shading, const Vec3& ng, const Bsdf& lobes)
        : frame_(shading), ng_(ng), count_(lobes.count_), delta_count_(lobes.delta_count_) {
        for (int i = 0; i < count_; ++i) lobes_[i] = lobes.lobes_[i];
    }
    // The same into an existing Bsdf: every hit of a constant material does this, and assigning a
    // constructed temporary copied all kMaxLobes lobes, not count_.
    void assign(const Frame& shading, const Vec3& ng, const Bsdf& lobes) {
        frame_ = shading;
        ng_ = ng;
        count_ = lobes.count_;
        delta_count_ = lobes.delta_count_;
        bumped_ = false;
        for (int i = 0; i < count_; ++i) lobes_[i] = lobes.lobes_[i];
    }
    void add(const Lobe& lobe);
    int lobe_count() const { return count_; }
    // The same mixture without the lobes for which keep(lobe) is false (frame and bump state kept):
    // the lobes a light sample may light, or a surface keeps with caustics off (lobe_ray_types.h).
    template <class Keep>
    Bsdf only(Keep&& keep) const {
        Bsdf kept = *this;
        kept.count_ = kept.delta_count_ = 0;
        for (int i = 0; i < count_; ++i) {
            if (!keep(lobes_[i])) continue;
            kept.lobes_[kept.count_++] = lobes_[i];
            if (lobe_is_delta(lobes_[i])) ++kept.delta_count_;
        }
        return kept;
    }
    // Each lobe through change(lobe) in place, the Dirac count redone (Filter Glossy raises the
    // roughness of the microfacet lobes: lobe_ray_types.h's blur_lobe).
    template <class Change>
    void change_lobes(Change&& change) {
        delta_count_ = 0;
        for (int i = 0; i < count_; ++i) {
            change(lobes_[i]);
            if (lobe_is_delta(lobes_[i])) ++delta_count_;
        }
    }
    const Lobe& lobe(int i) const { return lobes_[i]; }
    // Every Subsurface lobe becomes its diffuse fallback (Lambert for the Subsurface Scattering
    // node, the principled Lambert part for Principled, whose retro-reflection lobe completes it):
    // what Cycles renders after a diffuse bounce, and what integrators without a walk render.
    // Out of line: the path tracer's loop stays small for scenes without subsurface.
    [[gnu::noinline]] void subsurface_as_diffuse();
    bool empty() const { return count_ == 0; }
    // True when every lobe is a Dirac: NEE is pointless there. Counted in add(), since every
    // vertex of every path asks.
    bool is_delta() const { return count_ > 0 && delta_count_ == count_; }
    // Some lobe is a Dirac (a mixture with a mirror or smooth glass lobe).
    bool has_delta() const { return delta_count_ > 0; }

    // World-space interface; wo, wi point away from the surface.
    Color eval(const Vec3& wo, const Vec3& wi) const;
    // eval() per lobe, factored (see LobeTerms) for spectral evaluation; false when wo, wi are on
    // inconsistent sides (eval() would return 0). terms has lobe_count() entries.
    bool eval_terms(const Vec3& wo, const Vec3& wi, LobeTerms* terms) const;
    float pdf(const Vec3& wo, const Vec3& wi) const;
    // The pdf for many wi with one wo (path-space filtering evaluates every technique's density for
    // every gathered sample): the wo-dependent work (local frame, lobe selection) is done once.
    // Per lobe, the wo-only factor of its pdf is precomputed too (lobe.h's fixed_wo_scale): 1/pi for
    // Lambert (cosine sampling), G1(wo) / (4 cos_o) for GGX reflection (visible normals).
    struct FixedWo {
        Vec3 wo, wo_local;
        float probs[kMaxLobes];
        float pdf_scale[kMaxLobes];
    };
    FixedWo fix_wo(const Vec3& wo) const;
    float pdf(const FixedWo& fixed, const Vec3& wi) const;
    BsdfSample sample(const Vec3& wo, Point2 u, float u_lobe) const;
    // The lobe sample() would have picked, given that it returned direction wi: lobe i with
    // probability prob_i pdf_i(wi) / pdf(wi), chosen with u in [0, 1). For a direction found by
    // another technique (integrators/glow_directions.h), so that its ray is labelled (diffuse,
    // glossy, transmission) as BSDF sampling would label the same direction. 0 when no lobe has density there.
    int lobe_at(const Vec3& wo, const Vec3& wi, float u) const;
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
    float pdf_one_lobe(const Vec3& wo, const Vec3& wi) const;
    // Out of line, so the common (unbent) path of eval() and sample() keeps its inlining.
    [[gnu::noinline]] Color eval_bumped(const Vec3& wi, const Vec3& wo_l, const Vec3& wi_l) const;
    // A bumped sample's value (direction wi, wi_l in the local frame): eval_bumped, or when the chosen
    // lobe's value is not its eval (Cycles' walk lobes) the mixture with that lobe's sample value.
    // Out of line, and the value by copy, so that sample() keeps its sample in registers.
    [[gnu::noinline]] Color bumped_sample_value(Color chosen_value, int chosen, const Vec3& wi, const Vec3& wo_l,
                                                const Vec3& wi_l) const;
    static bool walk_lobe(const Lobe& l) { return l.kind == LobeKind::MultiGgxWalk || l.kind == LobeKind::MultiGlassWalk; }
    [[gnu::noinline]] void shadow_diffuse_terms(const Vec3& wi, LobeTerms* terms) const;
    static bool diffuse_labelled(const Lobe& lobe) { return lobe_label(lobe) == RayLabel::Diffuse; }
    // Inlined into sample() and fix_wo(), its two callers (it was, until the dispatch grew).
    [[gnu::always_inline]] inline void selection_probabilities(const Vec3& wo_local, float* probs) const;
    Frame frame_;
    Vec3 ng_{0, 0, 1};
    LobeSlots<kMaxLobes> lobes_;
    int count_ = 0;
    int delta_count_ = 0;
    bool bumped_ = false;
    Vec3 bump_base_;
};

}  // namespace smis
