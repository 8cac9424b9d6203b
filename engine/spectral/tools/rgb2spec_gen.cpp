// Build-time generator of the Jakob-Hanika coefficient table (our own optimiser, spectral/sigmoid_fit.cpp).
// Layout as in JH 2019: for each index of the largest RGB component l, a res^3 grid over
// (z = that component, warped by smoothstep(smoothstep(.)), x, y = the two others divided by z).
// Each fit is warm-started from its neighbour along z, walking outwards from z = scale[res / 5].
// Usage: smis_rgb2spec_gen RES OUTPUT.inc
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

#include "spectral/sigmoid.h"

using namespace smis::spectral;

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s RES OUTPUT\n", argv[0]);
        return 1;
    }
    const int res = std::atoi(argv[1]);
    if (res < 4 || res > 128) return 1;
    std::vector<double> scale(res);
    auto smoothstep = [](double x) { return x * x * (3.0 - 2.0 * x); };
    for (int k = 0; k < res; ++k) scale[k] = smoothstep(smoothstep(double(k) / double(res - 1)));
    std::vector<float> out(size_t(3) * res * res * res * 3);
    double worst = 0.0;
    auto fit_column = [&](int l, int i, int j, double* worst_out) {
        double x = double(i) / double(res - 1), y = double(j) / double(res - 1);
        auto run = [&](int k, double c[3]) {
            double z = scale[k], rgb[3];
            rgb[l] = z;
            rgb[(l + 1) % 3] = x * z;
            rgb[(l + 2) % 3] = y * z;
            double err = fit_sigmoid(rgb, c, 100);
            if (z > 1e-3) *worst_out = std::max(*worst_out, err);
            float* dst = &out[((((size_t(l) * res + k) * res + j) * res + i) * 3)];
            for (int m = 0; m < 3; ++m) dst[m] = float(c[m]);
        };
        int start = res / 5;
        double c[3] = {0.0, 0.0, 0.0};
        for (int k = start; k < res; ++k) run(k, c);
        c[0] = c[1] = c[2] = 0.0;
        double c0[3];
        const float* s = &out[((((size_t(l) * res + start) * res + j) * res + i) * 3)];
        for (int m = 0; m < 3; ++m) c0[m] = s[m];
        for (int k = start - 1; k >= 0; --k) run(k, c0);
    };
    unsigned threads = std::max(1u, std::min(2u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    std::vector<double> worst_per(threads, 0.0);
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (int idx = int(t); idx < 3 * res * res; idx += int(threads))
                fit_column(idx / (res * res), (idx / res) % res, idx % res, &worst_per[t]);
        });
    for (auto& th : pool) th.join();
    for (double w : worst_per) worst = std::max(worst, w);

    FILE* f = std::fopen(argv[2], "w");
    if (!f) return 1;
    std::fprintf(f, "// GENERATED at build time by spectral/tools/rgb2spec_gen.cpp; worst CIELAB residual %.3g\n", worst);
    std::fprintf(f, "constexpr int kRgb2SpecRes = %d;\nconst float kRgb2SpecScale[] = {", res);
    for (int k = 0; k < res; ++k) std::fprintf(f, "%a,", scale[k]);
    std::fprintf(f, "};\nconst float kRgb2SpecCoeffs[] = {\n");
    for (size_t n = 0; n < out.size(); ++n) std::fprintf(f, "%a,%s", out[n], n % 12 == 11 ? "\n" : "");
    std::fprintf(f, "};\n");
    std::fclose(f);
    std::printf("rgb2spec table %d^3 written, worst CIELAB residual %.3g\n", res, worst);
    return 0;
}
