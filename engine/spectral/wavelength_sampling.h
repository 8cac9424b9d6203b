// Wavelength sampling strategies for spectral path tracing (paper §5, eq. 18-21): which wavelengths
// a path evaluates, which one conditions its sampling, and the weights that combine them.
//
// Every strategy draws n wavelengths l_1..l_n and a conditioning index c; the path x is sampled as if
// rendered at l_c and evaluated at all n wavelengths. Let r_j = p(x | l_j) / p(x | l_c) be the
// densities of x relative to the conditioning wavelength (all 1 unless a dispersive event made x
// depend on the wavelength). The contribution of wavelength i, with beta_i = f(x, l_i) / p(x | l_c), is
//     beta_i * W_i,   W_i = 1 / (q_i * sum_j a_j r_j),
// which covers the estimators of the paper:
//   * UNIFORM, SPECTRAL_IS: n = 1, q = p(l), a = 1 (plain one-wavelength Monte Carlo);
//   * HERO (eq. 19, Wilkie et al. 2014): l_c = hero ~ p(l), the others rotated by k / n of the range;
//     balance heuristic over the n rotations: q_i = 1, a_j = p(l_j);
//   * SMIS (eq. 21): l_i = P^-1((i + u) / n) (a stratified pattern warped by the CDF of p: one
//     offset u shifts the n strata together, a rotated rank-1 lattice), c uniform, balance heuristic
//     over the n: q_i = p(l_i), a_j = 1; since every technique has the same marginal p(l) the 1/n of
//     eq. (11) cancels (mis/smis.h, NORMALISATION);
//   * SMIS_INDEPENDENT: the same with n independent wavelengths (SMIS_i in the paper);
//   * BRUTE_FORCE: 512 wavelengths jittered in their own strata of the CDF of p (the reference).
// The offset u (SMIS's lattice shift, the hero of HERO, the single wavelength of UNIFORM and
// SPECTRAL_IS) and the number v that picks the conditioning index c = floor(v n) are the caller's:
// any independent numbers uniform on [0, 1) keep every mode unbiased (v only through floor(v n)),
// and the path tracer correlates them over a pixel's samples so that the wavelengths of successive
// samples stratify (all n of them, and the conditioning ones alone, which are all that survives a
// dispersive refraction): SpectralPathIntegrator::pixel_sample. Why the shared lattice shift and the pixel sequence: docs/bench/spectral_summary.md
// (they cut SMIS's excess colour variance over BRUTE_FORCE on the Fig. 8 scene).
// When a dispersive refraction makes x valid for l_c only, r_j = 0 for j != c and the estimator keeps
// l_c alone with W_c = 1 / (q_c a_c): unbiased because x was drawn from the mixture over c that the
// balance denominator describes (uniform c for SMIS; for HERO the hero's posterior among the rotations).
#pragma once
#include <string>
#include <vector>

#include "core/rng.h"
#include "spectral/color.h"

namespace smis::spectral {

enum class SpectralMode { Rgb, Uniform, SpectralIs, Hero, Smis, SmisIndependent, BruteForce };
// RGB, UNIFORM, SPECTRAL_IS, HERO, SMIS, SMIS_INDEPENDENT, BRUTE_FORCE (for messages; the setting's
// names are the settings table's, render_settings.h).
const char* spectral_mode_name(SpectralMode mode);

constexpr int kMaxWavelengths = 512;
constexpr int kBruteForceWavelengths = 512;

// Piecewise-constant density over [360, 830] nm in 1 nm bins, sampled by inverting its CDF.
class WavelengthPdf {
public:
    WavelengthPdf();  // uniform
    explicit WavelengthPdf(const std::vector<double>& bin_weights);  // kBins non-negative weights
    static constexpr int kBins = int(kLambdaRange);
    // The wavelength at CDF value u, always inside the bin whose CDF interval holds u; `density`
    // (if given) receives that bin's density, the one the sample was drawn with. Callers use it
    // rather than pdf(sample(u)): the two agree because the wavelength is kept off the bin's upper
    // edge, but the sampled density is what the estimators' weights must use.
    float sample(float u, float* density = nullptr) const;
    float pdf(float lambda) const;

private:
    std::vector<float> density_;
    std::vector<double> cdf_;
};

struct WavelengthSet {
    int n = 0, conditioning = 0;
    float lambda[kMaxWavelengths];
    float q[kMaxWavelengths];
    float a[kMaxWavelengths];
};

class WavelengthSampler {
public:
    // n is the number of wavelengths per path for HERO / SMIS / SMIS_INDEPENDENT (clamped to
    // [1, kMaxWavelengths]); UNIFORM and SPECTRAL_IS use 1, BRUTE_FORCE 512.
    WavelengthSampler(SpectralMode mode, int n, WavelengthPdf importance);
    int count() const { return n_; }
    SpectralMode mode() const { return mode_; }
    const WavelengthPdf& importance() const { return importance_; }
    // True when the wavelengths are a function of (u, v) alone (UNIFORM, SPECTRAL_IS, HERO, SMIS), so
    // correlating u, v over a pixel's samples stratifies them. BRUTE_FORCE (the reference, kept as
    // defined) and SMIS_INDEPENDENT (independent by definition) draw theirs from rng.
    bool follows_offsets() const {
        return mode_ != SpectralMode::BruteForce && mode_ != SpectralMode::SmisIndependent;
    }
    // `u`, `v`: the pattern's offset and the conditioning choice, uniform on [0, 1) (see above);
    // `rng` draws the rest (BRUTE_FORCE's jitter, SMIS_INDEPENDENT's wavelengths).
    void sample(float u, float v, Rng& rng, WavelengthSet* set) const;

private:
    SpectralMode mode_;
    int n_;
    WavelengthPdf importance_, uniform_;
};

}  // namespace smis::spectral
