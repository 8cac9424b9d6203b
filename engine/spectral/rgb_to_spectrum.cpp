#include "spectral/rgb_to_spectrum.h"

#include <algorithm>

namespace smis::spectral {

namespace {
#include "rgb2spec_table.inc"

const float* coeffs_at(int l, int z, int y, int x) {
    return &kRgb2SpecCoeffs[((((size_t(l) * kRgb2SpecRes + z) * kRgb2SpecRes + y) * kRgb2SpecRes + x) * 3)];
}

// Grey: the exact constant spectrum (the polynomial degenerates to c2, +-inf for white and black).
SigmoidPolynomial grey(float v) {
    SigmoidPolynomial p;
    if (v <= 0.0f) p.c2 = -kInf;
    else if (v >= 1.0f) p.c2 = kInf;
    else p.c2 = (v - 0.5f) / std::sqrt(v * (1.0f - v));
    return p;
}

Color clamp01(const Color& c) { return vmin(vmax(c, Color(0.0f)), Color(1.0f)); }
}  // namespace

SigmoidPolynomial rgb_to_sigmoid_table(const Color& rgb_in) {
    Color rgb = clamp01(rgb_in);
    if (rgb.x == rgb.y && rgb.y == rgb.z) return grey(rgb.x);
    int l = rgb.x >= rgb.y && rgb.x >= rgb.z ? 0 : (rgb.y >= rgb.z ? 1 : 2);
    const int res = kRgb2SpecRes;
    float z = rgb[l];
    float x = rgb[(l + 1) % 3] * float(res - 1) / z, y = rgb[(l + 2) % 3] * float(res - 1) / z;
    int xi = std::min(int(x), res - 2), yi = std::min(int(y), res - 2);
    int zi = int(std::upper_bound(kRgb2SpecScale, kRgb2SpecScale + res, z) - kRgb2SpecScale) - 1;
    zi = std::max(0, std::min(zi, res - 2));
    float dx = x - float(xi), dy = y - float(yi);
    float dz = (z - kRgb2SpecScale[zi]) / (kRgb2SpecScale[zi + 1] - kRgb2SpecScale[zi]);
    float c[3];
    for (int m = 0; m < 3; ++m) {
        auto at = [&](int a, int b, int d) { return coeffs_at(l, zi + d, yi + b, xi + a)[m]; };
        auto lx = [&](int b, int d) { return at(0, b, d) * (1.0f - dx) + at(1, b, d) * dx; };
        auto ly = [&](int d) { return lx(0, d) * (1.0f - dy) + lx(1, d) * dy; };
        c[m] = ly(0) * (1.0f - dz) + ly(1) * dz;
    }
    return {c[0], c[1], c[2]};
}

SigmoidPolynomial rgb_to_sigmoid(const Color& rgb_in) {
    Color rgb = clamp01(rgb_in);
    if (rgb.x == rgb.y && rgb.y == rgb.z) return grey(rgb.x);
    SigmoidPolynomial start = rgb_to_sigmoid_table(rgb);
    double target[3] = {rgb.x, rgb.y, rgb.z}, c[3] = {start.c0, start.c1, start.c2};
    double err = fit_sigmoid(target, c);
    if (err > 1e-4) {
        // The table's start was in the wrong basin (saturated corners): fit from the flat spectrum.
        double fresh[3] = {0.0, 0.0, 0.0};
        if (fit_sigmoid(target, fresh, 400) < err) std::copy(fresh, fresh + 3, c);
    }
    return {float(c[0]), float(c[1]), float(c[2])};
}

namespace {

template <class Fit>
RgbSpectrum scaled_spectrum(const Color& rgb_in, Fit&& fit) {
    Color rgb = vmax(is_finite(rgb_in) ? rgb_in : Color(0.0f), Color(0.0f));
    float m = max_component(rgb);
    RgbSpectrum s;
    if (m <= 1.0f) {
        s.poly = fit(rgb);
    } else {
        s.scale = 2.0f * m;
        s.poly = fit(rgb / s.scale);
    }
    return s;
}

}  // namespace

RgbSpectrum rgb_spectrum(const Color& rgb) { return scaled_spectrum(rgb, rgb_to_sigmoid); }
RgbSpectrum rgb_spectrum_table(const Color& rgb) { return scaled_spectrum(rgb, rgb_to_sigmoid_table); }

}  // namespace smis::spectral
