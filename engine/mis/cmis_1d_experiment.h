// The 1D variance experiment of West et al. 2020, sec. 3.3 / Fig. 2: two integrands on [0,1], four
// joint densities p(t, x) = p(t) p(x|t) on [0,1]^2 (t = technique, x = sample), and the estimators
// the paper compares, plus the stochastic-weight variants of the MIS supplement
// (shared/papers/001_*.txt). Shared by engine/tests/mis_fig2_test.cpp and bench/fig2/fig2_variance.cpp.
// Not used by the renderer.
//
// The paper gives no formulas, only descriptions; the concrete choices (L_s(u) = 1 + s (2u - 1) is the
// linear density on [0,1] with slope parameter s, |s| <= 1):
//
//   integrands (column a), both with integral exactly 1:
//     f1(x) = 3 x^2                   smooth, increasing: the linear techniques suit it
//     f2(x) = 2 [x >= 1/2]            a step: discontinuous, zero on half the domain
//   joint densities (top row):
//     (b) p(t) = 1,                   p(x|t) = L_0.9(x) = 0.1 + 1.8 x        all techniques identical
//     (c) p(t) = L_0.9(t),            p(x|t) = 1                             (b) transposed
//     (d) p(t) = 1 + 0.9 cos(2 pi t), p(x|t) = L_{0.9 t}(x)                  sinusoid; uniform (t=0) to linear (t=1)
//     (e) p(t) = 1,                   p(x|t) = L_{0.9 (1 - 2t)}(x)           both marginals uniform, conditionals vary
//   marginals p(x) = int p(t) p(x|t) dt (all linear in x): (b) L_0.9, (c) 1, (d) L_0.45, (e) 1. The
//   estimators use the numerical quadrature marginal_x(); marginal_x_analytic() checks it.
//   The star configuration of Fig. 2f is (f1, e).
//
// Estimators (one REALIZATION each; an N-sample estimate averages N / n independent realizations):
//   CMIS_u   (t,x) ~ p(t,x); w_u = 1 / |T| = 1; f(x) / (p(t) p(x|t))                       eq. (7), n = 1
//   CMIS_b   (t,x) ~ p(t,x); f(x) / p(x), p(x) by quadrature                                 eq. (10), n = 1
//   SMIS_n   t_1..t_n iid ~ p(t), x_i ~ p(x|t_i); sum_i f(x_i) / sum_j p(x_i|t_j)             eq. (12)
//   SMIS_n^strat  as SMIS_n with t_j = P^-1((u + j) / n) (mis::stratified_1d)
//   SMIS_n^pow    eq. (12)'s form with power-heuristic weights (beta = 2); unbiased by appendix B
//   SW_m     stochastic-weight CMIS (supplement 001, sec. 5): (t,x) ~ p(t,x) and m-1 FRESH techniques
//            t'_k ~ p(t), independent of x. Balance weight with p(x) replaced by the random estimate
//              p^(x) = (1/m) (p(x|t) + sum_k p(x|t'_k))   (the sample's own technique is one term),
//            w^ = p(t) p(x|t) / p^(x),   estimate = w^ f(x) / (p(t) p(x|t)) = f(x) / p^(x).
//            The density in the estimator's denominator is the EXACT joint p(t,x); only the weight is
//            random, and its expectation w(t,x) = E[w^] satisfies int_T w(t,x) dt = 1 exactly: with
//            t_1 = t, int p(t) m E[p(x|t_1) / sum_j p(x|t_j)] dt = m E_{t_1..t_m iid}[...] = m (1/m)
//            by exchangeability. So it is unbiased (supplement, conditions 1 and 2), one f-sample per
//            realization, n = 1, and tends to CMIS_b as m grows.
//   SWF_m    SW_m with a stochastic f as well: Russian roulette f^ = f / q with probability q = 1/2,
//            else 0, from a random number independent of the weight's (supplement, sec. 4-5).
//   NAIVE_m  NEGATIVE CONTROL: f(x) / p~(x) with p~(x) = (1/m) sum_k p(x|t'_k) over m fresh techniques
//            only. Now E[w^] = p(t,x) E[1/p~(x)] > p(t,x) / p(x) (Jensen) wherever p(x|t) varies with t:
//            the expected weights integrate to more than 1, the supplement's condition fails, and the
//            estimator is biased upwards in (d) and (e). (In (b) and (c), p~ = p exactly.)
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/rng.h"
#include "mis/smis.h"

namespace smis {
namespace mis {
namespace cmis1d {

constexpr double kPi = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// 1D densities on [0, 1]

inline double linear_pdf(double u, double s) { return 1.0 + s * (2.0 * u - 1.0); }
// Inverse CDF of linear_pdf: CDF(u) = s u^2 + (1 - s) u; the root in the cancellation-free form.
inline double sample_linear(double v, double s) {
    if (s == 0.0) return v;
    double a = 1.0 - s;
    return std::min(1.0, 2.0 * v / (a + std::sqrt(a * a + 4.0 * s * v)));
}

constexpr double kCosAmplitude = 0.9;
inline double cosine_pdf(double t) { return 1.0 + kCosAmplitude * std::cos(2.0 * kPi * t); }
inline double cosine_cdf(double t) { return t + kCosAmplitude * std::sin(2.0 * kPi * t) / (2.0 * kPi); }
// Inverse CDF by Newton's method safeguarded with bisection (the CDF is strictly increasing), started
// from a tabulated inverse so that two or three Newton steps reach double precision.
inline double sample_cosine(double v) {
    constexpr int kTable = 256;
    static const std::vector<double> table = [] {
        std::vector<double> tab(kTable + 1);
        for (int i = 0; i <= kTable; ++i) {  // bisection to full precision, once
            double lo = 0.0, hi = 1.0, target = static_cast<double>(i) / kTable;
            for (int it = 0; it < 80; ++it) (cosine_cdf(0.5 * (lo + hi)) < target ? lo : hi) = 0.5 * (lo + hi);
            tab[i] = 0.5 * (lo + hi);
        }
        return tab;
    }();
    int cell = std::min(kTable - 1, static_cast<int>(v * kTable));
    double lo = table[cell], hi = table[cell + 1];
    double t = lo + (hi - lo) * (v * kTable - cell);
    lo = std::max(0.0, lo - 1e-12);
    hi = std::min(1.0, hi + 1e-12);
    for (int it = 0; it < 100; ++it) {
        double g = cosine_cdf(t) - v;
        if (g == 0.0) return t;
        if (g < 0.0) lo = t; else hi = t;
        double next = t - g / cosine_pdf(t);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::fabs(next - t) < 1e-13 || hi - lo < 1e-13) return next;  // Newton: next is ~1e-26 off
        t = next;
    }
    return t;
}

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on the Legendre recurrence).
inline void gauss_legendre(int n, std::vector<double>* nodes, std::vector<double>* weights) {
    nodes->assign(n, 0.0);
    weights->assign(n, 0.0);
    for (int i = 0; i < (n + 1) / 2; ++i) {
        double z = std::cos(kPi * (i + 0.75) / (n + 0.5)), pp = 0.0;
        for (int it = 0; it < 100; ++it) {
            double p1 = 1.0, p2 = 0.0;
            for (int j = 1; j <= n; ++j) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1.0) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1.0);
            double dz = p1 / pp;
            z -= dz;
            if (std::fabs(dz) < 1e-16) break;
        }
        (*nodes)[i] = -z;
        (*nodes)[n - 1 - i] = z;
        (*weights)[i] = (*weights)[n - 1 - i] = 2.0 / ((1.0 - z * z) * pp * pp);
    }
}

// Composite Gauss-Legendre rule on [0, 1]: `panels` panels of `order` nodes.
struct Quadrature {
    std::vector<double> x, w;
    Quadrature(int panels, int order) {
        std::vector<double> gx, gw;
        gauss_legendre(order, &gx, &gw);
        for (int p = 0; p < panels; ++p)
            for (int k = 0; k < order; ++k) {
                x.push_back((p + 0.5 * (gx[k] + 1.0)) / panels);
                w.push_back(0.5 * gw[k] / panels);
            }
    }
};

// ---------------------------------------------------------------------------------------------
// Integrands (Fig. 2a)

enum class IntegrandId { F1, F2 };
inline const char* integrand_name(IntegrandId f) { return f == IntegrandId::F1 ? "f1" : "f2"; }
inline double integrand(IntegrandId f, double x) {
    return f == IntegrandId::F1 ? 3.0 * x * x : (x >= 0.5 ? 2.0 : 0.0);
}
constexpr double kIntegral = 1.0;  // both integrate to exactly 1 over [0, 1]

// ---------------------------------------------------------------------------------------------
// Joint densities (Fig. 2b-e)

enum class PdfId { B, C, D, E };
inline const char* pdf_name(PdfId p) { return p == PdfId::B ? "b" : p == PdfId::C ? "c" : p == PdfId::D ? "d" : "e"; }

constexpr double kSlope = 0.9;

class JointPdf {
public:
    explicit JointPdf(PdfId id) : id_(id) {
        // p(x) = int p(t) p(x|t) dt by a 4 x 8-node Gauss-Legendre rule (relative error < 1e-14 here);
        // p(t_k) is folded into the weights.
        Quadrature q(4, 8);
        qt_ = q.x;
        for (size_t k = 0; k < q.x.size(); ++k) qw_.push_back(q.w[k] * pdf_t(q.x[k]));
    }
    PdfId id() const { return id_; }

    double pdf_t(double t) const {
        switch (id_) {
            case PdfId::C: return linear_pdf(t, kSlope);
            case PdfId::D: return cosine_pdf(t);
            default: return 1.0;
        }
    }
    double sample_t(double u) const {
        switch (id_) {
            case PdfId::C: return sample_linear(u, kSlope);
            case PdfId::D: return sample_cosine(u);
            default: return u;
        }
    }
    double pdf_x_given_t(double x, double t) const { return linear_pdf(x, slope_x(t)); }
    double sample_x(double u, double t) const { return sample_linear(u, slope_x(t)); }

    // The marginal p(x) by quadrature over t (what CMIS_b uses), and its closed form (for checks).
    double marginal_x(double x) const {
        double s = 0.0;
        for (size_t k = 0; k < qt_.size(); ++k) s += qw_[k] * pdf_x_given_t(x, qt_[k]);
        return s;
    }
    double marginal_x_analytic(double x) const {
        switch (id_) {
            case PdfId::B: return linear_pdf(x, kSlope);
            case PdfId::D: return linear_pdf(x, 0.5 * kSlope);  // E[t] = 1/2 under 1 + 0.9 cos(2 pi t)
            default: return 1.0;
        }
    }

private:
    // p(x|t) = L_s(x) with s depending on t.
    double slope_x(double t) const {
        switch (id_) {
            case PdfId::B: return kSlope;
            case PdfId::C: return 0.0;
            case PdfId::D: return kSlope * t;
            default: return kSlope * (1.0 - 2.0 * t);
        }
    }
    PdfId id_;
    std::vector<double> qt_, qw_;
};

// ---------------------------------------------------------------------------------------------
// Estimators

enum class Method { CmisU, CmisB, Smis, SmisStrat, SmisPower, StochWeight, StochWeightF, Naive };

struct Estimator {
    Method method;
    int n = 1;  // SMIS: techniques = samples per realization; SW / SWF / NAIVE: techniques in the weight
    std::string name() const {
        std::string k = std::to_string(n);
        switch (method) {
            case Method::CmisU: return "CMIS_u";
            case Method::CmisB: return "CMIS_b";
            case Method::Smis: return "SMIS_" + k;
            case Method::SmisStrat: return "SMIS_" + k + "_strat";
            case Method::SmisPower: return "SMIS_" + k + "_pow";
            case Method::StochWeight: return "SW_" + k;
            case Method::StochWeightF: return "SWF_" + k;
            case Method::Naive: return "NAIVE_" + k;
        }
        return "?";
    }
    // Integrand samples consumed by one realization (the unit of the equal-sample-count comparison).
    int samples() const {
        return (method == Method::Smis || method == Method::SmisStrat || method == Method::SmisPower) ? n : 1;
    }
};

constexpr int kMaxTechniques = 64;

// One realization of `e` for integrand f under joint density p.
inline double realize(const Estimator& e, const JointPdf& p, IntegrandId f, Rng& rng) {
    const int n = e.n;
    switch (e.method) {
        case Method::CmisU: {
            double t = p.sample_t(rng.next_double());
            double x = p.sample_x(rng.next_double(), t);
            return cmis_estimate(1.0 /* w_u = 1/|T|, |T| = 1 */, integrand(f, x), p.pdf_t(t), p.pdf_x_given_t(x, t));
        }
        case Method::CmisB: {
            double t = p.sample_t(rng.next_double());
            double x = p.sample_x(rng.next_double(), t);
            double px = p.marginal_x(x);
            return usable_pdf(px) ? integrand(f, x) / px : 0.0;  // eq. (10)
        }
        case Method::Smis:
        case Method::SmisStrat:
        case Method::SmisPower: {
            std::array<double, kMaxTechniques> t, x, pdfs;
            double u0 = rng.next_double();
            for (int j = 0; j < n; ++j)
                t[j] = p.sample_t(e.method == Method::SmisStrat ? stratified_1d(u0, n, j) : (j == 0 ? u0 : rng.next_double()));
            for (int i = 0; i < n; ++i) x[i] = p.sample_x(rng.next_double(), t[i]);
            SmisCombiner<double, double> c(e.method == Method::SmisPower ? MisHeuristic::Power : MisHeuristic::Balance);
            for (int i = 0; i < n; ++i) {
                for (int j = 0; j < n; ++j) pdfs[j] = p.pdf_x_given_t(x[i], t[j]);
                c.add(integrand(f, x[i]), pdfs.data(), n, i);
            }
            return c.estimate();  // eq. (12): the sum, no 1/n
        }
        case Method::StochWeight:
        case Method::StochWeightF: {
            double t = p.sample_t(rng.next_double());
            double x = p.sample_x(rng.next_double(), t);
            std::array<double, kMaxTechniques> pdfs;
            pdfs[0] = p.pdf_x_given_t(x, t);
            for (int k = 1; k < n; ++k) pdfs[k] = p.pdf_x_given_t(x, p.sample_t(rng.next_double()));
            const double pt = p.pdf_t(t);
            // w^ = p(t) p(x|t) / p^(x) = m p(t) * (balance weight of the own technique among the m).
            double w = n * pt * balance_weight(pdfs.data(), n, 0);
            double fx = integrand(f, x);
            if (e.method == Method::StochWeightF) fx = rng.next_double() < 0.5 ? fx / 0.5 : 0.0;
            return cmis_estimate(w, fx, pt, pdfs[0]);  // exact joint density in the denominator
        }
        case Method::Naive: {
            double t = p.sample_t(rng.next_double());
            double x = p.sample_x(rng.next_double(), t);
            double sum = 0.0;
            for (int k = 0; k < n; ++k) sum += p.pdf_x_given_t(x, p.sample_t(rng.next_double()));
            return sum > 0.0 ? integrand(f, x) / (sum / n) : 0.0;
        }
    }
    return 0.0;
}

// The N-sample estimate: the mean of N / samples() independent realizations (N a multiple of samples()).
inline double estimate(const Estimator& e, const JointPdf& p, IntegrandId f, int total_samples, Rng& rng) {
    int r = total_samples / e.samples();
    double s = 0.0;
    for (int k = 0; k < r; ++k) s += realize(e, p, f, rng);
    return s / r;
}

// ---------------------------------------------------------------------------------------------
// Exact reference values by quadrature (smooth except f2's step at x = 1/2, a panel boundary).
// Variances are per SAMPLE: Var[one realization] * samples(), so Var[N-sample estimate] = value / N.

struct Exact {
    double cmis_u = 0, cmis_b = 0, smis_1 = 0;
    // Limit of n Var[SMIS_n] as n -> infinity with independent techniques:
    // Var[CMIS_b] - Var_t[mu(t)], mu(t) = int f(x) p(x|t) / p(x) dx (the techniques' shares I_t / p(t)).
    // Conditionally on the techniques SMIS_n is a one-sample-per-technique DMIS estimator, i.e.
    // stratified sampling of the mixture, which removes the between-technique term; hence SMIS_n can
    // drop BELOW CMIS_b, whose optimality (appendix A) is among one-sample CMIS estimators only.
    double smis_limit = 0;
};

inline Exact exact_variances(const JointPdf& p, IntegrandId f) {
    Quadrature q(64, 16);  // 1024 nodes per axis; x = 1/2 is a panel boundary
    const double I = kIntegral;
    Exact r;
    double eu = 0, eb = 0, e1 = 0, mu_sq = 0;
    for (size_t a = 0; a < q.x.size(); ++a) {
        double x = q.x[a], fx = integrand(f, x), px = p.marginal_x_analytic(x);
        eb += q.w[a] * fx * fx / px;
    }
    for (size_t b = 0; b < q.x.size(); ++b) {
        double t = q.x[b], pt = p.pdf_t(t), mu = 0;
        for (size_t a = 0; a < q.x.size(); ++a) {
            double x = q.x[a], fx = integrand(f, x), pxt = p.pdf_x_given_t(x, t);
            eu += q.w[b] * q.w[a] * fx * fx / (pt * pxt);
            e1 += q.w[b] * q.w[a] * pt * fx * fx / pxt;
            mu += q.w[a] * fx * pxt / p.marginal_x_analytic(x);
        }
        mu_sq += q.w[b] * pt * mu * mu;
    }
    r.cmis_u = eu - I * I;
    r.cmis_b = eb - I * I;
    r.smis_1 = e1 - I * I;
    r.smis_limit = r.cmis_b - (mu_sq - I * I);
    return r;
}

}  // namespace cmis1d
}  // namespace mis
}  // namespace smis
