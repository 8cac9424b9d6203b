#include "integrators/aux_passes.h"
#include "integrators/integrator.h"
#include "integrators/tiles.h"

namespace smis {

void PixelIntegrator::render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) {
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        const PixelCamera camera(ctx, x, y);
        for (uint32_t s = s0; s < s1; ++s) {
            Rng rng;
            Ray ray = camera.ray(s, &rng);
            local.sample_diagnostic = local.sample_transparency = 0.0f;
            local.camera_depth = std::numeric_limits<float>::quiet_NaN();
            const Camera& cam = ctx.scene.camera();
            Color L = kWithSpectral ? pixel_sample(ctx, x + cam.window_x0(), y + cam.window_y0(), s, ray, rng, local)
                                    : Li(ctx.scene, ctx.settings, ray, rng, local);
            // After the sample, for its diagnostic value; the passes draw their own random numbers.
            if (ctx.film.has_aux()) add_aux_sample(ctx, x, y, s, ray, local.sample_diagnostic, local.camera_depth);
            ++local.paths;
            ctx.film.add(x, y, guard_sample(L, local), local.sample_transparency);
        }
    });
}

}  // namespace smis
