// RGB -> spectrum upsampling (Jakob & Hanika 2019). A colour's coefficients come from the table our
// optimiser computes at build time (tools/rgb2spec_gen.cpp), then a few Gauss-Newton iterations from
// that start make the round trip exact for this colour. Scenes upsample their colours once, when the
// spectral integrator is set up, never per ray.
#pragma once
#include "spectral/sigmoid.h"

namespace smis::spectral {

// Table lookup only (trilinear in the JH 2019 parametrisation); rgb in [0, 1]^3.
SigmoidPolynomial rgb_to_sigmoid_table(const Color& rgb);
// Table lookup refined by Gauss-Newton for this colour; rgb is clamped to [0, 1]^3.
SigmoidPolynomial rgb_to_sigmoid(const Color& rgb);

// A spectrum from an RGB colour: scale * sigmoid polynomial. Bounded colours (reflectances, all
// channels <= 1) use scale 1; larger ones are fitted at half their maximum and scaled by twice it,
// as JH 2019 §4.2 does for unbounded and emission spectra, so the sigmoid stays well inside (0, 1).
struct RgbSpectrum {
    SigmoidPolynomial poly;
    float scale = 1.0f;
    float operator()(float lambda) const { return scale * poly(lambda); }
};
RgbSpectrum rgb_spectrum(const Color& rgb);
// The same from the table alone, cheap enough per hit (textured colours); not refined, so its round
// trip error is the table's (up to a few 1e-2 for saturated colours).
RgbSpectrum rgb_spectrum_table(const Color& rgb);

}  // namespace smis::spectral
