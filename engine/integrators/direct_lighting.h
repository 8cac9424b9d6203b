// Resampled direct lighting (Talbot et al. 2005 RIS; Bitterli et al. 2020 ReSTIR), shared by the path
// tracer's RIS strategy and the ReSTIR integrator.
//
// The domain. A light sample is kept in primary sample space: x = (light index i, u in [0,1)^2), the
// input of Light::sample. Its integrand at a shading point q is
//     g_q(x) = f_q(wo, wi) Le(y) / pdf_i(y | q),      y = light i's sample for (q, u),
// (f includes the cosine, pdf_i is the light's solid-angle density), and sum_i int g_q(i, u) du is the
// unshadowed direct light at q. The domain and its measure are the same for every shading point, so a
// sample moves to another pixel unchanged (the identity shift): no Jacobian, for every light type.
// For area and triangle lights (area sampling) the same u is the same point y at every pixel.
//
// Candidates come from the power-based light selection: p(x) = pmf(i). The resampling target is
// p^_q(x) = luminance(g_q(x)), the unshadowed contribution.
#pragma once
#include "integrators/path_tracing.h"

namespace smis {

struct LightCandidate {
    uint32_t light = 0;
    Point2 u;
};

// A candidate evaluated at a shading point.
struct CandidateEval {
    LightSample ls;     // the light's sample for (q, u)
    Color g{0.0f};      // f(wo, wi) Le / pdf_light: the integrand in primary sample space (unshadowed)
    float target = 0;   // p^_q(x) = luminance(g)
};
CandidateEval evaluate_candidate(const Scene& scene, const ShadingPoint& sp, const LightCandidate& x);
// Whether the candidate's light point is visible from the shading point (one shadow ray).
bool candidate_visible(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e);

// A weighted reservoir (Chao 1982) holding one sample y with an unbiased contribution weight W: for
// any h supported where the reservoir can produce samples, E[h(y) W] = int h (Lin et al. 2022).
// M is the confidence weight (candidates seen), used to weight reservoirs against each other.
struct Reservoir {
    LightCandidate y;
    float w_sum = 0.0f;
    float M = 0.0f;
    float W = 0.0f;
    bool has_sample() const { return W > 0.0f; }
    // Streams one candidate with resampling weight w; u decides whether it replaces y.
    bool update(const LightCandidate& x, float w, float u) {
        if (!(w > 0.0f)) return false;
        w_sum += w;
        if (u * w_sum >= w) return false;
        y = x;
        return true;
    }
};

// RIS at one shading point: M candidates from the light selection, resampled by p^/p (Talbot et al.
// 2005 eq. 4), W = w_sum / (M p^(y)). With `visibility_reuse`, an occluded y gets W = 0 (one shadow
// ray; Bitterli et al. 2020 Alg. 5 lines 7-9), which makes the reservoir's support the visible set.
// `selected` receives the chosen sample's evaluation (its target, for the caller's bookkeeping).
Reservoir ris_reservoir(const Scene& scene, const ShadingPoint& sp, int candidates, bool visibility_reuse, Rng& rng,
                        CandidateEval* selected = nullptr);

// The direct-light contribution of a reservoir at its shading point: g(y) V(y) W, one shadow ray.
// No MIS with BSDF sampling: the resampled estimator takes ALL of the direct light (the caller sets
// PathState::light_sampling_only, so the emission that the vertex's BSDF sample finds gets weight 0;
// weights 1 and 0 sum to one, shared/papers/001 sec. 3). Why: the target p^ already contains the
// BSDF, so resampling follows glossy lobes, while the path tracer's MIS weight (from the power-based
// NEE pdf, far below the resampled density for small lights) gave the BSDF-sampled hits of small
// emitters almost full weight and made them the fireflies of glossy surfaces. Dirac lobes, which
// light sampling cannot reach, keep their emission (weight 1, prev_delta).
Color reservoir_contribution(const Scene& scene, const ShadingPoint& sp, const Reservoir& r);

// The RIS strategy of the path tracer: ris_reservoir + reservoir_contribution.
Color ris_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng);

}  // namespace smis
