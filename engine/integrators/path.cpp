#include "integrators/path.h"

namespace smis {

Color PathIntegrator::Li(const Scene& scene, const RenderSettings& settings, Ray ray, Rng& rng,
                         LocalCounters& counters) const {
    Color L(0.0f), beta(1.0f);
    float eta_scale = 1.0f;    // radiance scaling through refraction, undone for Russian roulette
    bool prev_delta = true;    // camera rays and Dirac bounces: emission is not MIS-weighted
    float prev_pdf = 0.0f;     // solid-angle pdf of the BSDF sample that produced `ray`
    Vec3 prev_p = ray.o;
    const MisHeuristic mis = settings.mis;
    const DiscreteDistribution& selection = scene.light_selection();

    // Emission found by following `ray`: weighted against light sampling unless it could not have
    // been light-sampled from the previous vertex.
    auto emitted = [&](float light_pmf, float light_pdf) {
        return prev_delta ? 1.0f : mis_weight(mis, prev_pdf, light_pmf * light_pdf);
    };

    for (int depth = 0;; ++depth) {
        SurfaceHit hit;
        bool found = scene.intersect(ray, &hit);
        Ray to_hit = ray;
        to_hit.tmax = found ? hit.t : kInf;
        // Area, point and spot lights are not in the BVH (as in Cycles): test them separately.
        scene.for_each_light_hit(to_hit, [&](uint32_t i, const LightHit& h) {
            if (depth == 0 && !scene.light(i).visible_to_camera) return;
            L += beta * h.L * emitted(scene.light_pmf(i), h.pdf);
        });
        if (!found) {
            LightHit h;
            for (uint32_t i : scene.infinite_lights())
                if ((depth > 0 || scene.light(i).visible_to_camera) && scene.light(i).intersect(to_hit, &h))
                    L += beta * h.L * emitted(scene.light_pmf(i), h.pdf);
            break;
        }
        const Material& mat = scene.material(hit.material);
        if (hit.light >= 0) {
            auto& tri = static_cast<const TriangleLight&>(scene.light(hit.light));
            L += beta * mat.emission * emitted(scene.light_pmf(hit.light), tri.pdf_at(prev_p, hit.p));
        }
        // The ray leaving the last allowed bounce only collects emission (Cycles' max_bounces).
        if (depth > settings.max_bounces) break;

        const Vec3 wo = -ray.d;
        const bool backfacing = dot(wo, hit.ng) < 0.0f;
        const Vec3 ng = backfacing ? -hit.ng : hit.ng;
        const Vec3 ns = backfacing ? -hit.ns : hit.ns;
        const Bsdf bsdf = mat.make_bsdf(Frame(ns), ng, backfacing);
        if (bsdf.empty()) break;

        // Next-event estimation: one light chosen in proportion to power, one point on it.
        if (!bsdf.is_delta() && !selection.empty()) {
            float u_select = rng.next_float();
            Point2 u{rng.next_float(), rng.next_float()};
            uint32_t li = static_cast<uint32_t>(selection.sample(u_select));
            float pmf = selection.pmf(li);
            const Light& light = scene.light(li);
            LightSample ls = light.sample(hit.p, u);
            if (!ls.valid()) {
                // A light seen from behind is simply dark; only numerical failures count as rejected.
                if (!std::isfinite(ls.pdf) || !is_finite(ls.L)) ++counters.samples_rejected;
            } else {
                Color f = bsdf.eval(wo, ls.wi);
                if (!is_black(f)) {
                    Vec3 origin = offset_ray_origin(hit.p, dot(ls.wi, ng) > 0.0f ? ng : -ng);
                    float tmax = std::isinf(ls.dist) ? kInf : ls.dist * (1.0f - 1e-4f);
                    if (!scene.occluded(origin, ls.wi, tmax)) {
                        float light_pdf = pmf * ls.pdf;
                        float w = ls.delta ? 1.0f : mis_weight(mis, light_pdf, bsdf.pdf(wo, ls.wi));
                        L += beta * f * ls.L * (w / light_pdf);
                    }
                }
            }
        }

        // Continue the path by sampling the BSDF.
        float u_lobe = rng.next_float();
        Point2 u{rng.next_float(), rng.next_float()};
        BsdfSample bs = bsdf.sample(wo, u, u_lobe);
        if (!bs.valid()) {
            ++counters.samples_rejected;
            break;
        }
        beta *= bs.value / bs.pdf;
        if (bs.transmission) eta_scale *= sqr(bs.eta);
        prev_delta = bs.delta;
        prev_pdf = bs.pdf;
        prev_p = hit.p;
        ray.o = offset_ray_origin(hit.p, dot(bs.wi, ng) > 0.0f ? ng : -ng);
        ray.d = bs.wi;
        ray.tmin = 0.0f;
        ray.tmax = kInf;

        // Russian roulette on the throughput (without the refraction scaling, which cancels on exit).
        if (depth >= 2) {
            float q = std::max(0.0f, 1.0f - max_component(beta) * eta_scale);
            q = std::min(q, 0.95f);
            if (rng.next_float() < q) break;
            beta = beta / (1.0f - q);
        }
        if (is_black(beta)) break;
    }
    return L;
}

}  // namespace smis
