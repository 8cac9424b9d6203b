// Statistical test harness shared by the sampling tests (BSDFs, lights, ...).
//
//  * chi2_test_directions(): Pearson chi-square goodness-of-fit of a direction sampler against its
//    claimed solid-angle pdf, on a (theta, phi) histogram of the full sphere. Modelled on pbrt-v3's
//    src/tests/bsdfs.cpp (itself after Mitsuba's chi2 test): expected counts come from numerically
//    integrating the pdf over every cell, cells with an expected count below 5 are pooled, and the
//    p-value is compared against a Sidak-corrected significance level so that a whole suite of tests
//    has a 1% chance of a false alarm.
//  * z-test helpers for Monte-Carlo estimates (furnace tests, estimator comparisons).
//  * Regularised incomplete gamma functions for chi-square p-values.
//
// Header-only and independent of the rest of the engine except core/math.h and core/rng.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace smis {
namespace stats {

constexpr double kPiD = 3.14159265358979323846;

// ---------------------------------------------------------------------------------------------
// Special functions

// Regularised lower incomplete gamma P(a, x) and its complement Q(a, x) = 1 - P(a, x), computed
// with the series (x < a + 1) or the Lentz continued fraction (otherwise), Numerical Recipes 6.2.
// Q is computed directly in the tail, so tiny p-values do not cancel to 0.
namespace detail {
inline double gamma_series_p(double a, double x) {
    double ap = a, sum = 1.0 / a, del = sum;
    for (int n = 0; n < 100000; ++n) {
        ap += 1.0;
        del *= x / ap;
        sum += del;
        if (std::fabs(del) < std::fabs(sum) * 1e-16) break;
    }
    return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}
inline double gamma_cf_q(double a, double x) {
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::fabs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::fabs(c) < tiny) c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::fabs(del - 1.0) < 1e-16) break;
    }
    return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}
}  // namespace detail

inline double regularized_gamma_p(double a, double x) {
    if (!(a > 0.0) || std::isnan(x)) return std::nan("");
    if (x <= 0.0) return 0.0;
    if (std::isinf(x)) return 1.0;
    return x < a + 1.0 ? detail::gamma_series_p(a, x) : 1.0 - detail::gamma_cf_q(a, x);
}

inline double regularized_gamma_q(double a, double x) {
    if (!(a > 0.0) || std::isnan(x)) return std::nan("");
    if (x <= 0.0) return 1.0;
    if (std::isinf(x)) return 0.0;
    return x < a + 1.0 ? 1.0 - detail::gamma_series_p(a, x) : detail::gamma_cf_q(a, x);
}

// P(X >= chi2) for X ~ chi-square with `dof` degrees of freedom: the test's p-value.
inline double chi2_survival(double chi2, double dof) { return regularized_gamma_q(0.5 * dof, 0.5 * chi2); }

// Per-test significance so that `num_tests` independent tests together reject a correct sampler with
// probability `family_significance` (Sidak correction).
inline double sidak_significance(double family_significance, int num_tests) {
    return 1.0 - std::pow(1.0 - family_significance, 1.0 / std::max(1, num_tests));
}

// ---------------------------------------------------------------------------------------------
// Mean estimates and z-tests

// Running mean / variance (Welford), for Monte-Carlo estimators.
class MeanEstimator {
public:
    void add(double x) {
        ++n_;
        double d = x - mean_;
        mean_ += d / static_cast<double>(n_);
        m2_ += d * (x - mean_);
    }
    uint64_t count() const { return n_; }
    // The estimator of k times every value added (a k-times-wrong estimator's, for tests' power).
    void scale(double k) {
        mean_ *= k;
        m2_ *= k * k;
    }
    double mean() const { return mean_; }
    double variance() const { return n_ > 1 ? m2_ / static_cast<double>(n_ - 1) : 0.0; }
    // Standard error of the mean.
    double std_error() const { return n_ > 0 ? std::sqrt(variance() / static_cast<double>(n_)) : 0.0; }

private:
    uint64_t n_ = 0;
    double mean_ = 0.0, m2_ = 0.0;
};

struct ZTest {
    double z = 0.0;        // signed: (estimate - expected) / std_error
    double p_value = 1.0;  // two-sided
};

inline double two_sided_p_value(double z) { return std::erfc(std::fabs(z) / std::sqrt(2.0)); }

// Two-sided z-test of `estimate` (with standard error `std_error`) against a known value. A zero
// standard error (deterministic estimator) accepts only an exact match up to `abs_tolerance`.
inline ZTest z_test(double estimate, double expected, double std_error, double abs_tolerance = 0.0) {
    ZTest t;
    double diff = estimate - expected;
    if (std::fabs(diff) <= abs_tolerance) diff = 0.0;
    if (std_error > 0.0) {
        t.z = diff / std_error;
    } else {
        t.z = diff == 0.0 ? 0.0 : std::copysign(INFINITY, diff);
    }
    t.p_value = two_sided_p_value(t.z);
    return t;
}
inline ZTest z_test_mean(const MeanEstimator& m, double expected, double abs_tolerance = 0.0) {
    return z_test(m.mean(), expected, m.std_error(), abs_tolerance);
}
// Difference of two independent estimates of the same quantity.
inline ZTest z_test_difference(const MeanEstimator& a, const MeanEstimator& b, double abs_tolerance = 0.0) {
    double se = std::hypot(a.std_error(), b.std_error());
    return z_test(a.mean() - b.mean(), 0.0, se, abs_tolerance);
}
// One-sided "estimate <= bound" test: true unless the estimate exceeds the bound by more than
// `sigmas` standard errors (plus an absolute slack for deterministic estimators).
inline bool at_most(const MeanEstimator& m, double bound, double sigmas = 3.0, double abs_tolerance = 1e-6) {
    return m.mean() <= bound + sigmas * m.std_error() + abs_tolerance;
}

// ---------------------------------------------------------------------------------------------
// Direction histograms

// What a sampler produced: a direction on the unit sphere, a Dirac event (no density: excluded from
// the histogram, the pdf has no mass for it), or a failure (e.g. reflected below the horizon).
// A Valid sample may also carry the pdf the sampler reported for it (pdf >= 0); the test then checks
// it against pdf_fn(w), which catches a sampler whose returned pdf disagrees with its pdf() routine.
struct DirSample {
    enum class Kind : uint8_t { Valid, Delta, Invalid };
    Vec3 w;
    Kind kind = Kind::Invalid;
    double pdf = -1.0;  // < 0: not reported
    static DirSample valid(const Vec3& w, double reported_pdf = -1.0) { return {w, Kind::Valid, reported_pdf}; }
    static DirSample delta() { return {Vec3(0.0f), Kind::Delta, -1.0}; }
    static DirSample invalid() { return {Vec3(0.0f), Kind::Invalid, -1.0}; }
};

inline Vec3 spherical_direction(double theta, double phi) {
    double st = std::sin(theta);
    return Vec3(static_cast<float>(st * std::cos(phi)), static_cast<float>(st * std::sin(phi)),
                static_cast<float>(std::cos(theta)));
}

// (theta, phi) histogram layout: theta in [0, pi] from +z, phi in [0, 2 pi) from +x.
struct SphereGrid {
    int n_theta = 20, n_phi = 40;
    int cells() const { return n_theta * n_phi; }
    // Cell index of a unit direction, or -1 for a non-finite one.
    int cell_of(const Vec3& w) const {
        if (!is_finite(w)) return -1;
        double theta = std::acos(std::clamp(static_cast<double>(w.z), -1.0, 1.0));
        double phi = std::atan2(static_cast<double>(w.y), static_cast<double>(w.x));
        if (phi < 0.0) phi += 2.0 * kPiD;
        int it = std::min(n_theta - 1, static_cast<int>(theta / kPiD * n_theta));
        int ip = std::min(n_phi - 1, static_cast<int>(phi / (2.0 * kPiD) * n_phi));
        return std::max(0, it) * n_phi + std::max(0, ip);
    }
};

// Numerical integration of f(direction) over (theta, phi) rectangles, with respect to solid angle
// (dw = sin(theta) dtheta dphi).
struct IntegrationOptions {
    // Every histogram cell starts as subdivisions^2 rectangles: peaked lobes (GGX with alpha = 0.05)
    // could otherwise fall between the first nodes of the adaptive rule and be missed entirely.
    int subdivisions = 4;
    // Quadtree refinement of a rectangle stops once its 3x3 Gauss-Legendre value and the sum over its
    // four children agree within max(abs_tolerance, rel_tolerance * value); the absolute tolerance is
    // halved per level so the error along a discontinuity curve still converges.
    double abs_tolerance = 1e-7;
    double rel_tolerance = 1e-5;
    int max_depth = 9;
    // Refinement stops for good after this many integrand evaluations (per integrate_cells call), so a
    // noisy or broken pdf makes the test fail quickly instead of refining forever.
    uint64_t max_evaluations = 50000000;
};

namespace detail {
// 3x3 Gauss-Legendre rule on [t0,t1] x [p0,p1]. The nodes never touch the rectangle's border, where
// discontinuities (the horizon at a cell border) usually sit.
template <class Fn>
double gauss_rect(Fn& f, double t0, double t1, double p0, double p1) {
    static const double kNodes[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double kWeights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    double ht = 0.5 * (t1 - t0), hp = 0.5 * (p1 - p0), tc = t0 + ht, pc = p0 + hp;
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
        double theta = tc + kNodes[i] * ht;
        double wt = kWeights[i] * std::sin(theta);
        for (int j = 0; j < 3; ++j)
            sum += wt * kWeights[j] * static_cast<double>(f(spherical_direction(theta, pc + kNodes[j] * hp)));
    }
    return sum * ht * hp;
}

template <class Fn>
double adaptive_rect(Fn& f, double t0, double t1, double p0, double p1, double whole, double abs_tol,
                     const IntegrationOptions& opt, int depth, uint64_t* evaluations) {
    double tm = 0.5 * (t0 + t1), pm = 0.5 * (p0 + p1);
    double q[4] = {gauss_rect(f, t0, tm, p0, pm), gauss_rect(f, t0, tm, pm, p1), gauss_rect(f, tm, t1, p0, pm),
                   gauss_rect(f, tm, t1, pm, p1)};
    *evaluations += 36;
    double sum = q[0] + q[1] + q[2] + q[3];
    if (depth >= opt.max_depth || *evaluations >= opt.max_evaluations ||
        std::fabs(sum - whole) <= std::max(abs_tol, opt.rel_tolerance * std::fabs(sum)) || !std::isfinite(sum))
        return sum;
    double t = 0.5 * abs_tol;
    return adaptive_rect(f, t0, tm, p0, pm, q[0], t, opt, depth + 1, evaluations) +
           adaptive_rect(f, t0, tm, pm, p1, q[1], t, opt, depth + 1, evaluations) +
           adaptive_rect(f, tm, t1, p0, pm, q[2], t, opt, depth + 1, evaluations) +
           adaptive_rect(f, tm, t1, pm, p1, q[3], t, opt, depth + 1, evaluations);
}
}  // namespace detail

// Integral of f over every cell of `grid`.
template <class Fn>
std::vector<double> integrate_cells(const SphereGrid& grid, Fn&& f, const IntegrationOptions& opt = {}) {
    std::vector<double> out(grid.cells(), 0.0);
    const int sub = std::max(1, opt.subdivisions);
    const double dt = kPiD / grid.n_theta / sub, dp = 2.0 * kPiD / grid.n_phi / sub;
    uint64_t evaluations = 0;
    for (int it = 0; it < grid.n_theta; ++it) {
        for (int ip = 0; ip < grid.n_phi; ++ip) {
            double sum = 0.0;
            for (int st = 0; st < sub; ++st) {
                double t0 = (it * sub + st) * dt, t1 = t0 + dt;
                for (int sp = 0; sp < sub; ++sp) {
                    double p0 = (ip * sub + sp) * dp, p1 = p0 + dp;
                    double whole = detail::gauss_rect(f, t0, t1, p0, p1);
                    sum += detail::adaptive_rect(f, t0, t1, p0, p1, whole, opt.abs_tolerance, opt, 0, &evaluations);
                }
            }
            out[it * grid.n_phi + ip] = sum;
        }
    }
    return out;
}

// Integral of f over the whole sphere (solid angle), with the same rule.
template <class Fn>
double integrate_sphere(Fn&& f, const IntegrationOptions& opt = {}, SphereGrid grid = SphereGrid{20, 40}) {
    std::vector<double> cells = integrate_cells(grid, f, opt);
    double sum = 0.0;
    for (double c : cells) sum += c;
    return sum;
}

struct Chi2Options {
    SphereGrid grid{20, 40};
    uint64_t seed = 1;
    double min_expected = 5.0;  // pool cells expected to receive fewer samples than this
    IntegrationOptions integration;  // how the pdf is integrated over the cells
    double pdf_rel_tolerance = 1e-3;  // reported vs pdf_fn() pdf agreement (<= 0 disables the check)
};

struct Chi2Result {
    double chi2 = 0.0;
    int dof = 0;
    double p_value = 0.0;
    int pooled_cells = 0;
    uint64_t n_samples = 0, n_valid = 0, n_delta = 0, n_invalid = 0;
    uint64_t n_bad = 0;         // valid samples that are not finite unit vectors
    uint64_t n_pdf_mismatch = 0;  // valid samples whose reported pdf disagrees with pdf_fn
    double pdf_integral = 0.0;  // integral of the pdf over the sphere (1 minus failures and Diracs)
    std::string error;          // set when the test could not even be run meaningfully
    SphereGrid grid;
    std::vector<double> observed, expected;

    // Accept the sampler at per-test significance level `alpha`.
    bool passes(double alpha) const { return error.empty() && std::isfinite(p_value) && p_value >= alpha; }

    std::string summary() const {
        char buf[512];
        std::snprintf(buf, sizeof(buf),
                      "chi2 = %.2f, dof = %d, p = %.4g, pooled cells = %d, samples: %llu valid / %llu delta / "
                      "%llu invalid / %llu bad / %llu pdf mismatches, pdf integral = %.6f, valid fraction = %.6f%s%s",
                      chi2, dof, p_value, pooled_cells, (unsigned long long)n_valid, (unsigned long long)n_delta,
                      (unsigned long long)n_invalid, (unsigned long long)n_bad, (unsigned long long)n_pdf_mismatch,
                      pdf_integral,
                      n_samples ? double(n_valid) / double(n_samples) : 0.0, error.empty() ? "" : ", error: ",
                      error.c_str());
        return buf;
    }

    // Map of signed residuals (obs - exp) / sqrt(exp), one row per theta band, for failure reports:
    // '.' |r| < 2, '+'/'-' 2..4, '#'/'=' above 4, 'X' samples in a zero-expectation cell, ' ' empty.
    std::string residual_map() const {
        std::string s;
        for (int it = 0; it < grid.n_theta; ++it) {
            for (int ip = 0; ip < grid.n_phi; ++ip) {
                int c = it * grid.n_phi + ip;
                double e = expected[c], o = observed[c];
                char ch = ' ';
                if (e <= 0.0) {
                    ch = o > 0.0 ? 'X' : ' ';
                } else {
                    double r = (o - e) / std::sqrt(e);
                    ch = std::fabs(r) < 2.0 ? '.' : (std::fabs(r) < 4.0 ? (r > 0 ? '+' : '-') : (r > 0 ? '#' : '='));
                }
                s += ch;
            }
            s += '\n';
        }
        return s;
    }
};

// Pearson chi-square statistic with pbrt-v3's pooling of cells whose expected count is below
// `min_expected` (low expectations break the chi-square approximation of the statistic).
inline void chi2_statistic(const std::vector<double>& observed, const std::vector<double>& expected,
                           double min_expected, uint64_t n_samples, Chi2Result* res) {
    std::vector<int> order(expected.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
    std::sort(order.begin(), order.end(), [&](int a, int b) { return expected[a] < expected[b]; });
    double pooled_obs = 0.0, pooled_exp = 0.0, chi2 = 0.0;
    int pooled = 0, dof = 0;
    for (int c : order) {
        if (expected[c] <= 0.0) {
            // Samples where the pdf claims there is no mass: a hard error beyond a rounding-noise level.
            if (observed[c] > static_cast<double>(n_samples) * 1e-5) {
                char buf[160];
                std::snprintf(buf, sizeof(buf), "%.0f samples in cell %d whose expected count is 0", observed[c], c);
                res->error = buf;
            }
        } else if (expected[c] < min_expected || (pooled_exp > 0.0 && pooled_exp < min_expected)) {
            pooled_obs += observed[c];
            pooled_exp += expected[c];
            ++pooled;
        } else {
            double d = observed[c] - expected[c];
            chi2 += d * d / expected[c];
            ++dof;
        }
    }
    if (pooled_exp > 0.0 || pooled_obs > 0.0) {
        double d = pooled_obs - pooled_exp;
        chi2 += pooled_exp > 0.0 ? d * d / pooled_exp : INFINITY;
        ++dof;
    }
    dof -= 1;  // every parameter is known; only the total is (approximately) constrained
    res->chi2 = chi2;
    res->dof = dof;
    res->pooled_cells = pooled;
    if (dof <= 0) {
        if (res->error.empty()) res->error = "too few degrees of freedom (distribution too concentrated for the grid)";
        res->p_value = 0.0;
        return;
    }
    res->p_value = chi2_survival(chi2, dof);
}

// The chi-square test of a direction sampler against its pdf.
//   sample_fn(Rng&) -> DirSample: draw one sample (draw as many random numbers as needed from the Rng).
//   pdf_fn(const Vec3&) -> float/double: solid-angle density of sample_fn's Valid outcomes.
// Delta and Invalid samples are counted but not histogrammed (the pdf has no mass for them), so the
// pdf must integrate to the fraction of Valid samples; a mismatch shows up in chi2.
// Typical use, with the Sidak-corrected level for the number of chi-square tests in the suite:
//   Chi2Result r = chi2_test_directions(sample, pdf, 1000000);
//   EXPECT_TRUE(r.passes(sidak_significance(0.01, num_tests))) << r.summary() << r.residual_map();
template <class SampleFn, class PdfFn>
Chi2Result chi2_test_directions(SampleFn&& sample_fn, PdfFn&& pdf_fn, uint64_t n_samples,
                                const Chi2Options& opt = Chi2Options{}) {
    Chi2Result res;
    res.grid = opt.grid;
    res.n_samples = n_samples;
    res.observed.assign(opt.grid.cells(), 0.0);
    Rng rng(mix64(opt.seed), mix64(opt.seed ^ 0x5bd1e995u));
    for (uint64_t i = 0; i < n_samples; ++i) {
        DirSample s = sample_fn(rng);
        if (s.kind == DirSample::Kind::Delta) {
            ++res.n_delta;
        } else if (s.kind == DirSample::Kind::Invalid) {
            ++res.n_invalid;
        } else {
            ++res.n_valid;
            int c = opt.grid.cell_of(s.w);
            if (c < 0 || std::fabs(length(s.w) - 1.0f) > 1e-3f) {
                ++res.n_bad;
                continue;
            }
            res.observed[c] += 1.0;
            if (s.pdf >= 0.0 && opt.pdf_rel_tolerance > 0.0) {
                double p = static_cast<double>(pdf_fn(s.w));
                if (!(std::fabs(p - s.pdf) <= opt.pdf_rel_tolerance * std::max(p, s.pdf) + 1e-7)) ++res.n_pdf_mismatch;
            }
        }
    }
    res.expected = integrate_cells(opt.grid, pdf_fn, opt.integration);
    bool pdf_ok = true;
    for (double& e : res.expected) {
        if (!std::isfinite(e) || e < 0.0) pdf_ok = false;
        res.pdf_integral += e;
        e *= static_cast<double>(n_samples);
    }
    chi2_statistic(res.observed, res.expected, opt.min_expected, n_samples, &res);
    if (!pdf_ok) res.error = "pdf is negative or not finite somewhere";
    if (res.n_bad > 0 && res.error.empty()) res.error = "sampler returned non-finite or non-unit directions";
    if (res.n_pdf_mismatch > 0 && res.error.empty()) res.error = "sampler's reported pdf disagrees with pdf_fn";
    return res;
}

// Convenience form: grid resolution and seed as plain arguments.
template <class SampleFn, class PdfFn>
Chi2Result chi2_test_directions(SampleFn&& sample_fn, PdfFn&& pdf_fn, int n_theta, int n_phi, uint64_t n_samples,
                                uint64_t seed = 1) {
    Chi2Options opt;
    opt.grid = SphereGrid{n_theta, n_phi};
    opt.seed = seed;
    return chi2_test_directions(sample_fn, pdf_fn, n_samples, opt);
}

// A parameter in a test's name ("0.5" -> "0p5", "-1" -> "m1": gtest names allow neither '.' nor '-').
inline std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof(buf), "%g", v);
    std::string s;
    for (char c : std::string(buf)) s += c == '.' ? 'p' : (c == '-' ? 'm' : c);
    return s;
}

// a and b within a relative tolerance of the larger, plus an absolute floor.
inline bool close_rel(double a, double b, double rel = 1e-3, double abs_floor = 1e-7) {
    return std::fabs(a - b) <= rel * std::max(std::fabs(a), std::fabs(b)) + abs_floor;
}

}  // namespace stats
}  // namespace smis
