// Data for bench/fig2/fig2.py: the 1D experiment of West et al. 2020, Fig. 2 (configurations and
// estimators in engine/mis/cmis_1d_experiment.h). Single-threaded.
//
//   fig2_variance [--runs R]   CSV on stdout: variance of the N-sample estimate against the total sample
//                              count N (R independent runs per point; each run averages N/n realizations),
//                              for every configuration and estimator (panel "main") and for SMIS_n,
//                              n = 1..64, in the star configuration (f1, e) (panel "f").
//   fig2_variance --per-sample [--samples M]
//                              CSV: per-sample variance v = n Var[realization] (Var at N = v / N) from M
//                              samples per estimator, with standard errors, and the quadrature values.
//   fig2_variance --joint G    CSV: p(t, x) on a G x G grid and the marginals, for the top-row images.
//
// Build: g++ -O2 -std=c++17 -I engine bench/fig2/fig2_variance.cpp -o fig2_variance
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mis/cmis_1d_experiment.h"

using namespace smis;
using namespace smis::mis;
using namespace smis::mis::cmis1d;

namespace {

const PdfId kPdfs[] = {PdfId::B, PdfId::C, PdfId::D, PdfId::E};
const IntegrandId kIntegrands[] = {IntegrandId::F1, IntegrandId::F2};
const std::vector<Estimator> kMain = {{Method::CmisU, 1},     {Method::CmisB, 1},        {Method::Smis, 1},
                                      {Method::Smis, 2},      {Method::Smis, 4},         {Method::SmisStrat, 4},
                                      {Method::SmisPower, 4}, {Method::StochWeight, 4},  {Method::StochWeightF, 4},
                                      {Method::Naive, 4}};

uint64_t seed_of(PdfId p, IntegrandId f, const Estimator& e, uint64_t salt) {
    return mix64((static_cast<uint64_t>(p) << 40) ^ (static_cast<uint64_t>(f) << 32) ^
                 (static_cast<uint64_t>(e.method) << 16) ^ static_cast<uint64_t>(e.n) ^ (salt << 48) ^ 0xf19ull);
}

struct Stats {
    double mean = 0, mean_se = 0, var = 0, var_se = 0;
};
Stats stats_of(const std::vector<double>& x) {
    const double K = static_cast<double>(x.size());
    Stats s;
    for (double a : x) s.mean += a;
    s.mean /= K;
    double m2 = 0, m4 = 0;
    for (double a : x) {
        double d = (a - s.mean) * (a - s.mean);
        m2 += d;
        m4 += d * d;
    }
    s.var = m2 / (K - 1);
    m4 /= K;
    // Delta-method standard error of s^2 plus its second-order term (see engine/tests/mis_fig2_test.cpp).
    s.var_se = std::sqrt(std::max(0.0, (m4 - s.var * s.var * (K - 3) / (K - 1)) / K) + std::pow(6.0 * s.var / K, 2));
    s.mean_se = std::sqrt(s.var / K);
    return s;
}

void variance_vs_n(const char* panel, PdfId pid, IntegrandId f, const Estimator& e, const std::vector<int>& counts,
                   int runs) {
    JointPdf p(pid);
    for (int N : counts) {
        if (N % e.samples() != 0) continue;
        Rng rng(seed_of(pid, f, e, static_cast<uint64_t>(N)), 1);
        std::vector<double> est(runs);
        for (double& x : est) x = estimate(e, p, f, N, rng);
        Stats s = stats_of(est);
        std::printf("%s,%s,%s,%s,%d,%d,%d,%.9g,%.9g,%.9g,%.9g\n", panel, integrand_name(f), pdf_name(pid),
                    e.name().c_str(), e.samples(), N, runs, s.mean, s.mean_se, s.var, s.var_se);
    }
}

void per_sample(long samples) {
    std::printf("integrand,config,estimator,n,realizations,mean,mean_se,per_sample_variance,per_sample_variance_se,"
                "exact_cmis_u,exact_cmis_b,exact_smis_1,smis_large_n_limit\n");
    auto row = [&](PdfId pid, IntegrandId f, const Estimator& e) {
        JointPdf p(pid);
        Exact ex = exact_variances(p, f);
        Rng rng(seed_of(pid, f, e, 999), 2);
        std::vector<double> v(samples / e.samples());
        for (double& x : v) x = realize(e, p, f, rng);
        Stats s = stats_of(v);
        std::printf("%s,%s,%s,%d,%zu,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n", integrand_name(f), pdf_name(pid),
                    e.name().c_str(), e.samples(), v.size(), s.mean, s.mean_se, e.samples() * s.var,
                    e.samples() * s.var_se, ex.cmis_u, ex.cmis_b, ex.smis_1, ex.smis_limit);
        std::fflush(stdout);
    };
    for (IntegrandId f : kIntegrands)
        for (PdfId pid : kPdfs)
            for (const Estimator& e : kMain) row(pid, f, e);
    for (int n : {8, 16, 32, 64}) row(PdfId::E, IntegrandId::F1, {Method::Smis, n});
    for (int n : {1, 2, 8, 16, 32, 64}) row(PdfId::E, IntegrandId::F1, {Method::StochWeight, n});
}

void joint(int grid) {
    std::printf("config,t,x,p_tx,p_t,p_x\n");
    for (PdfId pid : kPdfs) {
        JointPdf p(pid);
        for (int i = 0; i < grid; ++i)
            for (int j = 0; j < grid; ++j) {
                double t = (i + 0.5) / grid, x = (j + 0.5) / grid;
                std::printf("%s,%.6f,%.6f,%.6f,%.6f,%.6f\n", pdf_name(pid), t, x, p.pdf_t(t) * p.pdf_x_given_t(x, t),
                            p.pdf_t(t), p.marginal_x(x));
            }
    }
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 1000;
    long samples = 1L << 20;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--runs") && i + 1 < argc) {
            runs = std::atoi(argv[++i]);
        } else if (!std::strcmp(argv[i], "--samples") && i + 1 < argc) {
            samples = std::atol(argv[++i]);
        } else if (!std::strcmp(argv[i], "--per-sample")) {
            for (int k = i + 1; k + 1 < argc; ++k)
                if (!std::strcmp(argv[k], "--samples")) samples = std::atol(argv[k + 1]);
            per_sample(samples);
            return 0;
        } else if (!std::strcmp(argv[i], "--joint") && i + 1 < argc) {
            joint(std::atoi(argv[i + 1]));
            return 0;
        } else {
            std::fprintf(stderr, "usage: %s [--runs R] | --per-sample [--samples M] | --joint G\n", argv[0]);
            return 2;
        }
    }
    std::printf("panel,integrand,config,estimator,n,N,runs,mean,mean_se,variance,variance_se\n");
    const std::vector<int> counts = {4, 8, 16, 32, 64, 128, 256, 512, 1024};
    for (IntegrandId f : kIntegrands)
        for (PdfId pid : kPdfs)
            for (const Estimator& e : kMain) variance_vs_n("main", pid, f, e, counts, runs);
    for (int n : {1, 2, 4, 8, 16, 32, 64})
        variance_vs_n("f", PdfId::E, IntegrandId::F1, {Method::Smis, n}, {64, 128, 256, 512, 1024}, runs);
    return 0;
}
