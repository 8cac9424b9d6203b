#include "integrators/reservoir_reuse.h"

namespace smis {
namespace {

// M_j p_j(x) summed over the inputs, and p_own(x) for input `own`, the one x comes from: the balance
// heuristic's parts. Two of the pdfs are known without work: the own input's, p^_{q_own}(x) = its
// r.target (x is visible from q_own, see combine_reservoirs), and q's (input 0), at_q, whose
// visibility is traced here when needed and reported in visible_from_q.
struct MisSums {
    double weighted_sum = 0.0;
    float own = 0.0f;
    bool visible_from_q = true;
};
MisSums mis_sums(const Scene& scene, const ReuseInput* inputs, int n, int own, const LightCandidate& x,
                 const CandidateEval& at_q, bool visibility, ReuseCost& cost) {
    MisSums s;
    for (int j = 0; j < n; ++j) {
        const ShadingPoint& qj = *inputs[j].sp;
        float p;
        if (j == own) {
            p = inputs[j].r->target;
        } else {
            CandidateEval evaluated;
            const CandidateEval* e = &at_q;
            if (j != 0) {
                evaluated = evaluate_candidate(scene, qj, x);
                ++cost.pdf_evaluations;
                e = &evaluated;
            }
            p = e->target;
            if (visibility && p > 0.0f) {
                ++cost.shadow_rays;
                if (!candidate_visible(scene, qj, *e, inputs[j].medium)) p = 0.0f;
            }
            if (j == 0) s.visible_from_q = p > 0.0f;
        }
        s.weighted_sum += double(inputs[j].r->M) * p;
        if (j == own) s.own = p;
    }
    return s;
}

float balance_weight(const MisSums& m, float M_own) {
    return m.weighted_sum > 0.0 ? float(double(M_own) * m.own / m.weighted_sum) : 0.0f;
}

}  // namespace

CombinedReservoir combine_reservoirs(const Scene& scene, const ShadingPoint& q, const ReuseInput* inputs, int n,
                                     RestirMis mis, bool visibility_in_mis, Rng& rng, ReuseCost& cost) {
    CombinedReservoir out;
    Reservoir& s = out.r;
    int selected = -1;
    bool selected_visible = true;
    for (int i = 0; i < n; ++i) {
        const Reservoir& r = *inputs[i].r;
        s.M += r.M;
        float u = rng.next_float();  // drawn for every input: the stream does not depend on the weights
        if (!r.has_sample()) continue;
        CandidateEval e = i == 0 && inputs[0].eval ? *inputs[0].eval : evaluate_candidate(scene, q, r.y);
        if (!(e.target > 0.0f)) continue;
        float w = e.target * r.W;
        bool visible = true;
        if (mis == RestirMis::Talbot) {
            MisSums m = mis_sums(scene, inputs, n, i, r.y, e, visibility_in_mis, cost);
            w *= balance_weight(m, r.M);
            visible = m.visible_from_q;
        } else {
            w *= r.M;
        }
        if (s.update(r.y, w, u)) selected = i, out.at_q = e, selected_visible = visible;
    }
    if (selected < 0) return out;
    float W = s.w_sum / out.at_q.target;
    if (mis == RestirMis::Seed) {
        MisSums m = mis_sums(scene, inputs, n, selected, s.y, out.at_q, visibility_in_mis, cost);
        W *= balance_weight(m, 1.0f);
        selected_visible = m.visible_from_q;
    } else if (mis == RestirMis::None) {
        W /= s.M;
    }
    out.visibility_known = visibility_in_mis && mis != RestirMis::None;
    if (out.visibility_known && !selected_visible) W = 0.0f;  // dropped: occluded from q
    s.W = std::isfinite(W) ? W : 0.0f;
    s.target = s.W > 0.0f ? out.at_q.target : 0.0f;
    return out;
}

}  // namespace smis
