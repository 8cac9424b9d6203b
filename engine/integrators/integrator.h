// The integrator interface. An integrator renders a range of sample indices for every pixel of the
// film window ("a pass"); the session calls it repeatedly for progressive rendering. Per-pixel
// estimators derive from PixelIntegrator, which parallelises over tiles; multi-stage estimators
// (path-space filtering, photon planes, ReSTIR) derive from IterativeIntegrator (whole-image iterations).
#pragma once
#include <atomic>
#include <chrono>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/rng.h"
#include "core/sampler.h"
#include "core/sampling.h"
#include "film/film.h"
#include "film/pixel_filter.h"
#include "render_settings.h"
#include "scene/scene.h"

namespace smis {

// struct RenderSettings and its enums (IntegratorKind, SpectralSetting, VolumeEstimator,
// DirectLightStrategy, RestirMis, ...) are generated from the one table of the render settings,
// addon/smis_render/settings_schema.py (engine/render/tools/gen_settings.py).

class FirstHitPasses;
struct RayMedia;

// Counters reported to the user (stats line) and checked by the stress tests.
struct RenderCounters {
    std::atomic<uint64_t> paths{0};             // camera samples completed
    std::atomic<uint64_t> nan_caught{0};        // non-finite samples dropped before the film
    std::atomic<uint64_t> samples_rejected{0};  // sampling routines that returned no valid sample
};

// Per-thread tallies, flushed to RenderCounters once per tile so the hot loop touches no atomics.
struct LocalCounters {
    uint64_t paths = 0, nan_caught = 0, samples_rejected = 0;
    // The current sample's value for the integrator's diagnostic pass, set by Li() where it has one
    // (PixelIntegrator resets it per sample and hands it to the auxiliary passes); not a counter.
    float sample_diagnostic = 0.0f;
    // Where the current sample's camera path records the auxiliary passes at its first hit
    // (aux_passes.h, set by RecordPasses while the passes are on); null: nowhere. Not a counter.
    FirstHitPasses* passes = nullptr;
    // The current sample's transparency for Film Transparent (PathState::transparent_background),
    // reset per sample like sample_diagnostic; not a counter.
    float sample_transparency = 0.0f;
    // Where the current sample's path copies its camera ray's media segments (the first
    // intersect_through of a path in a scene with media), then nulls it; null: nowhere. The photon
    // planes' gather takes them from there instead of tracing the same camera ray again. Not a counter.
    RayMedia* camera_media = nullptr;
    void flush(RenderCounters& c) {
        c.paths += paths, c.nan_caught += nan_caught, c.samples_rejected += samples_rejected;
        *this = {};
    }
};

struct RenderContext {
    const Scene& scene;
    const RenderSettings& settings;
    Film& film;
    const PixelFilter& filter;
    RenderCounters& counters;
    const std::atomic<bool>& cancel;
    std::chrono::steady_clock::time_point deadline;  // time_point::max() when unlimited
    bool should_stop() const {
        return cancel.load(std::memory_order_relaxed) || std::chrono::steady_clock::now() >= deadline;
    }
};

class Integrator {
public:
    virtual ~Integrator() = default;
    // Adds samples [s0, s1) to every pixel of the window; returns early when ctx.should_stop().
    virtual void render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) = 0;
    // Largest number of samples per pass. Multi-stage integrators finish whole iterations only, so
    // they take one sample per pass: a time limit then wastes at most one iteration.
    virtual uint32_t max_pass_samples() const { return 16; }
    // Integrator-specific measurements (stage timings, reuse statistics) for stats and benchmarks.
    virtual std::map<std::string, double> stats() const { return {}; }
    // Work this integrator leaves out for these settings, for the stats line ("skipped: ...").
    virtual void add_skipped(const RenderSettings& settings, std::vector<std::string>* skipped) const {}
};

// Multi-stage integrators (path-space filtering, photon planes, ReSTIR) render whole-image
// iterations of one sample per pixel; a pass runs iterations [s0, s1), one pass per iteration.
class IterativeIntegrator : public Integrator {
public:
    void render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) final {
        for (uint32_t s = s0; s < s1 && !ctx.should_stop(); ++s) iteration(ctx, s);
    }
    uint32_t max_pass_samples() const final { return 1; }

protected:
    virtual void iteration(RenderContext& ctx, uint32_t s) = 0;
};

class PixelIntegrator : public Integrator {
public:
    void render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) override;

protected:
    // Radiance along a camera ray; `sampler` holds the sample's named numbers and its own stream.
    virtual Color Li(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                     LocalCounters& counters) const = 0;
    // Radiance of sample `s` of film pixel (px, py) along `ray`: Li() unless the integrator
    // stratifies a dimension over the samples of a pixel (core/pixel_sequence.h), which needs them.
    virtual Color pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray,
                               Sampler& sampler, LocalCounters& counters) const {
        return Li(ctx.scene, ctx.settings, ray, sampler, counters);
    }

private:
    // Sample `s` of window pixel (x, y) along `ray`: pixel_sample() or Li().
    Color sample(const RenderContext& ctx, int x, int y, uint32_t s, const Ray& ray, Sampler& sampler,
                 LocalCounters& local) const;
};

// Creates the integrator settings.integrator selects (the spectral path tracer for PATH when
// settings.spectral resolves to a spectral mode for this scene); throws std::invalid_argument for
// combinations the engine refuses.
std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings, const Scene& scene);
// The spectral mode settings.spectral selects for this scene (Rgb when it resolves to RGB rendering; never Auto).
SpectralSetting resolve_spectral_mode(const RenderSettings& settings, const Scene& scene);

}  // namespace smis
