#pragma once
#include "integrators/integrator.h"
#include "spectral/spectral_scene.h"
#include "spectral/wavelength_sampling.h"

namespace smis {

// Spectral path tracer (paper §5): the path tracer of path_tracing.h conditioned on one wavelength
// and evaluating every BSDF and light at all n wavelengths of its WavelengthSet, combined by the
// strategy's weights (spectral/wavelength_sampling.h). Directions are sampled exactly as in RGB
// rendering (the lobe choice uses the RGB weights), so p(x | lambda) only depends on lambda at
// dispersive Dirac events, which the per-wavelength relative densities r_j track.
class SpectralPathIntegrator : public PixelIntegrator {
public:
    // fixed_wavelength > 0: every path at that wavelength alone, its radiance in every channel
    // (RenderSettings::spectral_wavelength; `mode` and `wavelengths` are then unused).
    SpectralPathIntegrator(const Scene& scene, spectral::SpectralMode mode, int wavelengths,
                           float fixed_wavelength = 0.0f);
    std::map<std::string, double> stats() const override;

protected:
    // A wavelength offset from rng (a lone camera ray)...
    Color Li(const Scene& scene, const RenderSettings& settings, Ray ray, Rng& rng,
             LocalCounters& counters) const override;
    // ... or stratified over the samples of the pixel (settings.spectral_pixel_sequence).
    Color pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray, Rng& rng,
                       LocalCounters& counters) const override;

private:
    // The path for the wavelength set of offset `u` and conditioning choice `v` (WavelengthSampler);
    // the modes' other wavelength draws come from `wavelength_rng`, the path's from `rng`.
    Color trace(const Scene& scene, const RenderSettings& settings, Ray ray, float u, float v, Rng& wavelength_rng,
                Rng& rng, LocalCounters& counters) const;

    spectral::SpectralScene spectral_;
    spectral::WavelengthSampler sampler_;
    float fixed_wavelength_;
};

}  // namespace smis
