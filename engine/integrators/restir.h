// ReSTIR direct lighting (Bitterli et al. 2020) at the camera path's first non-specular vertex, as
// a progressive multi-stage integrator: the path tracer with settings.direct_light = RESTIR.
#pragma once
#include <vector>

#include "integrators/aux_passes.h"
#include "integrators/reservoir_reuse.h"
#include "integrators/spectral_path.h"

namespace smis {

// One pixel's first vertex and its reservoir, kept for the neighbours and for the next iteration.
struct RestirPixel {
    bool has_vertex = false;
    ShadingPoint sp;
    Color beta{0.0f};      // camera prefix throughput up to the vertex
    Color fixed{0.0f};     // everything but the direct light at the vertex (path-traced)
    float transparency = 0.0f;  // Film Transparent: the throughput that reached the World unseen
    float distance = 0.0f; // camera-to-vertex path length, for the neighbour similarity test
    bool camera_hit = false;  // the vertex is the camera ray's hit: its light is Clamp Direct's, else Indirect's
    int32_t medium = kNoMedium;  // the medium the camera path arrived in at the vertex (scenes with media)
    Reservoir r;
    CandidateEval eval;    // r's sample evaluated at sp (when r has one), for the reuse stages
    // The auxiliary passes (when on) as the camera prefix recorded them at its first hit
    // (aux_passes.h), so stage 2 traces no second camera ray where it did.
    FirstHitPasses passes;
};

// Stage 1 of RGB ReSTIR for one pixel sample into px (restir.cpp): the camera prefix to x1, x1's
// initial reservoir, and the rest of the path as px.fixed. `sampler`: the pixel sample's.
void trace_restir_pixel(const Scene& scene, const RenderSettings& settings, const Ray& camera, Sampler& sampler,
                        LocalCounters& counters, RestirPixel& px);

class RestirIntegrator : public IterativeIntegrator {
public:
    RestirIntegrator() = default;
    // On spectral paths: stage 1 traces the spectral path tracer's paths (SpectralPathIntegrator's
    // arguments), the reservoirs resample light samples with their RGB targets as in RGB rendering
    // (a sample and its W are independent of wavelengths), and the shading evaluates the final
    // sample at each of the pixel's wavelengths (direct_lighting.h, resampled_weight).
    RestirIntegrator(const Scene& scene, spectral::SpectralMode mode, int wavelengths, float fixed_wavelength);
    std::map<std::string, double> stats() const override;

private:
    void iteration(RenderContext& ctx, uint32_t s) override;
    std::vector<RestirPixel> prev_;  // the last finished iteration (empty before the first)
    std::vector<RestirPixel> cur_;   // the iteration being rendered
    std::vector<Reservoir> prev_final_, final_;  // the pixels' final reservoirs (the history), by iteration
    std::unique_ptr<SpectralPathIntegrator> spectral_;  // spectral paths (null: RGB)
    // Spectral: per pixel of the iteration being rendered, its wavelengths and their RGB weights at
    // the vertex (SpectralPathIntegrator::trace_restir_pixel), wavelength_count() each.
    std::vector<float> lambda_;
    std::vector<Color> weight_;
    // Measurements, summed over iterations: stage 1 (trace, and the temporal reuse when on) and stage
    // 2 (spatial reuse and shading), wall seconds.
    double trace_seconds_ = 0, reuse_seconds_ = 0;
    uint64_t iterations_ = 0, vertices_ = 0, neighbours_ = 0, pdf_evaluations_ = 0, mis_shadow_rays_ = 0;
};

}  // namespace smis
