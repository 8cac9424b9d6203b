#include "integrators/direct_lighting.h"

namespace smis {
namespace {

// The contribution g T weight of a sample e evaluated at sp in a scene with media.
[[gnu::noinline]] Color shaded_through_media(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e,
                                             float weight, int32_t medium) {
    const Color tr = candidate_transmittance(scene, sp, e, medium);
    return is_black(tr) ? Color(0.0f) : e.g * weight * tr;
}

}  // namespace

CandidateEval evaluate_candidate(const Scene& scene, const ShadingPoint& sp, const LightCandidate& x) {
    CandidateEval e;
    e.light = x.light;
    const Light& light = scene.light(x.light);
    e.ls = light.sample_at(sp.hit.p, x.u, sp.hit.time);
    if (!e.ls.valid()) return e;
    // A light hidden from some ray types lights only the other lobes (Cycles' light visibility).
    const uint32_t hidden = ~light.visibility & kRayBounceTypes;
    Color f = hidden ? hidden_light_eval(sp.bsdf, hidden, sp.wo, e.ls.wi) : sp.bsdf.eval(sp.wo, e.ls.wi);
    e.g = f * e.ls.L / e.ls.pdf;
    // Colours are non-negative, so the luminance is positive wherever g is not black.
    e.target = luminance(e.g);
    if (!std::isfinite(e.target) || !(e.target > 0.0f)) e.target = 0.0f;
    return e;
}

bool candidate_visible(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e, int32_t medium) {
    if (!scene.light(e.light).cast_shadow) return true;  // Cast Shadow off: no shadow ray
    if (scene.has_media()) return !is_black(candidate_transmittance(scene, sp, e, medium));
    const ShadowRay shadow = shadow_ray(sp, e.ls.wi, e.ls.dist);
    return !scene.occluded(shadow.o, shadow.d, shadow.tmax, shadow.time) && reaches_mesh_light(scene, shadow, e.ls);
}

Color candidate_transmittance(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e, int32_t medium) {
    if (!scene.light(e.light).cast_shadow) return Color(1.0f);  // nor the media on the way (Cycles)
    const ShadowRay shadow = shadow_ray(sp, e.ls.wi, e.ls.dist);
    const Color tr =
        shadow_transmittance(scene, shadow.o, shadow.d, shadow.tmax, medium_towards(scene, sp, e.ls.wi, medium));
    return is_black(tr) || !reaches_mesh_light(scene, shadow, e.ls) ? Color(0.0f) : tr;
}

Reservoir ris_reservoir(const Scene& scene, const ShadingPoint& sp, int candidates, bool visibility_reuse, Rng& rng,
                        CandidateEval* chosen_out, int32_t medium) {
    Reservoir r;
    const DiscreteDistribution& selection = scene.light_selection();
    r.M = float(std::max(1, candidates));
    if (sp.bsdf.is_delta() || selection.empty()) return r;
    CandidateEval chosen;
    for (int j = 0; j < candidates; ++j) {
        LightCandidate x;
        x.light = static_cast<uint32_t>(selection.sample(rng.next_float()));
        x.u = {rng.next_float(), rng.next_float()};
        float u_pick = rng.next_float();
        CandidateEval e = evaluate_candidate(scene, sp, x);
        // Resampling weight p^(x) / p(x), p(x) = pmf(i) (u is uniform).
        if (r.update(x, e.target / selection.pmf(x.light), u_pick)) chosen = e;
    }
    if (chosen.target > 0.0f && !(visibility_reuse && !candidate_visible(scene, sp, chosen, medium))) {
        r.W = r.w_sum / (r.M * chosen.target);
        r.target = chosen.target;
    }
    if (chosen_out) *chosen_out = chosen;
    return r;
}

Color reservoir_contribution(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                             const Reservoir& r, int32_t medium) {
    if (!r.has_sample()) return Color(0.0f);
    CandidateEval e = evaluate_candidate(scene, sp, r.y);
    if (!(e.target > 0.0f)) return Color(0.0f);
    if (scene.has_media()) return shaded_through_media(scene, sp, e, resampled_weight(scene, settings, sp, r, e), medium);
    if (!candidate_visible(scene, sp, e)) return Color(0.0f);
    return visible_reservoir_contribution(scene, settings, sp, r, e);
}

float resampled_weight(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, const Reservoir& r,
                       const CandidateEval& e) {
    if (!r.has_sample() || !(e.target > 0.0f)) return 0.0f;
    float w_light = 1.0f;
    if (!e.ls.delta && scene.light(r.y.light).use_mis) {  // Multiple Importance off: unweighted
        float light_pdf = resampled_light_pdf_scale(settings) * scene.light_pmf(r.y.light) * e.ls.pdf;
        const uint32_t hidden = ~scene.light(r.y.light).visibility & kRayBounceTypes;
        const float bsdf_pdf = hidden ? hidden_light_pdf(sp.bsdf, hidden, sp.wo, e.ls.wi) : sp.bsdf.pdf(sp.wo, e.ls.wi);
        w_light = mis_weight(settings.mis, light_pdf, bsdf_pdf);
    }
    return w_light * r.W;
}

Color visible_reservoir_contribution(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                                     const Reservoir& r, const CandidateEval& e) {
    const float weight = resampled_weight(scene, settings, sp, r, e);
    return weight > 0.0f ? e.g * weight : Color(0.0f);
}

ResampledLight ris_light(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng) {
    // No visibility reuse: the one shadow ray is traced for the contribution itself.
    ResampledLight out;
    Reservoir r = ris_reservoir(scene, sp, settings.ris_candidates, false, rng, &out.e);
    out.weight = resampled_weight(scene, settings, sp, r, out.e);
    return out;
}

Color ris_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                 int32_t medium) {
    const ResampledLight s = ris_light(scene, settings, sp, rng);
    if (!(s.weight > 0.0f)) return Color(0.0f);
    if (scene.has_media()) return shaded_through_media(scene, sp, s.e, s.weight, medium);
    if (!candidate_visible(scene, sp, s.e)) return Color(0.0f);
    return s.e.g * s.weight;
}

}  // namespace smis
