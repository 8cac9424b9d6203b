#include "integrators/aux_passes.h"

#include "integrators/path_tracing.h"
#include "integrators/tiles.h"

namespace smis {

namespace {

// Reflectance of the closures at normal incidence: each lobe's albedo (lobe.h), its weight times its
// Fresnel reflectance where it carries one (the Principled specular layer's dielectric F0, a metal's
// f0), so a white Principled BSDF reads about 1, not 1 plus the specular layer's full weight.
Color albedo(const Bsdf& bsdf) {
    Color sum(0.0f);
    for (int i = 0; i < bsdf.lobe_count(); ++i) sum += lobe_albedo(bsdf.lobe(i));
    return sum;
}

// The passes at the camera ray's first hit, whose shading point is `first`.
AuxSample aux_at(const Scene& scene, const ShadingPoint& first, Rng& rng) {
    AuxSample a;
    a.depth = scene.camera().view_depth(first.hit.p);
    a.normal = first.ns;
    if (!first.bsdf.is_delta()) {
        a.albedo = albedo(first.bsdf);
    } else {
        ShadingPoint sp = first;
        Color throughput(1.0f);
        for (int bounce = 0;; ++bounce) {
            if (!sp.bsdf.is_delta() || bounce == kAuxMaxDeltaBounces) {
                a.albedo = throughput * albedo(sp.bsdf);
                break;
            }
            BsdfSample bs = sample_bsdf(sp, rng);
            if (!bs.valid()) break;
            throughput *= bs.value / bs.pdf;
            // Dirac bounces only: a glossy reflection or a transmission (ray_visibility.h).
            const Ray ray{spawn_origin(sp, bs.wi), bs.wi, 0.0f, kInf, sp.hit.time,
                          ray_mask(bs.transmission ? kRayTransmission : kRayGlossy)};
            SurfaceHit hit;
            if (!scene.intersect(ray, &hit)) break;
            sp = make_shading_point(scene, hit, ray.d);
        }
    }
    if (!is_finite(a.albedo)) a.albedo = Color(0.0f);
    return a;
}

// A stream apart from the pixel sample's, so enabling passes leaves the image unchanged.
Rng aux_rng(const RenderContext& ctx, int x, int y, uint32_t s) {
    const Camera& cam = ctx.scene.camera();
    return pixel_sample_rng(x + cam.window_x0(), y + cam.window_y0(), s, ctx.settings.seed ^ 0xa0c5a11eu);
}

}  // namespace

AuxSample first_hit_depth(const Scene& scene, const Ray& camera_ray) {
    AuxSample a;
    SurfaceHit hit;
    if (scene.intersect(camera_ray, &hit)) a.depth = scene.camera().view_depth(hit.p);
    return a;
}

AuxSample first_hit_aux(const Scene& scene, const Ray& camera_ray, Rng& rng) {
    SurfaceHit hit;
    if (!scene.intersect(camera_ray, &hit)) return AuxSample{};
    return aux_at(scene, make_shading_point(scene, hit, camera_ray.d), rng);
}

void FirstHitPasses::at_first_hit(const Scene& scene, const ShadingPoint& first) {
    Rng rng = aux_rng(*ctx_, x_, y_, s_);
    aux = aux_at(scene, first, rng);
    ready = true;
}

void add_aux_sample(RenderContext& ctx, int x, int y, uint32_t s, const FirstHitPasses& recorded, float diagnostic) {
    if (!ctx.film.has_aux()) return;
    AuxSample a = recorded.aux;
    if (!recorded.ready) {
        const Ray ray = camera_ray(ctx, x, y, s);
        if (ctx.settings.aux_shading) {
            Rng rng = aux_rng(ctx, x, y, s);
            a = first_hit_aux(ctx.scene, ray, rng);
        } else {
            a = first_hit_depth(ctx.scene, ray);
        }
    }
    a.diagnostic = diagnostic;
    ctx.film.add_aux(x, y, a);
}

}  // namespace smis
