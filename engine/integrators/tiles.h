// Parallel loop over the pixels of the film window in small tiles handed out by TBB's work-stealing
// scheduler. Each tile belongs to one thread and pixels are visited in a fixed order, so anything
// computed per pixel is independent of the thread count.
#pragma once
#include <tbb/blocked_range.h>

#include <chrono>
#include <tbb/parallel_for.h>

#include "core/float_mode.h"
#include "core/sampler.h"
#include "core/stratified.h"
#include "integrators/integrator.h"

namespace smis {

// Side of the square tiles (pixels); path-space filtering's pixel blocks must divide it.
constexpr int kTileSize = 16;

// fn(x, y, local_counters) for every window pixel (x, y), y = 0 the bottom row. Stops handing out
// tiles once ctx.should_stop().
template <class Fn>
void for_each_pixel_in_tiles(RenderContext& ctx, Fn&& fn) {
    constexpr int kTile = kTileSize;
    const int w = ctx.film.width(), h = ctx.film.height();
    const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
    tbb::parallel_for(
        tbb::blocked_range<int>(0, tiles_x * tiles_y, 1),
        [&](const tbb::blocked_range<int>& range) {
            ScopedFlushDenormals same_float_mode_on_every_thread;
            LocalCounters local;
            for (int tile = range.begin(); tile != range.end(); ++tile) {
                if (ctx.should_stop()) break;
                int tx = tile % tiles_x, ty = tile / tiles_x;
                for (int y = ty * kTile; y < std::min(h, (ty + 1) * kTile); ++y)
                    for (int x = tx * kTile; x < std::min(w, (tx + 1) * kTile); ++x) fn(x, y, local);
                local.flush(ctx.counters);
            }
        },
        tbb::simple_partitioner());
}

// The camera rays of one window pixel (x, y): ray(s, &sampler) is sample s's camera ray and makes
// `sampler` the sample's numbers (core/sampler.h). The camera asks for its numbers by name: pixel
// position, lens position (only with depth of field), time in the shutter (only with motion blur).
class PixelCamera {
public:
    PixelCamera(const RenderContext& ctx, int x, int y)
        : ctx_(ctx), cam_(ctx.scene.camera()), fx_(x + cam_.window_x0()), fy_(y + cam_.window_y0()),
          pixel_(fx_, fy_, ctx.settings.seed, ctx.settings.sampling_pattern == SamplingPattern::Stratified,
                 cam_.has_aperture(), ctx.scene.has_motion()) {}

    Ray ray(uint32_t s, Sampler* sampler) const {
        *sampler = pixel_.start(s);
        const Point2 off = ctx_.filter.sample(sampler->pixel());
        const float px = fx_ + 0.5f + off.x, py = fy_ + 0.5f + off.y;
        const bool lens = cam_.has_aperture();
        if (!ctx_.scene.has_motion()) {
            if (!lens) return cam_.generate_ray(px, py);
            return cam_.generate_ray(px, py, sampler->lens());
        }
        // Motion blur: every ray of the path sees the scene at the sample's time in the shutter. Drawn
        // after the lens, so that with the random pattern scenes that do not move keep their numbers.
        const Point2 u_lens = lens ? sampler->lens() : Point2{0.5f, 0.5f};
        return cam_.generate_ray(px, py, u_lens, cam_.sample_time(sampler->time()));
    }
    const PixelSampler& pixel_sampler() const { return pixel_; }

private:
    const RenderContext& ctx_;
    const Camera& cam_;
    int fx_, fy_;
    PixelSampler pixel_;
};

// A PixelCamera and sample s's ray, out of line, for the iterative integrators' stage loops (one
// sample per pixel per iteration): inlined there, they moved the compiler's inlining elsewhere in
// path-space filtering's iteration (psf_room, PSF_SMIS: +2.4% instructions, none of them the camera's).
[[gnu::noinline]] inline PixelCamera pixel_camera(const RenderContext& ctx, int x, int y) {
    return PixelCamera(ctx, x, y);
}
[[gnu::noinline]] inline Ray pixel_camera_ray(const PixelCamera& camera, uint32_t s, Sampler* sampler) {
    return camera.ray(s, sampler);
}

// Sample s's camera ray alone (the auxiliary passes' own ray, photon planes' crossing estimates).
inline Ray camera_ray(const RenderContext& ctx, int x, int y, uint32_t s) {
    Sampler sampler;
    return PixelCamera(ctx, x, y).ray(s, &sampler);
}

// Stage timings of the multi-stage integrators (reported through Integrator::stats()).
using StageClock = std::chrono::steady_clock;
inline double seconds_since(StageClock::time_point t0) {
    return std::chrono::duration<double>(StageClock::now() - t0).count();
}

// Non-finite radiance never reaches the film: the sample counts as black and is reported.
inline Color guard_sample(const Color& L, LocalCounters& local) {
    if (film_accepts(L)) return L;
    ++local.nan_caught;
    return Color(0.0f);
}

}  // namespace smis
