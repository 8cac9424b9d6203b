// The spectral view of a committed Scene, built once when a spectral render starts (RGB renders never
// build it): every light's emission spectrum, every material lobe's weight / f0 upsampled to spectra
// (Jakob-Hanika coefficients stored here, not computed per ray), measured metals, dispersion, and the
// wavelength importance density of the scene.
#pragma once
#include <vector>

#include "scene/scene.h"
#include "spectral/spectra.h"
#include "spectral/wavelength_sampling.h"

namespace smis::spectral {

struct SpectralLobe {
    RgbSpectrum weight, f0;                   // the lobe's RGB weight and Schlick f0 as spectra
    const tables::MetalTable* metal = nullptr;  // replaces the Fresnel of metal-like Microfacet lobes
    Dispersion dispersion;                    // smooth Dielectric lobes of a dispersive material only
    bool varies = false;                      // textured / object colour: weight and f0 come per hit
    // Subsurface lobes: the surface albedo (Lobe::f0) as a reflectance and the mean free path
    // (kind_colour) as an unbounded spectrum, as a medium's albedo and sigma_t (a grey one stays grey).
    RgbSpectrum albedo, radius;
};

struct SpectralMaterial {
    std::vector<SpectralLobe> lobes;  // indexed by Lobe::index
    bool dispersive = false;
};

// A homogeneous medium's coefficients as spectra (the Scene's are RGB, per metre). sigma_t is
// upsampled as an unbounded spectrum (rgb_spectrum: JH 2019 §4.2, fitted at half its largest channel
// and scaled by twice it) and the single-scattering albedo sigma_s / sigma_t per channel as a
// reflectance (bounded by 1), so that sigma_s(l) = albedo(l) sigma_t(l) <= sigma_t(l) at every
// wavelength: the medium never gains energy, and a grey medium (equal channels) stays grey.
struct SpectralMedium {
    RgbSpectrum sigma_t, albedo;
    float sigma_s(float lambda) const { return albedo(lambda) * sigma_t(lambda); }
};

class SpectralScene {
public:
    explicit SpectralScene(const Scene& scene);
    // Emitted spectrum per unit luminance of light `i` (spectral/spectra.h, EmitterSpectrum).
    const EmitterSpectrum& emitter(uint32_t light) const { return emitters_[light_emitter_[light]]; }
    // The spectrum per unit luminance of emission `rgb` found on a strand of material `material` (no
    // light: for_each_emission_along's kStrandLight): the material's emission spectrum or constant
    // colour, fitted once; a colour that varies (a program, a texture) upsampled from the hit's RGB
    // by the table alone (EmitterSpectrum::upsampled: saturated colours' weak channels off by a few
    // per cent, as the spectral lobes' varying colours).
    EmitterSpectrum strand_emitter(uint32_t material, const Color& rgb) const {
        const int32_t fixed = material_emitter_[material];
        return fixed >= 0 ? emitters_[fixed] : EmitterSpectrum::upsampled(rgb);
    }
    const SpectralMaterial& material(uint32_t id) const { return materials_[id]; }
    const SpectralMedium& medium(int32_t id) const { return media_[id]; }
    // p(lambda) proportional to the observer response times the mixture of the lights' spectra
    // weighted by their selection probability (paper §5.2), with `uniform_fraction` of a uniform
    // density mixed in so that p > 0 wherever an integrand can be non-zero. The observer response is
    // the length of the output's RGB response vector |rgb_response(lambda)| (the colour matching
    // functions of the RGB space, negative lobes included): the error is measured in RGB, and it
    // gave 10-20% lower RGB error than xbar + ybar + zbar on the Fig. 8 scene.
    WavelengthPdf importance(float uniform_fraction = 0.05f) const;

private:
    const Scene& scene_;
    std::vector<EmitterSpectrum> emitters_;
    std::vector<uint32_t> light_emitter_;
    std::vector<int32_t> material_emitter_;  // per material: its fitted emitter, or -1 (per hit)
    std::vector<SpectralMaterial> materials_;
    std::vector<SpectralMedium> media_;
};

}  // namespace smis::spectral
