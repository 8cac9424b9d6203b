#pragma once
#include "integrators/integrator.h"
#include "spectral/spectral_scene.h"
#include "spectral/wavelength_sampling.h"

namespace smis {

struct CandidateEval;
struct RestirPixel;
struct SpectralRestirRecord;

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

    // ReSTIR on spectral paths (restir.cpp). The wavelengths each path carries.
    int wavelength_count() const;
    // Pixel sample s's path as pixel_sample traces it, but with its first non-specular vertex's
    // direct light left out: that vertex is recorded into `vertex` (shading point, medium, camera
    // distance, its initial RIS reservoir, as RestirIntegrator's RGB stage 1 does) and the path's
    // weight there into lambda[i] and weight[i], i < wavelength_count(): wavelength i's radiance
    // counts as weight[i] times it in RGB. Returns the radiance of the rest of the path.
    Color trace_restir_pixel(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray,
                             Sampler& sampler, LocalCounters& counters, RestirPixel& vertex, float* lambda,
                             Color* weight) const;
    // The direct light at a recorded vertex from light sample e (evaluated at vertex.sp) with
    // resampled weight w (direct_lighting.h, resampled_weight): at each of the path's wavelengths,
    // through its own shadow ray (none without media when `visible`: the reuse traced it), as RGB.
    Color shade_restir_vertex(const Scene& scene, const RestirPixel& vertex, const float* lambda, const Color* weight,
                              const CandidateEval& e, float w, bool visible) const;

protected:
    // A wavelength offset from rng (a lone camera ray)...
    Color Li(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
             LocalCounters& counters) const override;
    // ... or stratified over the samples of the pixel (settings.spectral_pixel_sequence).
    Color pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray,
                       Sampler& sampler, LocalCounters& counters) const override;

private:
    // The path for the wavelength set of offset `u` and conditioning choice `v` (WavelengthSampler);
    // the modes' other wavelength draws come from `wavelength_rng`, the path's from `rng`.
    // `restir`: record the first non-specular vertex for ReSTIR instead of lighting it. `camera`: the
    // pixel sample's Sampler (rng its stream), whose first-vertex numbers the path asks for by name
    // (path_loop.h).
    Color trace(const Scene& scene, const RenderSettings& settings, Ray ray, float u, float v, Rng& wavelength_rng,
                Rng& rng, LocalCounters& counters, SpectralRestirRecord* restir, Sampler* camera) const;
    Color sample_path(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray, Rng& rng,
                      LocalCounters& counters, SpectralRestirRecord* restir, Sampler* camera) const;

    spectral::SpectralScene spectral_;
    spectral::WavelengthSampler sampler_;
    float fixed_wavelength_;
};

}  // namespace smis
