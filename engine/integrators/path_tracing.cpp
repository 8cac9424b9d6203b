#include "integrators/path_tracing.h"

#include "integrators/direct_lighting.h"

namespace smis {

ShadingPoint make_shading_point(const Scene& scene, const SurfaceHit& hit, const Vec3& ray_dir) {
    ShadingPoint sp;
    sp.hit = hit;
    sp.wo = -ray_dir;
    sp.backfacing = dot(sp.wo, hit.ng) < 0.0f;
    sp.ng = sp.backfacing ? -hit.ng : hit.ng;
    sp.ns = sp.backfacing ? -hit.ns : hit.ns;
    sp.bsdf = scene.material(hit.material).make_bsdf(Frame(sp.ns), sp.ng, sp.backfacing);
    return sp;
}

DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                           LocalCounters& counters) {
    DirectSample ds;
    const DiscreteDistribution& selection = scene.light_selection();
    // Draw the random numbers even when unused, so later decisions of the path keep their streams.
    float u_select = rng.next_float();
    Point2 u{rng.next_float(), rng.next_float()};
    if (sp.bsdf.is_delta() || selection.empty()) return ds;
    uint32_t li = static_cast<uint32_t>(selection.sample(u_select));
    float pmf = selection.pmf(li);
    LightSample ls = scene.light(li).sample(sp.hit.p, u);
    if (!ls.valid()) {
        // A light seen from behind is simply dark; only numerical failures count as rejected.
        if (!std::isfinite(ls.pdf) || !is_finite(ls.L)) ++counters.samples_rejected;
        return ds;
    }
    float tmax = std::isinf(ls.dist) ? kInf : ls.dist * (1.0f - 1e-4f);
    if (scene.occluded(spawn_origin(sp, ls.wi), ls.wi, tmax)) return ds;
    float light_pdf = pmf * ls.pdf;
    float w = ls.delta ? 1.0f : mis_weight(settings.mis, light_pdf, sp.bsdf.pdf(sp.wo, ls.wi));
    ds.wi = ls.wi;
    ds.weighted = ls.L * (w / light_pdf);
    ds.valid = true;
    return ds;
}

Color emission_along(const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                     const SurfaceHit& hit, const PathState& state) {
    auto weight = [&](float light_pmf, float light_pdf) {
        return state.prev_delta ? 1.0f
                                : mis_weight(settings.mis, state.prev_pdf, state.light_pdf_scale * light_pmf * light_pdf);
    };
    Color L(0.0f);
    Ray to_hit = ray;
    to_hit.tmax = found ? hit.t : kInf;
    // Area, point and spot lights are not in the BVH (as in Cycles): test them separately.
    scene.for_each_light_hit(to_hit, [&](uint32_t i, const LightHit& h) {
        if (state.depth == 0 && !scene.light(i).visible_to_camera) return;
        L += h.L * weight(scene.light_pmf(i), h.pdf);
    });
    if (!found) {
        LightHit h;
        for (uint32_t i : scene.infinite_lights())
            if ((state.depth > 0 || scene.light(i).visible_to_camera) && scene.light(i).intersect(to_hit, &h))
                L += h.L * weight(scene.light_pmf(i), h.pdf);
    } else if (hit.light >= 0) {
        auto& tri = static_cast<const TriangleLight&>(scene.light(hit.light));
        L += scene.material(hit.material).emission * weight(scene.light_pmf(hit.light), tri.pdf_at(state.prev_p, hit.p));
    }
    return L;
}

bool russian_roulette(int depth, Color& beta, float eta_scale, Rng& rng) {
    float u = rng.next_float();
    if (depth < 2) return true;
    // On the throughput without the refraction scaling, which cancels when the path leaves the medium.
    float q = std::min(0.95f, std::max(0.0f, 1.0f - max_component(beta) * eta_scale));
    if (u < q) return false;
    beta = beta / (1.0f - q);
    return true;
}

Color trace_path(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                 LocalCounters& counters) {
    Color L(0.0f), beta(1.0f);
    float eta_scale = 1.0f;
    for (;; ++state.depth) {
        SurfaceHit hit;
        bool found = scene.intersect(ray, &hit);
        L += beta * emission_along(scene, settings, ray, found, hit, state);
        // The ray leaving the last allowed bounce only collects emission (Cycles' max_bounces).
        if (!found || state.depth > settings.max_bounces) break;
        ShadingPoint sp = make_shading_point(scene, hit, ray.d);
        if (sp.bsdf.empty()) break;

        bool resample = false;
        if (state.first_vertex_ahead && !sp.bsdf.is_delta()) {
            state.first_vertex_ahead = false;
            resample = settings.direct_light == DirectLightStrategy::Ris;
        }
        state.light_pdf_scale = resample ? resampled_light_pdf_scale(settings) : 1.0f;
        if (resample) {
            L += beta * ris_direct(scene, settings, sp, rng);
        } else {
            DirectSample ds = sample_direct(scene, settings, sp, rng, counters);
            if (ds.valid) L += beta * sp.bsdf.eval(sp.wo, ds.wi) * ds.weighted;
        }

        float u_lobe = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        BsdfSample bs = sp.bsdf.sample(sp.wo, u, u_lobe);
        if (!bs.valid()) {
            ++counters.samples_rejected;
            break;
        }
        beta *= bs.value / bs.pdf;
        if (bs.transmission) eta_scale *= sqr(bs.eta);
        state.prev_delta = bs.delta;
        state.prev_pdf = bs.pdf;
        state.prev_p = hit.p;
        ray = Ray{spawn_origin(sp, bs.wi), bs.wi, 0.0f, kInf};
        if (!russian_roulette(state.depth, beta, eta_scale, rng) || is_black(beta)) break;
    }
    return L;
}

}  // namespace smis
