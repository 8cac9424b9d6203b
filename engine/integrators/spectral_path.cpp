#include "integrators/spectral_path.h"

#include "integrators/spectral_throughput.h"

namespace smis {

using namespace spectral;
using namespace spectral_paths;


SpectralPathIntegrator::SpectralPathIntegrator(const Scene& scene, SpectralMode mode, int wavelengths,
                                               float fixed_wavelength)
    : spectral_(scene), sampler_(mode, wavelengths, spectral_.importance()), fixed_wavelength_(fixed_wavelength) {}

std::map<std::string, double> SpectralPathIntegrator::stats() const {
    return {{"wavelengths_per_path", double(sampler_.count())}};
}

Color SpectralPathIntegrator::Li(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                                 LocalCounters& counters) const {
    Rng& rng = sampler.rng();
    float u = rng.next_float();
    float v = rng.next_float();
    return trace(scene, settings, ray, u, v, rng, rng, counters, nullptr, &sampler);
}

// The offsets of sample s: wavelength_offsets (spectral_throughput.h).
Color SpectralPathIntegrator::pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s,
                                           const Ray& ray, Sampler& sampler, LocalCounters& counters) const {
    return sample_path(ctx, px, py, s, ray, sampler.rng(), counters, nullptr, &sampler);
}

Color SpectralPathIntegrator::sample_path(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s,
                                          const Ray& ray, Rng& rng, LocalCounters& counters,
                                          SpectralRestirRecord* restir, Sampler* camera) const {
    // The wavelengths draw from a stream of their own, so that in every mode the path is driven by
    // the pixel sample's stream and its named groups (core/sampler.h) alike: modes differ only in
    // how they choose wavelengths.
    Rng wavelength_rng = pixel_sample_rng(px, py, s, ctx.settings.seed ^ kWavelengthStream);
    float u, v;
    wavelength_offsets(sampler_, ctx.settings, px, py, s, wavelength_rng, &u, &v);
    return trace(ctx.scene, ctx.settings, ray, u, v, wavelength_rng, rng, counters, restir, camera);
}

Color SpectralPathIntegrator::trace(const Scene& scene, const RenderSettings& settings, Ray ray, float u, float v,
                                    Rng& wavelength_rng, Rng& rng, LocalCounters& counters,
                                    SpectralRestirRecord* restir, Sampler* camera) const {
    SpectralPath p;
    if (fixed_wavelength_ > 0.0f) p.start_at(fixed_wavelength_);
    else p.start(sampler_, u, v, wavelength_rng);
    // Always with the Light Path rules (their checks cost little next to n wavelengths; they carry
    // the subsurface walks).
    PathState state = camera_path_state(ray.o);
    state.first_vertex_ahead = true;  // RIS, when settings.direct_light asks for it
    state.medium = scene.camera_medium();
    return scene.has_media()
               ? trace_path_loop<SpectralThroughput, true, true>(scene, settings, ray, state, rng, counters,
                                                                 SpectralThroughput(spectral_, p, restir), camera)
               : trace_path_loop<SpectralThroughput, false, true>(scene, settings, ray, state, rng, counters,
                                                                  SpectralThroughput(spectral_, p, restir), camera);
}

int SpectralPathIntegrator::wavelength_count() const { return fixed_wavelength_ > 0.0f ? 1 : sampler_.count(); }

Color SpectralPathIntegrator::trace_restir_pixel(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s,
                                                 const Ray& ray, Sampler& sampler, LocalCounters& counters,
                                                 RestirPixel& vertex, float* lambda, Color* weight) const {
    vertex.has_vertex = false;
    vertex.distance = 0.0f;
    vertex.r = Reservoir{};
    vertex.eval = CandidateEval{};
    SpectralRestirRecord record{vertex, lambda, weight};
    return sample_path(ctx, px, py, s, ray, sampler.rng(), counters, &record, &sampler);
}

Color SpectralPathIntegrator::shade_restir_vertex(const Scene& scene, const RestirPixel& vertex, const float* lambda,
                                                  const Color* weight, const CandidateEval& e, float w,
                                                  bool visible) const {
    // The path at the vertex with its weights folded into the responses (beta 1, mixture 1).
    SpectralPath p;
    p.n = p.ws.n = wavelength_count();
    for (int i = 0; i < p.n; ++i) {
        p.ws.lambda[i] = lambda[i];
        p.beta[i] = 1.0f;
        p.response[i] = weight[i];
    }
    p.inv_mix = 1.0f;
    SpectralThroughput at_vertex(spectral_, p);
    at_vertex.at_material(vertex.sp);
    return at_vertex.light_sample(scene, vertex.sp, e, w, vertex.medium, visible);
}

}  // namespace smis
