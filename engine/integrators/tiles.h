// Parallel loop over the pixels of the film window in small tiles handed out by TBB's work-stealing
// scheduler. Each tile belongs to one thread and pixels are visited in a fixed order, so anything
// computed per pixel is independent of the thread count.
#pragma once
#include <tbb/blocked_range.h>

#include <chrono>
#include <tbb/parallel_for.h>

#include "core/float_mode.h"
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

// The camera ray of sample `s` of window pixel (x, y), and the sample's own random stream.
// The stratified prefix of a pixel sample's stream (core/stratified.h), in the order the path
// tracers draw: pixel position (2D), lens position (2D, only with depth of field), then at the first
// vertex next-event estimation (light choice 1D, point on the light 2D) and the BSDF sample (lobe
// 1D, direction 2D). The two 1D choices share one 2D group. Every integrator that starts with
// camera_ray() gets it; one that draws in another order stays unbiased (each value is uniform and
// independent of the others on its own) and only loses the stratification.
inline uint64_t stratified_pixel_key(uint32_t fx, uint32_t fy, uint32_t seed) {
    return mix64(mix64((uint64_t(fy) << 32) | fx) ^ (uint64_t(seed) * 0xd1b54a32d192ed03ull));
}
// The first vertex's values, deferred until the path draws them, last first (Rng::DeferredValues):
// drawn as light choice, light point (2D), lobe choice, direction (2D).
inline void first_vertex_values(uint64_t key, uint32_t s, float* out) {
    float choices[2], point[2], direction[2];
    stratified::sample_2d(s, key, 2, choices);
    stratified::sample_2d(s, key, 3, point);
    stratified::sample_2d(s, key, 4, direction);
    out[5] = choices[0], out[4] = point[0], out[3] = point[1];
    out[2] = choices[1], out[1] = direction[0], out[0] = direction[1];
}

// Extra light samples at the first vertex (path-space filtering takes several): light sample i of
// n - 1 extra ones of pixel sample s draws its light choice and point from dimension groups 5 and 6
// at index s (n - 1) + i, so a pixel's extra samples over all its pixel samples are one stratified
// set, as its first light sample is over the pixel samples (groups 2 and 3). Sets the next three
// numbers of `rng` in sample_direct's order: choice, then the point.
inline void set_extra_light_sample_prefix(Rng* rng, uint64_t pixel_key, uint32_t s, uint32_t i, uint32_t n_extra) {
    float point[2], choice[2];
    stratified::sample_2d(s * n_extra + i, pixel_key, 5, point);
    stratified::sample_2d(s * n_extra + i, pixel_key, 6, choice);
    const float v[3] = {choice[0], point[0], point[1]};
    rng->set_prefix(v, 3);
}

// Extra BSDF samples at the first vertex (path-space filtering's extra paths): a pixel's i-th extra
// BSDF sample over the whole render draws its lobe choice and direction from dimension groups 7 and 8
// at index i, so they form one stratified set per pixel. Sets the next three numbers in sample_bsdf's
// order: lobe, then the direction.
inline void set_extra_bsdf_sample_prefix(Rng* rng, uint64_t pixel_key, uint32_t i) {
    float dir[2], choice[2];
    stratified::sample_2d(i, pixel_key, 7, dir);
    stratified::sample_2d(i, pixel_key, 8, choice);
    const float v[3] = {choice[0], dir[0], dir[1]};
    rng->set_prefix(v, 3);
}

// The dimension group of a camera sample's time in the shutter (groups 0-8 are taken above). Groups
// 10-12 are the first scattering segment's (volume.h, kScatteringDimensionGroup).
constexpr uint32_t kTimeDimensionGroup = 9;

// The camera rays of one window pixel (x, y): ray(s, &rng) is sample s's camera ray and sets rng
// to the sample's own random stream. What depends on the pixel and the seed only (the stream's key,
// the stratified scrambles of the pixel position, lens and time) is hashed once for all the pixel's
// samples: where most camera rays leave the scene, these hashes were a tenth of a sample's cost.
class PixelCamera {
public:
    PixelCamera(const RenderContext& ctx, int x, int y)
        : ctx_(ctx), cam_(ctx.scene.camera()), fx_(x + cam_.window_x0()), fy_(y + cam_.window_y0()),
          stream_(pixel_stream(fx_, fy_, ctx.settings.seed)),
          stratified_(kWithStratified && ctx.settings.sampling_pattern == SamplingPattern::Stratified) {
        if (!stratified_) return;
        key_ = stratified_pixel_key(fx_, fy_, ctx.settings.seed);
        position_ = stratified::GroupSeeds(key_, 0);
        if (cam_.has_aperture()) lens_ = stratified::GroupSeeds(key_, 1);
        if (ctx.scene.has_motion()) time_ = stratified::GroupSeeds(key_, kTimeDimensionGroup);
    }

    Ray ray(uint32_t s, Rng* rng) const {
        *rng = pixel_sample_rng(stream_, s);
        const bool lens = cam_.has_aperture();
        if (stratified_) {
            float v[4];
            stratified::sample_2d(s, position_, v);
            if (lens) stratified::sample_2d(s, lens_, v + 2);
            rng->set_prefix(v, lens ? 4 : 2, first_vertex_values, 6, key_, s);
            rng->mark_scattering_segment();
        }
        Point2 off = ctx_.filter.sample({rng->next_float(), rng->next_float()});
        const float px = fx_ + 0.5f + off.x, py = fy_ + 0.5f + off.y;
        if (!ctx_.scene.has_motion()) {
            if (!lens) return cam_.generate_ray(px, py);
            Point2 u_lens{rng->next_float(), rng->next_float()};
            return cam_.generate_ray(px, py, u_lens);
        }
        // Motion blur: every ray of the path sees the scene at the sample's time in the shutter. Drawn
        // after the lens, so scenes that do not move keep their numbers; stratified over the pixel's
        // samples from a group of its own (the prefix's numbers stay the lens' and the first vertex's).
        Point2 u_lens{0.5f, 0.5f};
        if (lens) u_lens = {rng->next_float(), rng->next_float()};
        float u_time;
        if (stratified_) {
            float v[2];
            stratified::sample_2d(s, time_, v);
            u_time = v[0];
        } else {
            u_time = rng->next_float();
        }
        return cam_.generate_ray(px, py, u_lens, cam_.sample_time(u_time));
    }

private:
    const RenderContext& ctx_;
    const Camera& cam_;
    int fx_, fy_;
    uint64_t stream_;
    bool stratified_;
    uint64_t key_ = 0;
    stratified::GroupSeeds position_, lens_, time_;
};

inline Ray camera_ray(const RenderContext& ctx, int x, int y, uint32_t s, Rng* rng) {
    return PixelCamera(ctx, x, y).ray(s, rng);
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
