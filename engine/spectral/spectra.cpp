#include "spectral/spectra.h"

#include <algorithm>
#include <complex>
#include <cstring>

namespace smis::spectral {

bool parse_emitter_kind(const std::string& name, EmitterKind* kind) {
    static const std::pair<const char*, EmitterKind> names[] = {
        {"RGB", EmitterKind::Rgb}, {"BLACKBODY", EmitterKind::Blackbody}, {"D65", EmitterKind::D65},
        {"A", EmitterKind::A},     {"F2", EmitterKind::F2},               {"F10", EmitterKind::F10},
        {"F11", EmitterKind::F11}};
    for (auto& [n, k] : names)
        if (name == n) return *kind = k, true;
    return false;
}

double blackbody(double lambda_nm, double temperature) {
    constexpr double c = 299792458.0, h = 6.62607015e-34, kb = 1.380649e-23;
    double l = lambda_nm * 1e-9;
    double e = std::exp(h * c / (l * kb * temperature));
    return (2.0 * h * c * c) / (l * l * l * l * l * (e - 1.0)) * 1e-9;
}

EmitterSpectrum::EmitterSpectrum(EmitterKind kind, const Color& rgb, float temperature)
    : kind_(kind), temperature_(temperature) {
    switch (kind) {
        case EmitterKind::Rgb: rgb_ = rgb_spectrum(rgb); break;
        case EmitterKind::A: table_ = &tables::illum_A; break;
        case EmitterKind::F2: table_ = &tables::illum_F2; break;
        case EmitterKind::F10: table_ = &tables::illum_F10; break;
        case EmitterKind::F11: table_ = &tables::illum_F11; break;
        default: break;
    }
    double y = spectrum_luminance([this](float l) { return raw(l); });
    norm_ = y > 0.0 && std::isfinite(y) ? float(1.0 / y) : 0.0f;
}

EmitterSpectrum EmitterSpectrum::upsampled(const Color& rgb) {
    static const double y_d65 = spectrum_luminance([](float l) { return sample_table(tables::illum_D65, l); });
    EmitterSpectrum e;
    e.kind_ = EmitterKind::Rgb;
    const Color c = rgb / std::max(1e-20f, max_component(rgb));
    e.rgb_ = rgb_spectrum_table(c);
    const double y = y_d65 * double(luminance(c));
    e.norm_ = y > 0.0 && std::isfinite(y) ? float(1.0 / y) : 0.0f;
    return e;
}

float EmitterSpectrum::raw(float lambda) const {
    switch (kind_) {
        case EmitterKind::Rgb: return rgb_(lambda) * sample_table(tables::illum_D65, lambda);
        case EmitterKind::Blackbody: return float(blackbody(lambda, temperature_));
        default: return sample_table(*table_, lambda);
    }
}

const tables::MetalTable* find_metal(const std::string& name) {
    for (int i = 0; i < tables::metal_count; ++i)
        if (name == tables::metals[i].name) return &tables::metals[i];
    return nullptr;
}

ComplexIor metal_ior(const tables::MetalTable& m, float lambda) {
    // The tables cover 298-886 nm, a superset of the rendered range; clamp at the ends.
    if (lambda <= m.lambda[0]) return {m.n[0], m.k[0]};
    if (lambda >= m.lambda[m.count - 1]) return {m.n[m.count - 1], m.k[m.count - 1]};
    int i = int(std::upper_bound(m.lambda, m.lambda + m.count, lambda) - m.lambda) - 1;
    float t = (lambda - m.lambda[i]) / (m.lambda[i + 1] - m.lambda[i]);
    return {m.n[i] + t * (m.n[i + 1] - m.n[i]), m.k[i] + t * (m.k[i + 1] - m.k[i])};
}

float fresnel_conductor(float cos_i, ComplexIor eta) {
    // Fresnel equations with a complex IOR (as pbrt-v4's FrComplex): r_s, r_p from the complex cos_t.
    using C = std::complex<float>;
    cos_i = clampf(std::fabs(cos_i), 0.0f, 1.0f);
    C e(eta.n, eta.k);
    float sin2_i = 1.0f - cos_i * cos_i;
    C sin2_t = sin2_i / (e * e);
    C cos_t = std::sqrt(C(1.0f) - sin2_t);
    C r_parl = (e * cos_i - cos_t) / (e * cos_i + cos_t);
    C r_perp = (cos_i - e * cos_t) / (cos_i + e * cos_t);
    float f = 0.5f * (std::norm(r_parl) + std::norm(r_perp));
    return std::isfinite(f) ? clampf(f, 0.0f, 1.0f) : 1.0f;
}

bool Dispersion::sellmeier(const std::string& glass, Dispersion* out) {
    for (int i = 0; i < tables::glass_count; ++i) {
        const tables::SellmeierGlass& g = tables::glasses[i];
        if (glass != g.name) continue;
        out->kind_ = Kind::Sellmeier;
        std::memcpy(out->B_, g.B, sizeof(g.B));
        std::memcpy(out->C_, g.C, sizeof(g.C));
        return true;
    }
    return false;
}

Dispersion Dispersion::abbe(float n_d, float v_d) {
    constexpr float ld = 0.58756f, lf = 0.48613f, lc = 0.65627f;  // micrometres
    Dispersion d;
    d.kind_ = Kind::Cauchy;
    // n_F - n_C = (n_d - 1) / V_d = B (1/lf^2 - 1/lc^2).
    d.cauchy_b_ = (n_d - 1.0f) / (v_d * (1.0f / (lf * lf) - 1.0f / (lc * lc)));
    d.cauchy_a_ = n_d - d.cauchy_b_ / (ld * ld);
    return d;
}

float Dispersion::eta(float lambda) const {
    float l = lambda * 1e-3f, l2 = l * l;
    switch (kind_) {
        case Kind::Sellmeier: {
            float n2 = 1.0f;
            for (int i = 0; i < 3; ++i) n2 += B_[i] * l2 / (l2 - C_[i]);
            return std::sqrt(std::max(n2, 1e-4f));
        }
        case Kind::Cauchy: return cauchy_a_ + cauchy_b_ / l2;
        case Kind::None: break;
    }
    return 1.0f;
}

}  // namespace smis::spectral
