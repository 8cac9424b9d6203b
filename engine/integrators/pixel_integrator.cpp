#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/float_mode.h"
#include "integrators/integrator.h"

namespace smis {

namespace {
constexpr int kTile = 16;
}

void PixelIntegrator::render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) {
    const Camera& cam = ctx.scene.camera();
    const int w = ctx.film.width(), h = ctx.film.height();
    const int tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
    // Small tiles handed out by TBB's work-stealing scheduler; each tile belongs to one thread, and a
    // pixel's samples are added in index order, so the image does not depend on the thread count.
    tbb::parallel_for(
        tbb::blocked_range<int>(0, tiles_x * tiles_y, 1),
        [&](const tbb::blocked_range<int>& range) {
            ScopedFlushDenormals same_float_mode_on_every_thread;
            LocalCounters local;
            for (int tile = range.begin(); tile != range.end(); ++tile) {
                if (ctx.should_stop()) break;
                int tx = tile % tiles_x, ty = tile / tiles_x;
                for (int y = ty * kTile; y < std::min(h, (ty + 1) * kTile); ++y)
                    for (int x = tx * kTile; x < std::min(w, (tx + 1) * kTile); ++x) {
                        int fx = x + cam.window_x0(), fy = y + cam.window_y0();
                        for (uint32_t s = s0; s < s1; ++s) {
                            Rng rng = pixel_sample_rng(fx, fy, s, ctx.settings.seed);
                            Point2 off = ctx.filter.sample({rng.next_float(), rng.next_float()});
                            Ray ray = cam.generate_ray(fx + 0.5f + off.x, fy + 0.5f + off.y);
                            Color L = Li(ctx.scene, ctx.settings, ray, rng, local);
                            ++local.paths;
                            if (!film_accepts(L)) {
                                ++local.nan_caught;
                                L = Color(0.0f);  // counted as a black sample: keeps every pixel's count equal
                            }
                            ctx.film.add(x, y, L);
                        }
                    }
                local.flush(ctx.counters);
            }
        },
        tbb::simple_partitioner());
}

}  // namespace smis
