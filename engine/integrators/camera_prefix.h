// The camera prefix: a camera path on the path loop (path_loop.h) up to its first non-specular
// vertex x1, where the loop ends (kEndsAtFirstVertex), for the integrators that do their own thing
// at x1: ReSTIR (restir.cpp) and path-space filtering (psf_rgb.cpp, psf_spectral.cpp). CameraPrefix
// turns a spectrum policy (rgb_throughput.h, spectral_throughput.h) into a prefix's by keeping the
// bookkeeping every prefix needs in a PrefixEnd; the integrators' policies derive from it and add
// where x1's shading point and throughput go (first_vertex, calling CameraPrefix's first).
#pragma once
#include <utility>

#include "integrators/path_tracing.h"

namespace smis {

// What the prefix left at its end (x1 when reached).
struct PrefixEnd {
    bool reached = false;   // the path found x1 (else it ended before: escaped, absorbed, a hole)
    PathState state;        // the path's state at x1
    float distance = 0.0f;  // the camera path's length up to x1 (the last hit when not reached)
    float eta_scale = 1.0f; // the prefix's refractions' radiance scaling (Russian roulette leaves it out)
    // x1's light and BSDF numbers: the pixel sample's Sampler when x1 is the camera path's first
    // vertex (it asks for them by name, core/sampler.h), null when a vertex before it took the names
    // (x1 then draws from the stream): VertexSampler(stream, x1_names).
    Sampler* x1_names = nullptr;
};

template <class Spectrum>
class CameraPrefix : public Spectrum {
public:
    static constexpr bool kEndsAtFirstVertex = true;
    static constexpr bool kGlowDirections = false;  // the path ends at x1, before any light-aimed continuation
    template <class... Args>
    explicit CameraPrefix(PrefixEnd* end, Args&&... args) : Spectrum(std::forward<Args>(args)...), end_(end) {}
    void prepare(ShadingPoint& sp) {
        Spectrum::prepare(sp);
        end_->distance += sp.hit.t;
    }
    void after_scatter(const PathState& state, const BsdfSample& bs) {
        Spectrum::after_scatter(state, bs);
        if (bs.transmission) end_->eta_scale *= sqr(bs.eta);
    }
    void first_vertex(const ShadingPoint&, const PathState& state, const VertexSampler& numbers) {
        end_->reached = true;
        end_->state = state;
        end_->x1_names = numbers.names();
    }

private:
    PrefixEnd* end_;
};

}  // namespace smis
