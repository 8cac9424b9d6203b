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
#include "core/sampling.h"
#include "film/film.h"
#include "film/pixel_filter.h"
#include "scene/scene.h"

namespace smis {

enum class DirectLightStrategy { Nee, Ris, Restir };
// How reservoirs of different pixels are combined (ReSTIR supplement, Alg. 1 and 2).
enum class RestirMis {
    Seed,    // Alg. 1: one MIS weight for the selected sample, k pdf evaluations
    Talbot,  // Alg. 2: a weight for every input sample, k^2 pdf evaluations
    None,    // 1/sum(M): biased wherever the neighbours' supports differ
};

struct RenderSettings {
    uint32_t samples = 64;
    int max_bounces = 8;          // Cycles' meaning: 0 = direct lighting only
    // Cycles' Light Paths > Max Bounces per type (beyond_bounce_limits): diffuse, glossy and
    // transmission bounces, and passes through Transparent lobes (grey cut-outs are decided in the
    // BVH and spend none). The defaults leave only max_bounces in force, as an unbiased render wants.
    int max_diffuse_bounces = 1024, max_glossy_bounces = 1024, max_transmission_bounces = 1024,
        max_transparent_bounces = 1024;
    // Cycles' Clamp Direct / Clamp Indirect (clamp_contribution): 0 = off. Clamping biases (darkens).
    float clamp_direct = 0.0f, clamp_indirect = 0.0f;
    // Cycles' Reflective / Refractive Caustics: off, a surface reached by a diffuse ray leaves out its
    // glossy reflection / refraction lobes (lobe_is_caustic). Off biases (darkens) the image.
    bool caustics_reflective = true, caustics_refractive = true;
    // Cycles' Filter Glossy (scene.cycles.blur_glossy; blur_glossy_lobes): 0 = off. On, a vertex
    // reached by a path whose smallest BSDF sampling density so far is low (after a diffuse or rough
    // bounce) raises its microfacet lobes' roughness. Biased by design (less noise from caustics).
    float filter_glossy = 0.0f;
    uint32_t seed = 0;
    bool stratified = true;       // stratified prefix of every pixel sample's stream (core/stratified.h)
    MisHeuristic mis = MisHeuristic::Power;
    double time_limit = 0.0;      // seconds, 0 = none
    int threads = 0;              // 0 = all cores
    std::string integrator = "PATH";
    std::string filter = "BLACKMAN_HARRIS";
    bool aux_passes = false;      // Depth/Normal/Albedo/diagnostic passes (one extra camera ray per sample)
    bool aux_shading = true;      // ...of which Normal or Albedo (else the first hit's depth is all they need)
    // Blender's Film > Transparent: the World seen by camera rays (directly or through transparent
    // surfaces only) becomes alpha instead of colour; it still lights the scene (PathState).
    bool film_transparent = false;
    // Cycles' Transparent Glass (with Film Transparent): a refraction through glass whose GGX alpha
    // (roughness^2) is at most this keeps the path transparent, so the World behind glass becomes
    // alpha too. Negative: off.
    float film_transparent_glass = -1.0f;
    float filter_width = 1.5f;
    // Path-space filtering (integrators PSF_*).
    float psf_radius_px = 6.0f;        // gather radius in screen pixels, projected to world at the vertex
    float psf_radius_alpha = 2.0f / 3.0f;  // radius shrink: r_i = r_0 (i + 1)^((alpha - 1) / 2)
    // Techniques gathered per pixel (random subset beyond this). With shared technique sets
    // (psf_block_size) the k^2 denominators are paid once per set, and 24 beat 16 at 2 s (3 seeds,
    // two runs): psf_room SMAPE -7%, psf_glossy -2%; 32 helped the room more but raised psf_glossy's
    // relMSE by 10%.
    int psf_max_neighbors = 24;
    // Light samples at each path's prefix endpoint x1 per iteration. The direct light there stays per
    // pixel while the indirect light is shared, so it becomes the larger part of the error: at 8
    // iterations (seeds 1-3) 4 samples take psf_glossy's SMAPE from 0.074 to 0.053 and psf_room's MSE
    // from 0.0020 to 0.0015, for 17% / 11% more time per iteration (8 samples: 0.047, +48%).
    int psf_light_samples = 4;
    // Extra paths per iteration from x1 where the filter cannot share the pixel's suffix (sharp
    // lobes, thin or curved glossy objects): up to this many, in proportion to the own suffix's weight
    // in the pixel's estimate averaged over the past iterations; kept by the pixel (see
    // path_space_filtering.cpp). 0 = off.
    int psf_extra_paths = 4;
    // Side of the pixel blocks whose pixels share one technique set in stage 2 (1, 2 or 4; other
    // values round down): the grid query and eq. 17's denominators are computed once per block.
    int psf_block_size = 2;
    float psf_keller_normal_cos = 0.9f;    // Keller et al. 2014 acceptance: normals within ~26 degrees
    float psf_keller_plane = 0.1f;     // ... and within 0.1 radius of the query's tangent plane
    // Spectral rendering (paper §5): AUTO, RGB, UNIFORM, SPECTRAL_IS, HERO, SMIS, SMIS_INDEPENDENT,
    // BRUTE_FORCE (spectral/wavelength_sampling.h). AUTO = RGB for scenes without spectral content,
    // else SMIS. Applies to the PATH integrator.
    std::string spectral = "AUTO";
    int wavelengths = 4;               // n for HERO / SMIS / SMIS_INDEPENDENT
    // Wavelength offsets of a pixel's samples from core/pixel_sequence.h (stratified over the
    // samples) instead of independent random numbers; off only to measure what it brings.
    bool spectral_pixel_sequence = true;
    // > 0: PATH renders the spectral radiance at this one wavelength (nm, within [360, 830]) into every
    // channel, with no wavelength sampling and no RGB response: the tests' reference, integrated
    // against the observer by the test itself.
    float spectral_wavelength = 0.0f;
    // Single scattering in media (West et al. 2020, §6): PATH (distance sampling + NEE) or photon
    // planes PLANES_UNWEIGHTED / PLANES_CMIS / PLANES_SMIS_COS / PLANES_SMIS_EXACT.
    std::string volume_estimator = "PATH";
    uint32_t photon_planes = 40960;    // planes per iteration (one iteration = one camera sample)
    int smis_planes = 2;               // n: orientations per SMIS realisation (eq. 27)
    // K > 0: of a camera ray's plane crossings in one medium segment, about K trace their shadow ray,
    // each with probability q = min(1, K c / sum c) by its unshadowed contribution c and divided by q
    // (Russian roulette on visibility: unbiased); 0 traces every crossing's shadow ray.
    uint32_t plane_shadow_rays = 0;
    // Path-tracer samples per pixel that one plane set serves: each iteration gathers the planes along
    // one camera ray per pixel and averages this many path samples for everything else (surfaces,
    // other lights, secondary rays), so surfaces are not held to the plane iterations' count.
    // 0: chosen per scene from the plane set's gathering cost (photon_planes.cpp).
    uint32_t plane_surface_samples = 0;
    // Benchmarks of the volume estimators: render only the camera rays' single scattering (PATH:
    // from every light; photon planes: from the rectangular lights they cover).
    bool camera_volume_only = false;
    // Many-light direct illumination at the camera path's first non-specular vertex (PATH only;
    // deeper vertices keep NEE). RESTIR makes PATH a multi-stage integrator (integrators/restir.h).
    DirectLightStrategy direct_light = DirectLightStrategy::Nee;
    int ris_candidates = 16;           // M: light candidates per pixel and iteration
    int restir_neighbors = 5;          // k: spatial neighbours per pixel
    // Neighbours drawn uniformly from this disk (screen pixels). Close neighbours share visibility:
    // on scenes/many_lights.blend (128 px, k = 5, 64 spp) relMSE 0.0133 at 2 px, 0.0135 at 3, 0.0149
    // at 5 for the same time; 3 keeps a few more distinct pixels to draw k from.
    float restir_radius_px = 3.0f;
    // The previous iteration's reservoir counts at most cap x M; 0 (the default) makes every
    // iteration an independent ReSTIR estimate. Unlike real-time ReSTIR, the iterations are averaged,
    // and the history correlates them: on scenes/many_lights.blend (128 px, 64 spp) cap 2 gave the
    // same relMSE as cap 0 (0.0146-0.0148 vs 0.0147-0.0149) at ~10% more time per iteration, cap 8
    // a higher one (0.021 vs 0.015); cap 20 with a 30 px radius was 4x worse at 3 s.
    int restir_history_cap = 0;
    RestirMis restir_mis = RestirMis::Seed;
    bool restir_unbiased = true;           // visibility of every neighbour in the MIS pdfs
    bool restir_visibility_reuse = true;   // occluded initial samples are dropped (Bitterli et al. Alg. 5, l. 7-9)
};

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
    // The current sample's camera-ray depth (Cycles' Z), recorded by the path tracer as it traces
    // the camera ray so that the Z pass needs no ray of its own; NaN where nothing recorded it.
    float camera_depth = std::numeric_limits<float>::quiet_NaN();
    // The current sample's transparency for Film Transparent (PathState::transparent_background),
    // reset per sample like sample_diagnostic; not a counter.
    float sample_transparency = 0.0f;
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
    // Radiance along a camera ray; `rng` is the sample's own stream.
    virtual Color Li(const Scene& scene, const RenderSettings& settings, Ray ray, Rng& rng,
                     LocalCounters& counters) const = 0;
    // Radiance of sample `s` of film pixel (px, py) along `ray`: Li() unless the integrator
    // stratifies a dimension over the samples of a pixel (core/pixel_sequence.h), which needs them.
    virtual Color pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s, const Ray& ray,
                               Rng& rng, LocalCounters& counters) const {
        return Li(ctx.scene, ctx.settings, ray, rng, counters);
    }
};

// Creates the integrator named by settings.integrator (the spectral path tracer for PATH when
// settings.spectral resolves to a spectral mode for this scene); throws std::invalid_argument for
// unknown names.
std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings, const Scene& scene);
// The spectral mode settings.spectral selects for this scene ("RGB" when it resolves to RGB rendering).
std::string resolve_spectral_mode(const RenderSettings& settings, const Scene& scene);

}  // namespace smis
