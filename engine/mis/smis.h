// Balance / power heuristic combination over a (possibly stochastically selected) set of sampling
// techniques: the continuous and stochastic MIS of West, Georgiev, Gruson and Hachisuka 2020,
// "Continuous Multiple Importance Sampling" (shared/papers/003_*.txt; equation numbers below are the
// paper's), with Veach's discrete MIS as the special case of a fixed technique set.
//
// The model every integrator maps onto (path-space filtering: t = prefix path, x = suffix; spectral:
// t = hero wavelength, x = spectral path; photon planes: t = plane orientation, x = scattering point):
//
//   * A continuum of techniques t in T, selected with density p(t); technique t samples x ~ p(x|t).
//   * CMIS estimator, eq. (7):            <I> = w(t,x) f(x) / (p(t) p(x|t)),  with int_T w(t,x) dt = 1.
//     Its variance-optimal weight is the continuous balance heuristic, eq. (9):
//                                        w(t,x) = p(t) p(x|t) / p(x),  p(x) = int_T p(t') p(x|t') dt',
//     which turns the estimator into f(x) / p(x), eq. (10). p(x) is rarely available in closed form.
//   * SMIS estimator, eq. (11)-(12): draw n techniques t_1..t_n, each with marginal density p(t) (jointly
//     independent or stratified), and one sample x_i ~ p(x|t_i) from each. Eq. (11) replaces p(x) in
//     eq. (10) by its estimate (1/n) sum_j p(x|t_j), which simplifies to eq. (12):
//
//         <I>_SMIS = sum_{i=1..n} w_i(x_i) f(x_i) / p(x_i|t_i) = sum_{i=1..n} f(x_i) / sum_{j=1..n} p(x_i|t_j),
//         w_i(x)   = p(x|t_i) / sum_{j=1..n} p(x|t_j).
//
//     NORMALISATION: eq. (12) is a plain SUM over the n samples, with no 1/n in front: the 1/n of the
//     average in eq. (11) cancels against the 1/n of the marginal estimate, and p(t_i) cancels too, so
//     p(t) is never evaluated. (Averaging R independent realizations of eq. (12) then divides by R.)
//   * Unbiasedness (appendix B): conditionally on the selected t_1..t_n, eq. (12) is a multi-sample DMIS
//     estimator, eq. (4), with one sample per technique, so it is unbiased for ANY way of selecting the
//     techniques (independent, stratified, or fixed) as long as the weights sum to 1 over the SELECTED
//     techniques wherever f(x) != 0. The balance and power heuristics below do so whenever at least one
//     selected technique can produce x (sum_j p(x|t_j) > 0). Where none can, that part of the integral
//     is silently missed: every selected set must cover the support of f (e.g. p(x|t) > 0 on supp f for
//     all t, or a defensive technique in the set).
//   * Discrete MIS (Veach): a fixed, non-random set of T techniques with n_k samples each is the same
//     computation with counts: w_k(x) = n_k p_k(x) / sum_j n_j p_j(x), eq. (5) with P_k = n_k / n, and
//     the multi-sample estimator, eq. (4), adds w_k f / (n_k p_k) per sample. Listing technique k n_k
//     times in the pdf array gives the same weights, so SMIS with n single-sample techniques is the
//     case n_k = 1.
//
// Guards: a density is usable when it is finite and > 0. A sample whose OWN density is not usable
// contributes 0 (it could not have been sampled; f/p would be 0/0 or x/0). Unusable densities of the
// other techniques (0, negative, NaN, inf) are left out of the denominator, which therefore always
// contains the own density and is never 0. Sums are taken in double and the power heuristic is computed
// on ratios to the largest density, so large float densities (near-specular lobes) do not overflow.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/sampling.h"  // MisHeuristic { Balance, Power }

namespace smis {
namespace mis {

template <class Real>
inline bool usable_pdf(Real p) {
    return p > Real(0) && p < std::numeric_limits<Real>::infinity();  // false for NaN as well
}

// Weight of technique `own` among the n selected ones, given pdfs[j] = p(x | t_j) for the sample x.
// counts (may be null = all 1): DMIS sample counts n_j (or one-sample selection probabilities P_j).
//   Balance, eq. (5) / (12):  c_own p_own / sum_j c_j p_j
//   Power (exponent beta):    (c_own p_own)^beta / sum_j (c_j p_j)^beta      (Veach 1997, sec. 9.2.3)
// Both sum to 1 over the selected techniques wherever some usable density is present.
template <class Real>
inline Real mis_weight(MisHeuristic heuristic, const Real* pdfs, const Real* counts, int n, int own,
                       double beta = 2.0) {
    if (own < 0 || own >= n || !usable_pdf(pdfs[own])) return Real(0);
    auto term = [&](int j) -> double {
        double c = counts ? static_cast<double>(counts[j]) : 1.0;
        return (usable_pdf(pdfs[j]) && c > 0.0) ? c * static_cast<double>(pdfs[j]) : 0.0;
    };
    const double mine = term(own);
    if (!(mine > 0.0)) return Real(0);
    if (heuristic == MisHeuristic::Balance) {
        double sum = 0.0;
        for (int j = 0; j < n; ++j) sum += term(j);
        return static_cast<Real>(mine / sum);  // sum >= mine > 0
    }
    double largest = 0.0;
    for (int j = 0; j < n; ++j) largest = std::max(largest, term(j));
    auto power = [beta](double r) { return beta == 2.0 ? r * r : std::pow(r, beta); };
    double sum = 0.0;
    for (int j = 0; j < n; ++j) sum += power(term(j) / largest);
    return static_cast<Real>(power(mine / largest) / sum);  // sum >= 1 (the largest term)
}

// The two everyday forms: pdfs[j] = p(x | t_j) over the n selected techniques, x sampled by t_own.
template <class Real>
inline Real balance_weight(const Real* pdfs, int n, int own) {
    return mis_weight(MisHeuristic::Balance, pdfs, static_cast<const Real*>(nullptr), n, own);
}
template <class Real>
inline Real power_weight(const Real* pdfs, int n, int own, double beta = 2.0) {
    return mis_weight(MisHeuristic::Power, pdfs, static_cast<const Real*>(nullptr), n, own, beta);
}

// Accumulates sum_i w_i(x_i) f(x_i) / (n_i p(x_i | t_i)) over the samples of one estimator realization:
// eq. (12) for SMIS (counts null, so n_i = 1), eq. (4) for DMIS with sample counts. T is anything with
// T * Real and T += T (float, double, Color); Real is the density type (float or double).
//
//   SmisCombiner<Color> c(settings.mis);
//   for (int i = 0; i < n; ++i) {
//       for (int j = 0; j < n; ++j) pdfs[j] = pdf_x_given_t(x[i], t[j]);
//       c.add(f[i], pdfs, n, i);
//   }
//   Color estimate = c.estimate();  // eq. (12): already the estimate of the integral, no 1/n
template <class T, class Real = float>
class SmisCombiner {
public:
    explicit SmisCombiner(MisHeuristic heuristic = MisHeuristic::Balance, double beta = 2.0)
        : heuristic_(heuristic), beta_(beta) {}

    // Sample x (value f = f(x)) drawn by technique `own`; pdfs[j] = p(x | t_j) for all n selected
    // techniques (j = own included).
    void add(const T& f, const Real* pdfs, int n, int own) { add(f, pdfs, nullptr, n, own); }

    // DMIS form: technique j contributes counts[j] samples to the realization (eq. 4).
    void add(const T& f, const Real* pdfs, const Real* counts, int n, int own) {
        Real w = mis_weight(heuristic_, pdfs, counts, n, own, beta_);
        if (!(w > Real(0))) return;  // includes an unusable own density
        double c = counts ? static_cast<double>(counts[own]) : 1.0;
        sum_ += f * static_cast<Real>(static_cast<double>(w) / (c * static_cast<double>(pdfs[own])));
    }

    const T& estimate() const { return sum_; }
    void reset() { sum_ = T{}; }

private:
    MisHeuristic heuristic_;
    double beta_;
    T sum_{};
};

// One-call eq. (12) for a scalar integrand: fs[i] = f(x_i), pdfs[i * n + j] = p(x_i | t_j).
template <class Real>
inline double smis_estimate(const Real* fs, const Real* pdfs, int n, MisHeuristic heuristic = MisHeuristic::Balance) {
    SmisCombiner<double, Real> c(heuristic);
    for (int i = 0; i < n; ++i) c.add(static_cast<double>(fs[i]), pdfs + static_cast<long>(i) * n, n, i);
    return c.estimate();
}

// CMIS estimator, eq. (7): w(t,x) f(x) / (p(t) p(x|t)); 0 when the joint density is not usable.
// With the uniform weight w_u = 1 / |T| (the measure of the technique space) this is CMIS_u; with the
// balance heuristic (9) it reduces to f(x) / p(x), eq. (10).
template <class T>
inline T cmis_estimate(double weight, const T& f, double pdf_t, double pdf_x_given_t) {
    double joint = pdf_t * pdf_x_given_t;
    if (!usable_pdf(joint)) return T{};
    return f * (weight / joint);
}

// ---------------------------------------------------------------------------------------------
// Technique selection in a 1D technique space [0, 1) (map through p(t)'s inverse CDF afterwards).

// Largest Real below 1, so stratified coordinates stay in [0, 1) after rounding.
template <class Real>
inline Real one_minus_epsilon() {
    return Real(1) - std::numeric_limits<Real>::epsilon() / Real(2);
}

// Stratified pattern: u_j = (u + j) / n, j = 0..n-1, from ONE uniform u in [0, 1). Each u_j alone is
// uniform on [0, 1) (so t_j = P^-1(u_j) has density p(t)); jointly they cover the n strata. Eq. (12)
// stays unbiased (appendix B: any joint selection is fine) and the set is better spread than n
// independent draws.
template <class Real>
inline Real stratified_1d(Real u, int n, int j) {
    return std::min((u + static_cast<Real>(j)) / static_cast<Real>(n), one_minus_epsilon<Real>());
}

// Random rotation (Cranley-Patterson) of a fixed pattern point `base` in [0, 1) by u in [0, 1):
// frac(base + u). With base = j / n this is the same stratified set, e.g. hero wavelengths
// lambda_j = lambda_min + (lambda_max - lambda_min) * rotate_1d(j / n, u) (paper, sec. 5).
template <class Real>
inline Real rotate_1d(Real base, Real u) {
    Real v = base + u;
    v -= std::floor(v);
    return std::min(v, one_minus_epsilon<Real>());
}

}  // namespace mis
}  // namespace smis
