#include "integrators/path_tracing.h"

#include "integrators/volume.h"
#include "integrators/direct_lighting.h"
#include "integrators/subsurface_walk.h"
#include "shading/normals.h"

namespace smis {

ShadingPoint make_shading_point(const Scene& scene, const SurfaceHit& hit, const Vec3& ray_dir, const ShaderRay* ray) {
    ShadingPoint sp;
    sp.hit = hit;
    sp.wo = -ray_dir;
    sp.backfacing = dot(sp.wo, hit.ng) < 0.0f;
    sp.ng = sp.backfacing ? -hit.ng : hit.ng;
    sp.ns = sp.backfacing ? -hit.ns : hit.ns;
    const Material& m = scene.material(hit.material);
    if (m.program) sp.bsdf = program_shading(scene, hit, sp, ray);
    else if (hit.ns == hit.ng) m.make_bsdf_into(&sp.bsdf, Frame(sp.ns), sp.ng, sp.backfacing, hit.attr);
    else constant_bsdf_on_closure_normal(m, sp.ns, sp.ng, sp.wo, sp.backfacing, hit.attr, &sp.bsdf, &sp.ns);
    return sp;
}

[[gnu::noinline]] void constant_bsdf_on_closure_normal(const Material& m, Vec3 interpolated_ns, const Vec3& ng,
                                                       const Vec3& wo, bool backfacing, const SurfaceAttribs& attr,
                                                       Bsdf* bsdf, Vec3* closure_ns) {
    *closure_ns = shading::ensure_valid_reflection(ng, wo, interpolated_ns);
    m.make_bsdf_into(bsdf, Frame(*closure_ns), ng, backfacing, attr);
    if (!(*closure_ns == interpolated_ns)) bsdf->set_bump_base(interpolated_ns);
}

// Out of line: the constant materials' path through make_shading_point stays as small as it was.
[[gnu::noinline]] Bsdf program_shading(const Scene& scene, const SurfaceHit& hit, ShadingPoint& sp,
                                       const ShaderRay* ray) {
    return scene.program_bsdf(hit.material, hit.attr, sp.wo, sp.backfacing, ray ? *ray : ShaderRay{}, &sp.ns,
                              &sp.holdout);
}

DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                           LocalCounters& counters, int32_t medium, int light_samples, int bsdf_samples) {
    DirectSample ds;
    const DiscreteDistribution& selection = scene.light_selection();
    // Draw the random numbers even when unused, so later decisions of the path keep their streams.
    float u_select = rng.next_float();
    Point2 u{rng.next_float(), rng.next_float()};
    if (sp.bsdf.is_delta() || selection.empty()) return ds;
    uint32_t li = static_cast<uint32_t>(selection.sample(u_select));
    float pmf = selection.pmf(li);
    const Light& light = scene.light(li);
    // A light hidden from some ray types lights only the other lobes (Cycles' light visibility);
    // their mixture is also the BSDF density its MIS weight counts.
    ds.hidden = ~light.visibility & kRayBounceTypes;
    if (ds.hidden && hidden_light_lights_nothing(sp.bsdf, ds.hidden)) return ds;
    LightSample ls = light.sample_at(sp.hit.p, u, sp.hit.time);
    if (!ls.valid()) {
        // A light seen from behind is simply dark; only numerical failures count as rejected.
        if (!std::isfinite(ls.pdf) || !is_finite(ls.L)) ++counters.samples_rejected;
        return ds;
    }
    const ShadowRay shadow = shadow_ray(sp, ls.wi, ls.dist);
    Color tr(1.0f);
    if (light.cast_shadow) {  // Cycles' Cast Shadow off: no shadow ray at all
        if (!scene.has_media()) {
            if (scene.occluded(shadow.o, shadow.d, shadow.tmax, shadow.time) || !reaches_mesh_light(scene, shadow, ls))
                return ds;
        } else {
            tr = shadow_transmittance(scene, shadow.o, shadow.d, shadow.tmax, medium_towards(scene, sp, ls.wi, medium));
            if (is_black(tr) || !reaches_mesh_light(scene, shadow, ls)) return ds;
        }
    }
    float light_pdf = pmf * ls.pdf;
    const float n = float(light_samples);
    float w = ls.delta || !light.use_mis ? 1.0f : mis_weight(settings.mis, n * light_pdf,
                         float(bsdf_samples) * (ds.hidden ? hidden_light_pdf(sp.bsdf, ds.hidden, sp.wo, ls.wi)
                                                          : sp.bsdf.pdf(sp.wo, ls.wi)));
    ds.wi = ls.wi;
    ds.light = li;
    ds.weighted = ls.L * tr * (w / (n * light_pdf));
    ds.valid = true;
    return ds;
}

Color hidden_light_eval(const Bsdf& bsdf, uint32_t hidden, const Vec3& wo, const Vec3& wi) {
    return lobes_not_of(bsdf, hidden).eval(wo, wi);
}

float hidden_light_pdf(const Bsdf& bsdf, uint32_t hidden, const Vec3& wo, const Vec3& wi) {
    return lobes_not_of(bsdf, hidden).pdf(wo, wi);
}

bool hidden_light_lights_nothing(const Bsdf& bsdf, uint32_t hidden) {
    const Bsdf lit = lobes_not_of(bsdf, hidden);
    return lit.empty() || lit.is_delta();
}

ShadingPoint lit_lobes(const ShadingPoint& sp, const DirectSample& ds) {
    ShadingPoint lit = sp;
    lit.bsdf = lobes_not_of(sp.bsdf, ds.hidden);
    return lit;
}

void next_shader_ray(const Bsdf& bsdf, const BsdfSample& bs, ShaderRay* ray) {
    RayLabel label = bs.lobe >= 0 ? lobe_label(bsdf.lobe(bs.lobe)) : RayLabel::Diffuse;
    bool diffuse = !bs.delta && label == RayLabel::Diffuse;
    ray->camera = false;
    ray->singular = bs.delta;
    ray->diffuse = diffuse;
    ray->glossy = !bs.delta && !diffuse;
    ray->transmission = bs.transmission;
    ray->reflection = !bs.transmission;
    if (label == RayLabel::Transparent) ++ray->transparent_depth;
    else if (bs.transmission) ++ray->transmission_depth;
    else if (diffuse) ++ray->diffuse_depth;
    else ++ray->glossy_depth;
}

float russian_roulette_survival(int depth, float max_beta, float eta_scale, Rng& rng) {
    float u = rng.next_float();
    if (depth < 2) return 1.0f;
    // On the throughput without the refraction scaling, which cancels when the path leaves the medium.
    float q = std::min(0.95f, std::max(0.0f, 1.0f - max_beta * eta_scale));
    if (u < q) return 0.0f;
    return 1.0f - q;
}

namespace {

// Cycles' subsurface bounce at sp, whose BSDF sample bs picked a Subsurface lobe: the walk to the
// exit, which becomes sp, then the exit's light sample (*direct, with the throughput) and its BSDF
// sample (bs), at the entry's depth (the walk is no bounce of the path in Cycles). False: the path
// ends. Out of line, so the loops stay as they were for scenes without subsurface.
[[gnu::noinline]] bool subsurface_bounce(const Scene& scene, const RenderSettings& settings, ShadingPoint& sp,
                                         BsdfSample& bs, Color& beta, Rng& rng, LocalCounters& counters,
                                         int32_t medium, Color* direct) {
    beta *= bs.value / bs.pdf;
    const Lobe entry = sp.bsdf.lobe(bs.lobe);
    if (!subsurface_walk(scene, sp, entry, rng, &beta, &sp)) return false;
    DirectSample ds = sample_direct(scene, settings, sp, rng, counters, medium);
    *direct = ds.valid ? beta * direct_eval(sp, ds) * ds.weighted : Color(0.0f);
    bs = sample_bsdf(sp, rng);
    return true;
}

// The path tracer; kMedia adds transmittance, medium tracking and single scattering, and is only
// instantiated for scenes with media, so the surface-only loop is unchanged for the others. kRules
// adds Cycles' ray types, per-type bounce limits, clamping and caustics toggles, only for scenes
// that hide something from some rays or settings that use them (uses_light_path_rules): without,
// every ray sees every object and light, so the types cannot change what a ray finds. It also
// carries subsurface scattering (walks, the diffuse ancestor), so scenes without pay nothing.
template <bool kMedia, bool kRules>
Color trace_path_impl(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                      LocalCounters& counters) {
    auto clamped = [&](const Color& c, bool direct) {
        return kRules ? clamp_contribution(settings, c, direct, state.clamp_beta) : c;
    };
    Color L(0.0f), beta(1.0f);
    float eta_scale = 1.0f;
    ShaderRay sray;  // what the Light Path node reports for the next hit (scenes with programs)
    sray.camera = state.depth == 0;
    const bool programs = scene.has_programs() || scene.world_has_program();
    for (;; ++state.depth) {
        SurfaceHit hit;
        bool found;
        if constexpr (kMedia) {
            RayMedia media;
            found = intersect_through(scene, ray, state.medium, &hit, &media);
            L += clamped(beta * emission_along(scene, settings, ray, found, hit, state, &media, &sray), state.depth <= 1);
            // Single scattering at this bounce (Cycles' volume bounces = 0: no path continues from
            // a scattering vertex, so only its next-event estimate counts).
            if (state.depth <= settings.max_bounces)
                L += beta * single_scattering(scene, ray, media, rng, counters,
                                              state.depth == 0 && state.planes_on_camera_ray);
            beta *= media.transmittance_to_end();
            if (add_transparency(settings, state, found, hit, beta, counters)) break;
            state.medium = media.end_medium;
            if (is_black(beta)) break;
        } else {
            found = scene.intersect(ray, &hit);
            if (state.depth == 0 && settings.aux_passes && !settings.aux_shading)  // the Z pass alone
                counters.camera_depth = found ? scene.camera().view_depth(hit.p) : kBackgroundDepth;
            L += clamped(beta * emission_along(scene, settings, ray, found, hit, state, nullptr, &sray), state.depth <= 1);
            if (add_transparency(settings, state, found, hit, beta, counters)) break;
        }
        // The ray leaving the last allowed bounce only collects emission (Cycles' bounce limits).
        if (!found || (kRules ? beyond_bounce_limits(settings, state) : state.depth > settings.max_bounces)) break;
        if (programs) {
            sray.depth = state.depth;
            sray.length = hit.t;
        }
        ShadingPoint sp = make_shading_point(scene, hit, ray.d, &sray);
        if (holdout_ends_path(state, sp, beta, counters)) break;
        if constexpr (kRules) {
            light_path_lobes(settings, state, sp);
            if (state.diffuse_ancestor && scene.has_subsurface()) sp.bsdf.subsurface_as_diffuse();
        }
        if (sp.bsdf.empty()) break;

        bool resample = false;
        if (kWithResampledLights && state.first_vertex_ahead && !sp.bsdf.is_delta()) {
            state.first_vertex_ahead = false;
            resample = settings.direct_light == DirectLightStrategy::Ris;
        }
        state.light_pdf_scale = resample ? resampled_light_pdf_scale(settings) : 1.0f;
        if (resample) {
            L += clamped(beta * ris_direct(scene, settings, sp, rng, state.medium), state.depth == 0);
        } else {
            DirectSample ds = sample_direct(scene, settings, sp, rng, counters, state.medium);
            if (ds.valid)
                L += clamped(beta * direct_eval(sp, ds) * ds.weighted, state.depth == 0);
        }

        BsdfSample bs = sample_bsdf(sp, rng);
        if constexpr (kRules) {
            if (bs.delta && bs.lobe >= 0 && sp.bsdf.lobe(bs.lobe).kind == LobeKind::Subsurface) {
                Color direct;
                if (!subsurface_bounce(scene, settings, sp, bs, beta, rng, counters, state.medium, &direct)) break;
                L += clamped(direct, state.depth == 0);
            }
        }
        if (!bs.valid()) {
            ++counters.samples_rejected;
            break;
        }
        beta *= bs.value / bs.pdf;
        if (bs.transmission) eta_scale *= sqr(bs.eta);
        if (programs) next_shader_ray(sp.bsdf, bs, &sray);
        update_transparent_background(settings, state, sp.bsdf, bs);
        if constexpr (kRules) advance_ray_type(state, sp.bsdf, bs);
        if constexpr (kMedia) state.medium = medium_towards(scene, sp, bs.wi, state.medium);
        state.prev_delta = bs.delta;
        state.prev_pdf = bs.pdf;
        state.prev_p = sp.hit.p;
        ray = kRules ? bounce_ray(sp, bs, state) : Ray{spawn_origin(sp, bs.wi), bs.wi, 0.0f, kInf, hit.time};
        if (!russian_roulette(state.depth, beta, eta_scale * state.rr_scale, rng) || is_black(beta)) break;
    }
    return L;
}

// The loops with the light path rules, out of line: they leave trace_path's inlining budget to
// the plain loop, which every path of a scene without them takes (cornell, 8 spp: 1,376.1M
// instructions in the render loop against 1,377.8M before subsurface scattering).
[[gnu::noinline]] Color trace_path_with_rules(const Scene& scene, const RenderSettings& settings, Ray ray,
                                              PathState state, Rng& rng, LocalCounters& counters) {
    return scene.has_media() ? trace_path_impl<true, true>(scene, settings, ray, state, rng, counters)
                             : trace_path_impl<false, true>(scene, settings, ray, state, rng, counters);
}

}  // namespace

Color trace_path(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                 LocalCounters& counters) {
    if (uses_light_path_rules(scene, settings)) return trace_path_with_rules(scene, settings, ray, state, rng, counters);
    return scene.has_media() ? trace_path_impl<true, false>(scene, settings, ray, state, rng, counters)
                             : trace_path_impl<false, false>(scene, settings, ray, state, rng, counters);
}

}  // namespace smis
