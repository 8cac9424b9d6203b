#include "spectral/wavelength_sampling.h"

#include <algorithm>
#include <cmath>

namespace smis::spectral {

namespace {
const std::pair<const char*, SpectralMode> kModeNames[] = {
    {"RGB", SpectralMode::Rgb},   {"UNIFORM", SpectralMode::Uniform},
    {"SPECTRAL_IS", SpectralMode::SpectralIs}, {"HERO", SpectralMode::Hero},
    {"SMIS", SpectralMode::Smis}, {"SMIS_INDEPENDENT", SpectralMode::SmisIndependent},
    {"BRUTE_FORCE", SpectralMode::BruteForce}};

constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
}  // namespace

const char* spectral_mode_name(SpectralMode mode) {
    for (auto& [n, m] : kModeNames)
        if (m == mode) return n;
    return "?";
}

WavelengthPdf::WavelengthPdf() : WavelengthPdf(std::vector<double>(kBins, 1.0)) {}

WavelengthPdf::WavelengthPdf(const std::vector<double>& w) {
    density_.assign(kBins, 0.0f);
    cdf_.assign(kBins + 1, 0.0);
    for (int b = 0; b < kBins; ++b) {
        double v = b < int(w.size()) && w[b] > 0.0 && std::isfinite(w[b]) ? w[b] : 0.0;
        cdf_[b + 1] = cdf_[b] + v;
    }
    double total = cdf_.back();
    if (!(total > 0.0)) {  // nothing to importance sample: uniform
        for (int b = 0; b <= kBins; ++b) cdf_[b] = double(b);
        total = kBins;
    }
    for (int b = 0; b <= kBins; ++b) cdf_[b] /= total;
    for (int b = 0; b < kBins; ++b) density_[b] = float(cdf_[b + 1] - cdf_[b]);  // bins are 1 nm wide
}

float WavelengthPdf::sample(float u, float* density) const {
    double t = std::min(double(u), double(kOneMinusEpsilon));
    int b = int(std::upper_bound(cdf_.begin(), cdf_.end(), t) - cdf_.begin()) - 1;
    b = std::max(0, std::min(b, kBins - 1));
    while (density_[b] <= 0.0f && b > 0) --b;  // never land in an empty bin
    double w = cdf_[b + 1] - cdf_[b];
    float f = w > 0.0 ? float(std::min(1.0, std::max(0.0, (t - cdf_[b]) / w))) : 0.5f;
    // 360 + b + f rounds to the next bin's edge when f is within half an ulp of 1 (the ulp near
    // 600 nm is 6e-5), where pdf() would read the neighbour's density: stay below the edge.
    float lower = kLambdaMin + float(b), upper = lower + 1.0f;  // exact: whole numbers
    float lambda = lower + f;
    if (!(lambda < upper)) lambda = std::nextafter(upper, lower);
    if (density) *density = density_[b];
    return lambda;
}

float WavelengthPdf::pdf(float lambda) const {
    float x = lambda - kLambdaMin;
    if (!(x >= 0.0f) || x > kLambdaRange) return 0.0f;
    return density_[std::min(int(x), kBins - 1)];
}

WavelengthSampler::WavelengthSampler(SpectralMode mode, int n, WavelengthPdf importance)
    : mode_(mode), importance_(std::move(importance)) {
    switch (mode) {
        case SpectralMode::Uniform:
        case SpectralMode::SpectralIs:
        case SpectralMode::Rgb: n_ = 1; break;
        case SpectralMode::BruteForce: n_ = kBruteForceWavelengths; break;
        default: n_ = std::max(1, std::min(n, kMaxWavelengths));
    }
}

void WavelengthSampler::sample(float u, float v, Rng& rng, WavelengthSet* s) const {
    const int n = n_;
    s->n = n;
    s->conditioning = 0;
    switch (mode_) {
        case SpectralMode::Rgb:
        case SpectralMode::Uniform:
            s->lambda[0] = uniform_.sample(u, &s->q[0]);
            s->a[0] = 1.0f;
            return;
        case SpectralMode::SpectralIs:
            s->lambda[0] = importance_.sample(u, &s->q[0]);
            s->a[0] = 1.0f;
            return;
        case SpectralMode::Hero: {
            // Eq. (19): the hero from p, the others equally spaced (wrapping around the range). The
            // hero keeps its sampled wavelength and density (the round trip through [0, 1) below
            // could move it across a bin edge); the rotations' densities are p where they land.
            float hero_density;
            float hero_lambda = importance_.sample(u, &hero_density);
            float hero = (hero_lambda - kLambdaMin) / kLambdaRange;
            for (int i = 0; i < n; ++i) {
                float t = hero + float(i) / float(n);
                t -= std::floor(t);
                s->lambda[i] = i == 0 ? hero_lambda : std::min(kLambdaMin + t * kLambdaRange, kLambdaMax);
                s->q[i] = 1.0f;
                s->a[i] = i == 0 ? hero_density : importance_.pdf(s->lambda[i]);
            }
            return;
        }
        case SpectralMode::Smis:
        case SpectralMode::BruteForce:
        case SpectralMode::SmisIndependent: {
            // Eq. (21): n wavelengths from p, the path conditioned on one of them chosen uniformly.
            // SMIS shifts its n strata by the shared offset u; BRUTE_FORCE jitters each stratum on
            // its own; SMIS_INDEPENDENT (SMIS_i) draws n independent wavelengths.
            for (int i = 0; i < n; ++i) {
                float t = mode_ == SpectralMode::Smis ? (float(i) + u) / float(n)
                          : mode_ == SpectralMode::BruteForce ? (float(i) + rng.next_float()) / float(n)
                                                               : rng.next_float();
                s->lambda[i] = importance_.sample(std::min(t, kOneMinusEpsilon), &s->q[i]);
                s->a[i] = 1.0f;
            }
            s->conditioning = std::min(int(v * float(n)), n - 1);
            return;
        }
    }
}

}  // namespace smis::spectral
