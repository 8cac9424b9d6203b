#include <array>
#include <vector>

#include "spectral/sigmoid.h"
#include "spectral/tables.h"

namespace smis::spectral {

namespace {

// The optimiser works in double on the 1 nm grid: RGB(s) = sum_k s(x_k) w_k with
// w_k = M (xbar, ybar, zbar)(l_k) D65(l_k) / sum_k D65(l_k) ybar(l_k).
struct FitGrid {
    std::array<double, kTableSamples> x;
    std::array<std::array<double, 3>, kTableSamples> w;
    FitGrid() {
        double norm = 0.0;
        std::array<double, kTableSamples> d65{};
        for (int k = 0; k < kTableSamples; ++k) {
            float lambda = kLambdaMin + float(k);
            d65[k] = tables::illum_D65.values[int(lambda - tables::illum_D65.lambda0)];
            norm += d65[k] * tables::cie_y.values[k];
        }
        for (int k = 0; k < kTableSamples; ++k) {
            x[k] = double(k) / double(kTableSamples - 1);
            double X = tables::cie_x.values[k], Y = tables::cie_y.values[k], Z = tables::cie_z.values[k];
            double s = d65[k] / norm;
            w[k] = {s * (3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z),
                    s * (-0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z),
                    s * (0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z)};
        }
    }
};

const FitGrid& grid() {
    static const FitGrid g;
    return g;
}

double sigmoid_d(double z) {
    if (std::isinf(z)) return z > 0.0 ? 1.0 : 0.0;
    return 0.5 + z / (2.0 * std::sqrt(1.0 + z * z));
}

void spectrum_rgb(const double c[3], double out[3]) {
    const FitGrid& g = grid();
    out[0] = out[1] = out[2] = 0.0;
    for (int k = 0; k < kTableSamples; ++k) {
        double s = sigmoid_d((c[0] * g.x[k] + c[1]) * g.x[k] + c[2]);
        for (int i = 0; i < 3; ++i) out[i] += s * g.w[k][i];
    }
}

void rgb_to_lab(const double rgb[3], double lab[3]) {
    double X = 0.4124564 * rgb[0] + 0.3575761 * rgb[1] + 0.1804375 * rgb[2];
    double Y = 0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2];
    double Z = 0.0193339 * rgb[0] + 0.1191920 * rgb[1] + 0.9503041 * rgb[2];
    auto f = [](double t) {
        constexpr double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
    };
    // White point: the XYZ of RGB (1, 1, 1).
    double fx = f(X / 0.9504700), fy = f(Y / 1.0000001), fz = f(Z / 1.0888300);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

// Target CIELAB minus the spectrum's, and its norm.
double residual(const double target_lab[3], const double c[3], double r[3]) {
    double rgb[3], lab[3];
    spectrum_rgb(c, rgb);
    rgb_to_lab(rgb, lab);
    for (int i = 0; i < 3; ++i) r[i] = target_lab[i] - lab[i];
    return std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

// Solves A d = b for 3x3 A by Cramer's rule; false when A is (numerically) singular.
bool solve3(const double A[3][3], const double b[3], double d[3]) {
    auto det3 = [](const double m[3][3]) {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    };
    double det = det3(A);
    if (!(std::fabs(det) > 1e-300) || !std::isfinite(det)) return false;
    for (int col = 0; col < 3; ++col) {
        double m[3][3];
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) m[i][j] = j == col ? b[i] : A[i][j];
        d[col] = det3(m) / det;
    }
    return std::isfinite(d[0]) && std::isfinite(d[1]) && std::isfinite(d[2]);
}

}  // namespace

double fit_sigmoid(const double rgb[3], double c[3], int max_iterations) {
    double target[3];
    rgb_to_lab(rgb, target);
    double r[3];
    double err = residual(target, c, r);
    for (int it = 0; it < max_iterations && err > 1e-7; ++it) {
        // Jacobian of the spectrum's CIELAB by central differences.
        double J[3][3];
        for (int j = 0; j < 3; ++j) {
            constexpr double h = 1e-5;
            double cp[3] = {c[0], c[1], c[2]}, cm[3] = {c[0], c[1], c[2]}, rp[3], rm[3];
            cp[j] += h;
            cm[j] -= h;
            residual(target, cp, rp);
            residual(target, cm, rm);
            for (int i = 0; i < 3; ++i) J[i][j] = (rm[i] - rp[i]) / (2.0 * h);  // d(lab)/dc = -d(r)/dc
        }
        double d[3];
        if (!solve3(J, r, d)) break;
        double trial[3] = {c[0] + d[0], c[1] + d[1], c[2] + d[2]};
        // Keep the polynomial in the range where the sigmoid is not saturated in double (JH 2019 bound
        // the coefficients the same way); a damped step is tried when the full step does not improve.
        double m = std::max(std::fabs(trial[0]), std::max(std::fabs(trial[1]), std::fabs(trial[2])));
        if (m > 200.0)
            for (double& v : trial) v *= 200.0 / m;
        double rt[3];
        double et = residual(target, trial, rt);
        // Backtracking: halve the step until the residual decreases.
        for (double step = 0.5; !(et < err) && step > 1e-3; step *= 0.5) {
            for (int j = 0; j < 3; ++j) trial[j] = c[j] + step * d[j];
            et = residual(target, trial, rt);
        }
        if (!(et < err)) break;
        for (int j = 0; j < 3; ++j) c[j] = trial[j], r[j] = rt[j];
        err = et;
    }
    return err;
}

Color sigmoid_reflectance_rgb(const SigmoidPolynomial& p) {
    // The engine's own float evaluation of the spectrum, summed in double.
    const FitGrid& g = grid();
    double rgb[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < kTableSamples; ++k) {
        double s = p(kLambdaMin + float(k));
        for (int i = 0; i < 3; ++i) rgb[i] += s * g.w[k][i];
    }
    return {float(rgb[0]), float(rgb[1]), float(rgb[2])};
}

}  // namespace smis::spectral
