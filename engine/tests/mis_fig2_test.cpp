// The 1D experiment of West et al. 2020 (sec. 3.3, Fig. 2) as a statistical test of engine/mis/smis.h:
// every estimator is unbiased, the stochastic-weight estimators of the MIS supplement are unbiased
// (and the naive one that approximates the denominator is not), and the variance orderings the paper
// STATES hold. Configurations and estimators: engine/mis/cmis_1d_experiment.h.
//
// Variances. At an equal total sample count N, an estimator using n samples per realization averages
// N/n independent realizations, so Var[N-sample estimate] = n Var[realization] / N = v / N, with
// v = n Var[realization] its "per-sample variance". Every comparison at equal N is therefore a
// comparison of v, which we estimate from K = M/n realizations (M samples per estimator and
// configuration) with the sample variance s^2 and its large-sample standard error
// sqrt((m4 - s^4 (K-3)/(K-1)) / K) (m4: central fourth moment; no normality assumed, unlike an
// F-test). Differences of independent estimates are z-tested. EqualSampleCountRunsMatchPerSampleVariance
// checks the scaling itself on 16-sample runs.
//
// Significance: every check below is one hypothesis test; the family of all of them rejects a correct
// implementation with probability 1% (Sidak correction over kMaxChecks, an upper bound on their number:
// each test counts its checks against its share). The seeds are fixed, so the outcome is deterministic.
// One test per joint density (ctest runs every test in its own process, so each measures only its own
// configuration: 2 integrands x 10 estimators x 2^20 samples).
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "mis/cmis_1d_experiment.h"
#include "stats.h"

using namespace smis;
using namespace smis::mis;
using namespace smis::mis::cmis1d;

namespace {

constexpr int kChecksPerConfig = 50, kChecksRuns = 10;
constexpr int kMaxChecks = 4 * kChecksPerConfig + kChecksRuns;
const double kAlpha = stats::sidak_significance(0.01, kMaxChecks);

constexpr long kSamples = 1L << 20;  // M: integrand samples per estimator and configuration

const IntegrandId kIntegrands[] = {IntegrandId::F1, IntegrandId::F2};

const Estimator kCmisU{Method::CmisU, 1}, kCmisB{Method::CmisB, 1}, kSmis1{Method::Smis, 1}, kSmis2{Method::Smis, 2},
    kSmis4{Method::Smis, 4}, kSmis4Strat{Method::SmisStrat, 4}, kSmis4Pow{Method::SmisPower, 4},
    kSW4{Method::StochWeight, 4}, kSWF4{Method::StochWeightF, 4}, kNaive4{Method::Naive, 4};
const Estimator kAll[] = {kCmisU, kCmisB, kSmis1, kSmis2, kSmis4, kSmis4Strat, kSmis4Pow, kSW4, kSWF4, kNaive4};

// Mean and per-sample variance of one estimator in one configuration, with standard errors.
struct Measured {
    double mean = 0, mean_se = 0;
    double v = 0, v_se = 0;  // per-sample variance n Var[realization] and its standard error
};

Measured measure_values(const std::vector<double>& x, int samples_per_realization) {
    const double K = static_cast<double>(x.size());
    double mean = 0;
    for (double a : x) mean += a;
    mean /= K;
    double m2 = 0, m4 = 0;
    for (double a : x) {
        double d = (a - mean) * (a - mean);
        m2 += d;
        m4 += d * d;
    }
    double s2 = m2 / (K - 1);
    m4 /= K;
    // Delta-method variance of s^2, plus its second-order term (order s^2/K, chi-square like): that term
    // dominates when the first-order one vanishes, e.g. for f2 = 2 [x >= 1/2] under a uniform p(x),
    // whose estimates take the two values 0 and 2 with probability 1/2 each.
    double var_s2 = std::max(0.0, (m4 - s2 * s2 * (K - 3) / (K - 1)) / K) + std::pow(6.0 * s2 / K, 2);
    Measured m;
    m.mean = mean;
    m.mean_se = std::sqrt(s2 / K);
    m.v = samples_per_realization * s2;
    m.v_se = samples_per_realization * std::sqrt(var_s2);
    return m;
}

uint64_t seed_of(PdfId p, IntegrandId f, const Estimator& e, uint64_t salt = 0) {
    return mix64((static_cast<uint64_t>(p) << 40) ^ (static_cast<uint64_t>(f) << 32) ^
                 (static_cast<uint64_t>(e.method) << 16) ^ static_cast<uint64_t>(e.n) ^ (salt << 48) ^ 0x5eedull);
}

Measured measure(PdfId pid, IntegrandId f, const Estimator& e, long samples, uint64_t salt = 0) {
    JointPdf p(pid);
    Rng rng(seed_of(pid, f, e, salt), 0);
    std::vector<double> values(samples / e.samples());
    for (double& v : values) v = realize(e, p, f, rng);
    return measure_values(values, e.samples());
}

double one_sided_p(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }  // P(Z >= z)

// Every estimator of kAll for both integrands under one joint density, and the checks on them.
class Config {
public:
    explicit Config(PdfId pid) : pid_(pid) {
        auto t0 = std::chrono::steady_clock::now();
        for (IntegrandId f : kIntegrands)
            for (const Estimator& e : kAll) data_[key(f, e)] = measure(pid, f, e, kSamples);
        double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::printf("[fig2 %s] %zu estimators x %ld samples in %.2f s; variance at N = 64 (per-sample v / 64):\n",
                    pdf_name(pid), data_.size(), kSamples, secs);
        for (IntegrandId f : kIntegrands) {
            std::printf("  %s:", integrand_name(f));
            for (const Estimator& e : kAll) std::printf(" %s %.4e", e.name().c_str(), get(f, e).v / 64.0);
            std::printf("\n");
        }
    }
    ~Config() { EXPECT_LE(checks_, kChecksPerConfig) << "raise kChecksPerConfig"; }

    const Measured& get(IntegrandId f, const Estimator& e) const { return data_.at(key(f, e)); }

    void expect_unbiased(IntegrandId f, const Estimator& e) {
        ++checks_;
        const Measured& m = get(f, e);
        stats::ZTest t = stats::z_test(m.mean, kIntegral, m.mean_se);
        EXPECT_GE(t.p_value, kAlpha) << where(f) << e.name() << " biased: mean " << m.mean << " +- " << m.mean_se
                                     << " vs " << kIntegral << ", z = " << t.z;
    }
    void expect_biased_upwards(IntegrandId f, const Estimator& e) {
        ++checks_;
        const Measured& m = get(f, e);
        stats::ZTest t = stats::z_test(m.mean, kIntegral, m.mean_se);
        EXPECT_TRUE(t.z > 0.0 && t.p_value < kAlpha) << where(f) << e.name() << " not detectably biased: mean "
                                                     << m.mean << " +- " << m.mean_se << ", z = " << t.z;
    }
    // The per-sample variance agrees with a quadrature value.
    void expect_variance(IntegrandId f, const Estimator& e, double exact) {
        ++checks_;
        const Measured& m = get(f, e);
        double z = (m.v - exact) / m.v_se;
        EXPECT_GE(stats::two_sided_p_value(z), kAlpha) << where(f) << e.name() << ": v = " << m.v << " +- " << m.v_se
                                                       << ", quadrature " << exact << ", z = " << z;
    }
    // v(a) == v(b): not significantly different (two-sided).
    void expect_equal_variance(IntegrandId f, const Estimator& a, const Estimator& b) {
        double z = z_diff(f, a, b);
        EXPECT_GE(stats::two_sided_p_value(z), kAlpha) << describe("equal variances", f, a, b, z);
    }
    // v(a) > v(b), significantly.
    void expect_greater_variance(IntegrandId f, const Estimator& a, const Estimator& b) {
        double z = z_diff(f, a, b);
        EXPECT_LT(one_sided_p(z), kAlpha) << describe("first significantly above second", f, a, b, z);
    }
    // v(a) <= v(b): not significantly above.
    void expect_not_greater_variance(IntegrandId f, const Estimator& a, const Estimator& b) {
        double z = z_diff(f, a, b);
        EXPECT_GE(one_sided_p(z), kAlpha) << describe("first not above second", f, a, b, z);
    }
    // |v(SMIS_4) - v(CMIS_b)| < |v(SMIS_1) - v(CMIS_b)|. With v(SMIS_4) < v(SMIS_1) (checked separately)
    // this is v(SMIS_4) > 2 v(CMIS_b) - v(SMIS_1), significantly.
    void expect_closer_to_cmis_b(IntegrandId f, const Estimator& near, const Estimator& far) {
        ++checks_;
        const Measured &mn = get(f, near), &mf = get(f, far), &mb = get(f, kCmisB);
        double z = (mn.v - (2.0 * mb.v - mf.v)) / std::sqrt(mn.v_se * mn.v_se + 4.0 * mb.v_se * mb.v_se + mf.v_se * mf.v_se);
        EXPECT_LT(one_sided_p(z), kAlpha) << describe("first closer to CMIS_b than second", f, near, far, z)
                                          << ", CMIS_b v = " << mb.v;
    }

    // (a), (c): the paper's estimators and the stochastic-weight ones are unbiased; the measured
    // variances of CMIS_u, CMIS_b and SMIS_1 agree with quadrature.
    void common_checks() {
        for (IntegrandId f : kIntegrands) {
            SCOPED_TRACE(integrand_name(f));
            for (const Estimator& e : {kCmisU, kCmisB, kSmis1, kSmis2, kSmis4, kSmis4Strat, kSmis4Pow}) expect_unbiased(f, e);
            // Supplement 001: random weights whose expectation integrates to 1 over T, the exact joint
            // density in the denominator, independent random numbers for f: still unbiased.
            for (const Estimator& e : {kSW4, kSWF4}) expect_unbiased(f, e);
            Exact ex = exact_variances(JointPdf(pid_), f);
            expect_variance(f, kCmisU, ex.cmis_u);
            expect_variance(f, kCmisB, ex.cmis_b);
            expect_variance(f, kSmis1, ex.smis_1);
        }
    }

private:
    std::string key(IntegrandId f, const Estimator& e) const { return std::string(integrand_name(f)) + "/" + e.name(); }
    std::string where(IntegrandId f) const {
        return std::string("(") + pdf_name(pid_) + ", " + integrand_name(f) + ") ";
    }
    double z_diff(IntegrandId f, const Estimator& a, const Estimator& b) {
        ++checks_;
        const Measured &ma = get(f, a), &mb = get(f, b);
        return (ma.v - mb.v) / std::hypot(ma.v_se, mb.v_se);
    }
    std::string describe(const char* claim, IntegrandId f, const Estimator& a, const Estimator& b, double z) const {
        const Measured &ma = get(f, a), &mb = get(f, b);
        char buf[400];
        std::snprintf(buf, sizeof(buf), "%s%s: %s v = %.5f +- %.5f, %s v = %.5f +- %.5f, z = %.2f, alpha = %.2g",
                      where(f).c_str(), claim, a.name().c_str(), ma.v, ma.v_se, b.name().c_str(), mb.v, mb.v_se, z, kAlpha);
        return buf;
    }

    PdfId pid_;
    std::map<std::string, Measured> data_;
    int checks_ = 0;
};

// ---------------------------------------------------------------------------------------------

TEST(MisFig2, NumericalMarginalMatchesClosedForm) {
    for (PdfId pid : {PdfId::B, PdfId::C, PdfId::D, PdfId::E}) {
        JointPdf p(pid);
        for (int i = 0; i <= 1000; ++i) {
            double x = i / 1000.0;
            EXPECT_NEAR(p.marginal_x(x), p.marginal_x_analytic(x), 1e-12) << pdf_name(pid) << " x = " << x;
        }
    }
}

// (b) "all sampling techniques are both equally likely, since p(t) = const, and have identical
// conditional PDFs p(x|t) ... all estimators reduce to having the same expression."
TEST(MisFig2, ConfigB_AllEstimatorsEqual) {
    Config c(PdfId::B);
    c.common_checks();
    for (IntegrandId f : kIntegrands)
        for (const Estimator& e : {kCmisU, kSmis1, kSmis2, kSmis4, kSmis4Strat}) c.expect_equal_variance(f, e, kCmisB);
}

// (c) "CMIS_u is affected by the variation in p(t) as it evaluates the full joint PDF ... All other
// estimators are agnostic to this variation as they only evaluate p(x|t) or p(x)." + "CMIS_u performs worst".
TEST(MisFig2, ConfigC_CmisUniformWorst_SmisAgnosticToPt) {
    Config c(PdfId::C);
    c.common_checks();
    for (IntegrandId f : kIntegrands) {
        for (const Estimator& e : {kCmisB, kSmis1, kSmis2, kSmis4}) c.expect_greater_variance(f, kCmisU, e);
        for (const Estimator& e : {kSmis1, kSmis2, kSmis4}) c.expect_equal_variance(f, e, kCmisB);
    }
}

// (d) "Here CMIS_u performs as badly as in (c). SMIS approaches the performance of CMIS_b as the
// number of samples per realization increases."
TEST(MisFig2, ConfigD_CmisUniformWorst_SmisApproachesCmisB) {
    Config c(PdfId::D);
    c.common_checks();
    for (IntegrandId f : kIntegrands) {
        for (const Estimator& e : {kCmisB, kSmis1, kSmis2, kSmis4}) c.expect_greater_variance(f, kCmisU, e);
        c.expect_not_greater_variance(f, kSmis2, kSmis1);
        c.expect_not_greater_variance(f, kSmis4, kSmis2);
        c.expect_greater_variance(f, kSmis1, kSmis4);
        c.expect_closer_to_cmis_b(f, kSmis4, kSmis1);
        c.expect_not_greater_variance(f, kCmisB, kSmis1);  // eq. (9) is optimal among one-sample CMIS
    }
}

// (e) "the CMIS_u and SMIS_1 estimators perform the same ... increasing the number of samples pairs n
// in SMIS_n improves its performance asymptotically toward the optimal CMIS_b." Also the negative
// control: a random estimate of p(x) in the DENOMINATOR (NAIVE_4) is biased, and the test sees it.
TEST(MisFig2, ConfigE_CmisUniformEqualsSmis1_SmisApproachesCmisB) {
    Config c(PdfId::E);
    c.common_checks();
    for (IntegrandId f : kIntegrands) {
        c.expect_equal_variance(f, kCmisU, kSmis1);
        c.expect_not_greater_variance(f, kSmis2, kSmis1);
        c.expect_not_greater_variance(f, kSmis4, kSmis2);
        c.expect_greater_variance(f, kSmis1, kSmis4);
        c.expect_closer_to_cmis_b(f, kSmis4, kSmis1);
        c.expect_not_greater_variance(f, kCmisB, kSmis1);
        c.expect_biased_upwards(f, kNaive4);
    }
}

// (e) with p(t) = 1: CMIS_u and SMIS_1 are literally the same expression, f(x) / p(x|t): equal value
// realization by realization from the same random numbers.
TEST(MisFig2, ConfigE_CmisUniformIsSmis1RealizationByRealization) {
    JointPdf p(PdfId::E);
    for (IntegrandId f : kIntegrands) {
        Rng a(77, 1), b(77, 1);
        for (int i = 0; i < 10000; ++i) ASSERT_DOUBLE_EQ(realize(kCmisU, p, f, a), realize(kSmis1, p, f, b)) << i;
    }
}

// Equal-sample-count runs, as in the paper's plots: an N-sample estimate averages N/n realizations, and
// its variance is v / N. Checked on N = 16 runs in the star configuration (f1, e) against quadrature
// (CMIS_u, CMIS_b, SMIS_1) and against a per-realization measurement (SMIS_4).
TEST(MisFig2, EqualSampleCountRunsMatchPerSampleVariance) {
    const int N = 16, runs = 20000;
    const PdfId pid = PdfId::E;
    const IntegrandId f = IntegrandId::F1;
    JointPdf p(pid);
    Exact ex = exact_variances(p, f);
    int checks = 0;
    for (const Estimator& e : {kCmisU, kCmisB, kSmis1, kSmis4}) {
        Rng rng(seed_of(pid, f, e, 1), 3);
        std::vector<double> est(runs);
        for (double& x : est) x = estimate(e, p, f, N, rng);
        Measured run = measure_values(est, 1);  // run.v: variance of the N-sample estimate
        Measured ref{};
        if (e.method == Method::CmisU) ref.v = ex.cmis_u;
        else if (e.method == Method::CmisB) ref.v = ex.cmis_b;
        else if (e.n == 1) ref.v = ex.smis_1;
        else ref = measure(pid, f, e, kSamples, 2);
        ++checks;
        double z = (run.v - ref.v / N) / std::hypot(run.v_se, ref.v_se / N);
        EXPECT_GE(stats::two_sided_p_value(z), kAlpha) << e.name() << ": variance of " << N << "-sample runs "
                                                       << run.v << " +- " << run.v_se << " vs v / N = " << ref.v / N;
        ++checks;
        EXPECT_GE(stats::z_test(run.mean, kIntegral, run.mean_se).p_value, kAlpha) << e.name() << " run mean " << run.mean;
    }
    EXPECT_LE(checks, kChecksRuns);
}

}  // namespace
