// The RGB path tracer's spectrum policy for the path loop (path_loop.h describes the policy): one
// Color throughput. Shared by the path tracer (path_tracing.cpp), RGB path-space filtering's prefix
// and suffix (psf_rgb.cpp) and ReSTIR's prefix (restir.cpp), which derive from it. Internal to those files.
#pragma once
#include "integrators/camera_prefix.h"
#include "integrators/direct_lighting.h"
#include "integrators/path_loop.h"

namespace smis {

// Cycles' subsurface bounce at sp, whose BSDF sample bs picked a Subsurface lobe: the walk (or
// Christensen-Burley's disk sampling) to the exit, which becomes sp, then the exit's light sample
// (*direct, with the throughput) and its BSDF sample (bs), at the entry's depth (the walk is no
// bounce of the path in Cycles). False: the path ends. Out of line (path_tracing.cpp), so the loops
// stay as they were for scenes without subsurface.
[[gnu::noinline]] bool subsurface_bounce(const Scene& scene, const RenderSettings& settings, ShadingPoint& sp,
                                         BsdfSample& bs, Color& beta, Rng& rng, LocalCounters& counters,
                                         int32_t medium, Color* direct);

struct RgbThroughput {
    static constexpr bool kResampledLights = true;
    static constexpr bool kEndsAtFirstVertex = false;
    static constexpr bool kSubsurfaceWalks = true;
    static constexpr bool kGlowDirections = true;
    Color beta{1.0f};

    template <class Clamp>
    void emission(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, const Ray& ray,
                  bool found, const SurfaceHit& hit, const PathState& state, const RayMedia* media,
                  const ShaderRay* sray) const {
        L += clamped(beta * emission_along(scene, settings, ray, found, hit, state, media, sray), state.depth <= 1);
    }
    void scattering(Color& L, const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                    LocalCounters& counters, bool skip_plane_lights) const {
        L += beta * single_scattering(scene, ray, media, rng, counters, skip_plane_lights);
    }
    void attenuate(const RayMedia& media) { beta *= media.transmittance_to_end(); }
    const Color& transparency_beta() const { return beta; }
    bool is_black() const { return smis::is_black(beta); }
    void prepare(ShadingPoint&) const {}
    template <class Clamp>
    void resampled_direct(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings,
                          const ShadingPoint& sp, Rng& rng, const PathState& state) const {
        L += clamped(beta * ris_direct(scene, settings, sp, rng, state.medium), state.depth == 0);
    }
    template <class Clamp>
    void direct(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                VertexSampler u, LocalCounters& counters, const PathState& state) const {
        DirectSample ds = sample_direct(scene, settings, sp, u, counters, state.medium, 1, 1, state.glow_vertex);
        if (ds.valid) L += clamped(beta * direct_eval(sp, ds) * ds.weighted, state.depth == 0);
    }
    template <class Clamp>
    bool subsurface(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, ShadingPoint& sp,
                    BsdfSample& bs, Rng& rng, LocalCounters& counters, const PathState& state) {
        Color direct;
        if (!subsurface_bounce(scene, settings, sp, bs, beta, rng, counters, state.medium, &direct)) return false;
        L += clamped(direct, state.depth == 0);
        return true;
    }
    bool scatter(const ShadingPoint&, const BsdfSample& bs) {
        beta *= bs.value / bs.pdf;
        return true;
    }
    void after_scatter(const PathState&, const BsdfSample&) const {}
    bool roulette(int depth, float eta_scale, Rng& rng) {
        return russian_roulette(depth, beta, eta_scale, rng) && !smis::is_black(beta);
    }
    void finish(LocalCounters&) const {}
};

// The RGB camera prefix (camera_prefix.h) of ReSTIR and path-space filtering: its Dirac vertices
// take no light sample (none can light a Dirac BSDF, and no random numbers are drawn for one);
// x1's light is the integrator's own.
class RgbCameraPrefix : public CameraPrefix<RgbThroughput> {
public:
    static constexpr bool kResampledLights = false;
    using CameraPrefix::CameraPrefix;
    template <class Clamp>
    void direct(Color&, Clamp&&, const Scene&, const RenderSettings&, const ShadingPoint&, VertexSampler, LocalCounters&,
                const PathState&) const {}
};

}  // namespace smis
