// Jakob & Hanika 2019, "A Low-Dimensional Function Space for Efficient Spectral Upsampling": a
// reflectance spectrum is the sigmoid of a quadratic polynomial, s(l) = S(c0 x^2 + c1 x + c2) with
// S(z) = 1/2 + z / (2 sqrt(1 + z^2)) and x = (l - 360) / 470 the normalised wavelength. Its three
// coefficients are found by Gauss-Newton in CIELAB (JH 2019 §3) so that the spectrum, lit by D65,
// has the wanted RGB.
#pragma once
#include <cmath>

#include "core/math.h"
#include "spectral/color.h"

namespace smis::spectral {

inline float sigmoid(float z) {
    if (std::isinf(z)) return z > 0.0f ? 1.0f : 0.0f;  // the limits of black and white
    return 0.5f + z / (2.0f * std::sqrt(1.0f + z * z));
}

struct SigmoidPolynomial {
    float c0 = 0.0f, c1 = 0.0f, c2 = 0.0f;  // in the normalised wavelength x
    float operator()(float lambda) const {
        float x = (lambda - kLambdaMin) * (1.0f / kLambdaRange);
        return sigmoid((c0 * x + c1) * x + c2);
    }
};

// Gauss-Newton fit of the coefficients c (in/out: start value in, result out) to the linear Rec.709
// colour rgb (each channel in [0, 1]), minimising the CIELAB distance of the spectrum's colour under
// D65. Returns the final CIELAB residual (Euclidean, Delta E 1976).
double fit_sigmoid(const double rgb[3], double c[3], int max_iterations = 40);

// Linear RGB of the reflectance spectrum p under D65 (the quantity fit_sigmoid matches), by the same
// 1 nm rectangle sum the optimiser uses.
Color sigmoid_reflectance_rgb(const SigmoidPolynomial& p);

}  // namespace smis::spectral
