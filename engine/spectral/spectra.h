// Spectra the scene is made of: emitters (RGB colours upsampled as illuminants, blackbodies, CIE
// illuminants), measured conductors (complex IOR) and dispersive dielectrics (Sellmeier / Abbe).
#pragma once
#include <string>

#include "spectral/rgb_to_spectrum.h"
#include "spectral/tables.h"

namespace smis::spectral {

enum class EmitterKind { Rgb, Blackbody, D65, A, F2, F10, F11 };
// Accepts Blender's enum names RGB, BLACKBODY, D65, A, F2, F10, F11; false for anything else.
bool parse_emitter_kind(const std::string& name, EmitterKind* kind);

// Planck's law, spectral radiance in W / (sr m^2 nm) at lambda (nm) and temperature T (K).
double blackbody(double lambda_nm, double temperature);

// Emitted spectral radiance per unit luminance (its ybar-weighted integral / int ybar is 1). A light
// of RGB radiance L then emits lum(L) * s(lambda): a spectrum keeps the luminance, hence Blender's
// strength units, of the RGB light it replaces; its colour (the light's RGB) only scales it by its
// luminance. RGB emitters are the JH upsampling of their colour times D65 (the white of the RGB
// space), so an RGB light renders the same colour spectrally as in RGB.
class EmitterSpectrum {
public:
    EmitterSpectrum() = default;
    EmitterSpectrum(EmitterKind kind, const Color& rgb, float temperature);
    // An RGB emitter fitted per hit (emission that is no light's, so has no spectrum of its own: a
    // strand's): the table's coefficients, and the normalisation from the colour's luminance,
    // lum(rgb) Y(D65) (the upsampled reflectance under D65 has the colour's luminance, up to the
    // table's round trip), instead of the constructor's fit and luminance integral.
    static EmitterSpectrum upsampled(const Color& rgb);
    float operator()(float lambda) const { return norm_ * raw(lambda); }
    EmitterKind kind() const { return kind_; }

private:
    float raw(float lambda) const;
    EmitterKind kind_ = EmitterKind::D65;
    RgbSpectrum rgb_;
    const tables::UniformTable* table_ = &tables::illum_D65;
    float temperature_ = 6500.0f;
    float norm_ = 1.0f;
};

// Luminance of a spectrum: sum over the 1 nm grid of s ybar / int ybar.
template <class F>
double spectrum_luminance(const F& s) {
    double sum = 0.0;
    for (int k = 0; k < kTableSamples; ++k) sum += double(s(kLambdaMin + float(k))) * tables::cie_y.values[k];
    return sum / kCieYIntegral;
}

// Measured conductor (tables: Au, Ag, Cu, Al); nullptr for an unknown name.
const tables::MetalTable* find_metal(const std::string& name);
struct ComplexIor {
    float n = 1.0f, k = 0.0f;
};
ComplexIor metal_ior(const tables::MetalTable& metal, float lambda);
// Unpolarised Fresnel reflectance of a conductor n + ik for the cosine cos_i (from the dielectric side).
float fresnel_conductor(float cos_i, ComplexIor eta);

// Wavelength-dependent IOR of a dielectric: a Sellmeier glass from the table, or a Cauchy law
// n(l) = A + B / l^2 through (n_d, V_d) at the Fraunhofer d, F, C lines (587.56, 486.13, 656.27 nm).
class Dispersion {
public:
    Dispersion() = default;
    static bool sellmeier(const std::string& glass, Dispersion* out);  // false: unknown glass
    static Dispersion abbe(float n_d, float v_d);
    bool active() const { return kind_ != Kind::None; }
    float eta(float lambda) const;

private:
    enum class Kind { None, Sellmeier, Cauchy } kind_ = Kind::None;
    float B_[3] = {0, 0, 0}, C_[3] = {0, 0, 0};
    float cauchy_a_ = 1.5f, cauchy_b_ = 0.0f;
};

}  // namespace smis::spectral
