#include "integrators/aux_passes.h"
#include "integrators/integrator.h"
#include "integrators/tiles.h"

namespace smis {

Color PixelIntegrator::sample(const RenderContext& ctx, int x, int y, uint32_t s, const Ray& ray, Sampler& sampler,
                              LocalCounters& local) const {
    const Camera& cam = ctx.scene.camera();
    return kWithSpectral ? pixel_sample(ctx, x + cam.window_x0(), y + cam.window_y0(), s, ray, sampler, local)
                         : Li(ctx.scene, ctx.settings, ray, sampler, local);
}

void PixelIntegrator::render_pass(RenderContext& ctx, uint32_t s0, uint32_t s1) {
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        const PixelCamera camera(ctx, x, y);
        for (uint32_t s = s0; s < s1; ++s) {
            Sampler sampler;
            Ray ray = camera.ray(s, &sampler);
            local.sample_diagnostic = local.sample_transparency = 0.0f;
            Color L;
            if (ctx.film.has_aux()) {  // the path records the passes at its first hit (aux_passes.h)
                FirstHitPasses passes(ctx, x, y, s);
                {
                    RecordPasses recording(local, &passes);
                    L = sample(ctx, x, y, s, ray, sampler, local);
                }
                // After the sample, for its diagnostic value; the passes draw their own random numbers.
                add_aux_sample(ctx, x, y, s, passes, local.sample_diagnostic);
            } else {
                L = sample(ctx, x, y, s, ray, sampler, local);
            }
            ++local.paths;
            ctx.film.add(x, y, guard_sample(L, local), local.sample_transparency);
        }
    });
}

}  // namespace smis
