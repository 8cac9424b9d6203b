#include "integrators/reservoir_reuse.h"

namespace smis {
namespace {

// M_j p_j(x) summed over the inputs, and p_own(x) for input `own`: the balance heuristic's parts.
struct MisSums {
    double weighted_sum = 0.0;
    float own = 0.0f;
};
MisSums mis_sums(const Scene& scene, const ReuseInput* inputs, int n, int own, const LightCandidate& x,
                 bool visibility, ReuseCost& cost) {
    MisSums s;
    for (int j = 0; j < n; ++j) {
        const ShadingPoint& qj = *inputs[j].sp;
        CandidateEval e = evaluate_candidate(scene, qj, x);
        ++cost.pdf_evaluations;
        float p = e.target;
        if (visibility && p > 0.0f) {
            ++cost.shadow_rays;
            if (!candidate_visible(scene, qj, e)) p = 0.0f;
        }
        s.weighted_sum += double(inputs[j].r->M) * p;
        if (j == own) s.own = p;
    }
    return s;
}

}  // namespace

Reservoir combine_reservoirs(const Scene& scene, const ShadingPoint& q, const ReuseInput* inputs, int n,
                             RestirMis mis, bool visibility_in_mis, Rng& rng, ReuseCost& cost) {
    Reservoir s;
    int selected = -1;
    float target_selected = 0.0f;
    for (int i = 0; i < n; ++i) {
        const Reservoir& r = *inputs[i].r;
        s.M += r.M;
        float u = rng.next_float();  // drawn for every input: the stream does not depend on the weights
        if (!r.has_sample()) continue;
        float target = evaluate_candidate(scene, q, r.y).target;
        if (!(target > 0.0f)) continue;
        float w = target * r.W;
        if (mis == RestirMis::Talbot) {
            MisSums m = mis_sums(scene, inputs, n, i, r.y, visibility_in_mis, cost);
            w *= m.weighted_sum > 0.0 ? float(double(r.M) * m.own / m.weighted_sum) : 0.0f;
        } else {
            w *= r.M;
        }
        if (s.update(r.y, w, u)) selected = i, target_selected = target;
    }
    if (selected < 0) return s;
    float W = s.w_sum / target_selected;
    if (mis == RestirMis::Seed) {
        MisSums m = mis_sums(scene, inputs, n, selected, s.y, visibility_in_mis, cost);
        W = m.weighted_sum > 0.0 ? float(double(W) * m.own / m.weighted_sum) : 0.0f;
    } else if (mis == RestirMis::None) {
        W /= s.M;
    }
    s.W = std::isfinite(W) ? W : 0.0f;
    return s;
}

}  // namespace smis
