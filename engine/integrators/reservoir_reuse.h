// Combining reservoirs of different shading points (pixels, or the same pixel in the previous
// iteration): the resampling MIS of the ReSTIR supplement (shared/papers/004), Alg. 1 (Bitterli et
// al.) and Alg. 2 (Talbot et al.), and the biased 1/M normalisation.
//
// Input i is a reservoir (X_i, W_i, M_i) built at shading point q_i, W_i an unbiased contribution
// weight. Its sample's true density is unknown (it went through RIS); the MIS weights use the
// approximation p_i(x) = p^_{q_i}(x), times the visibility from q_i when the reservoirs dropped their
// occluded samples (then input i cannot produce x where q_i does not see it). Weights from approximate
// pdfs keep the estimator unbiased as long as they sum to one (shared/papers/001, sec. 3); with
// confidence weights M_i the balance heuristic is
//     m_i(x) = M_i p_i(x) / sum_j M_j p_j(x),
// and E[f(Y) W] = sum_i int m_i f = int f wherever the own (canonical) input covers f's support.
//   Talbot (Alg. 2): resampling weights w_i = m_i(X_i) p^_q(X_i) W_i, W = w_sum / p^_q(Y):
//                    every input's weight needs every input's pdf, (k+1)^2 evaluations.
//   Seed (Alg. 1):   w_i = p^_q(X_i) W_i M_i, and only the selected Y = X_s is weighted:
//                    W = w_sum p_s(Y) / (p^_q(Y) sum_j M_j p_j(Y)),   k+1 evaluations.
//                    (E[f W] = sum_i E[M_i W_i f(X_i) p_i / sum_j M_j p_j] = int f: the same m_i.)
//                    With equal M_i this is Alg. 1 with a 1/M in line 10 that the printed
//                    algorithm lacks (with k = 1 it would return W = M W_1; Alg. 2's line 10 has it).
//   None:            w_i = p^_q(X_i) W_i M_i, W = w_sum / (p^_q(Y) sum_i M_i): the 1/M of the
//                    original RIS. Biased where some input cannot produce Y (occluded from q_i, or
//                    behind q_i's surface): it darkens.
#pragma once
#include "integrators/direct_lighting.h"

namespace smis {

struct ReuseInput {
    const Reservoir* r;
    const ShadingPoint* sp;                 // q_i, where r was built
    const CandidateEval* eval = nullptr;    // r->y evaluated at q_i, when known (read for input 0 only)
    int32_t medium = kNoMedium;             // the medium q_i's path arrived in (scenes with media)
};

// Work done by the combiners, for the benchmarks' cost report.
struct ReuseCost {
    uint64_t pdf_evaluations = 0;  // p_j(x) for the MIS weights
    uint64_t shadow_rays = 0;      // visibility in those pdfs
};

// What a combination produced: the reservoir at q and what it learnt about the sample at q on the way.
struct CombinedReservoir {
    Reservoir r;
    CandidateEval at_q;              // evaluate_candidate(q, r.y), when r has a sample
    bool visibility_known = false;   // the sample's visibility from q was traced for the MIS: it is
                                     // visible (an occluded one is dropped), shading needs no shadow ray
};

// Combines inputs (input 0 is the pixel's own reservoir at q: inputs[0].sp is q) into one reservoir at
// shading point q. visibility_in_mis: the MIS pdfs include the visibility from q_j, which is unbiased
// when every input's sample is visible from its own q_j (initial reservoirs with visibility reuse, and
// the outputs of this mode, which drop a sample occluded from q: W' = W V_q(Y) is again an unbiased
// contribution weight, for the visible part of the integrand). The input's own pdf at its sample,
// r.target, is then known without evaluation or shadow ray. Without visibility_in_mis no shadow ray
// is traced. With media the visibility is [transmittance > 0] from q_j's medium (direct_lighting.h),
// and a sample's transmittance from q is left to the shading.
CombinedReservoir combine_reservoirs(const Scene& scene, const ShadingPoint& q, const ReuseInput* inputs, int n,
                                     RestirMis mis, bool visibility_in_mis, Rng& rng, ReuseCost& cost);

}  // namespace smis
