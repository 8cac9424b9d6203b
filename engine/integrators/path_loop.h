// The unidirectional path loop, written once for every spectrum the path tracers carry: the RGB path
// tracer (path_tracing.cpp, RgbThroughput) and the spectral one (spectral_path.cpp, n wavelengths
// with their relative densities). The loop owns what does not depend on the spectrum: intersection
// (through media), the bounce limits and Light Path rules, shading-point set-up, holdouts and film
// transparency, the ray's state, BSDF and light sampling in one order of random numbers. A spectrum
// policy owns the throughput and what it does with each estimate:
//   emission(L, clamped, ...)       emission found along the ray (MIS-weighted), attenuated by media
//   scattering(L, ...)              the ray's single scattering in media (kMedia)
//   attenuate(media)                the throughput times the ray's transmittance (kMedia)
//   transparency_beta()             the RGB throughput that Film Transparent and holdouts count
//   is_black()                      no wavelength / channel carries anything any more
//   prepare(sp)                     the hit's BSDF as the spectrum samples it (dispersion)
//   direct(L, clamped, ..., u, ...) next-event estimation at the vertex, its light numbers u.light()
//   scatter(sp, bs)                 the throughput after the BSDF sample; false ends the path
//   after_scatter(state, bs)        after the Light Path state moved on
//   roulette(depth, eta, rng)       Russian roulette on the throughput; false ends the path
//   finish(counters)                per-path diagnostics
// and says whether its direct() weighs its light sample against GlowDirections' mixture when the
// loop sets state.glow_vertex (kGlowDirections: then the loop continues such vertices by the
// mixture, glow_directions.h),
// and says, as constants, whether it takes RIS at the first vertex (kResampledLights) and subsurface
// walks (kSubsurfaceWalks; without, the caller starts the path with the diffuse ancestor set, so
// Subsurface lobes render as their diffuse fallback), and whether the path ends at its first
// non-specular vertex, handed to first_vertex(sp, state, numbers) with that vertex's numbers
// (kEndsAtFirstVertex). Only the policies' headers include this file: rgb_throughput.h (the path
// tracer, RGB path-space filtering's prefix and suffix in psf_rgb.cpp) and spectral_throughput.h
// (the spectral path tracer, spectral path-space filtering's prefix and suffix in psf_spectral.cpp).
#pragma once
#include "integrators/aux_passes.h"
#include "integrators/direct_lighting.h"
#include "integrators/glow_directions.h"
#include "integrators/path_tracing.h"
#include "integrators/volume.h"

namespace smis {

// sample_direct (path_tracing.h) with the shadow ray's transmittance in media given by
// transmittance(shadow ray, medium it starts in) -> Color: the RGB one, or for a spectral path a
// stand-in (1 or 0) while it keeps its wavelengths' own. The light choice and point: u.light().
// kGlow: the vertex continues by GlowDirections' mixture, the BSDF-side density of the MIS weight (a
// template argument, so that the vertices without, all of them in scenes without media, pay nothing).
template <bool kGlow = false, class Transmittance>
DirectSample sample_direct_through(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                                   VertexSampler numbers, LocalCounters& counters, int32_t medium, int light_samples,
                                   int bsdf_samples, Transmittance&& transmittance) {
    DirectSample ds;
    const DiscreteDistribution& selection = scene.light_selection();
    // Draw the random numbers even when unused, so later decisions of the path keep their streams.
    const LightNumbers drawn = numbers.light();
    const float u_select = drawn.choice;
    const Point2 u = drawn.point;
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
    // Only Cycles' glass walks read it (ShadingPoint::light_wi): other renders skip the stores.
    if (settings.multiscatter_cycles_walk) sp.light_wi = ls.wi;
    const ShadowRay shadow = shadow_ray(sp, ls.wi, ls.dist);
    Color tr(1.0f);
    if (light.cast_shadow) {  // Cycles' Cast Shadow off: no shadow ray at all
        if (!scene.has_media()) {
            if (scene.occluded(shadow.o, shadow.d, shadow.tmax, shadow.time) || !reaches_mesh_light(scene, shadow, ls))
                return ds;
        } else {
            tr = transmittance(shadow, medium_towards(scene, sp, ls.wi, medium));
            if (is_black(tr) || !reaches_mesh_light(scene, shadow, ls)) return ds;
        }
    }
    float light_pdf = pmf * ls.pdf;
    const float n = float(light_samples);
    float w = 1.0f;
    if (!ls.delta && light.use_mis) {
        float bsdf_pdf = ds.hidden ? hidden_light_pdf(sp.bsdf, ds.hidden, sp.wo, ls.wi) : sp.bsdf.pdf(sp.wo, ls.wi);
        if constexpr (kGlow) bsdf_pdf = glow_light_mis_pdf(scene, sp, medium, ds.hidden, bsdf_pdf, ls.wi);
        w = mis_weight(settings.mis, n * light_pdf, float(bsdf_samples) * bsdf_pdf);
    }
    ds.wi = ls.wi;
    ds.light = li;
    ds.weighted = ls.L * tr * (w / (n * light_pdf));
    ds.valid = true;
    return ds;
}

// kMedia adds transmittance, medium tracking and single scattering, and is only instantiated for
// scenes with media, so the surface-only loop is unchanged for the others. kRules adds Cycles' ray
// types, per-type bounce limits, clamping and caustics toggles, only for scenes that hide something
// from some rays or settings that use them (uses_light_path_rules): without, every ray sees every
// object and light, so the types cannot change what a ray finds. It also carries subsurface
// scattering (walks, the diffuse ancestor), so scenes without pay nothing. The policy is the loop's
// own (pass a temporary). Always inlined into its caller, so the path tracer's plain loop sits in
// trace_path as it did before the policy (cornell, 8 spp, callgrind: +0.48% instructions against
// the loop before the policy when called, +0.24% inlined). `camera`: the pixel sample's Sampler
// when the path starts at the camera (rng is then its stream), else null: the path's first vertex
// asks it for its light, lobe and direction numbers by name (VertexSampler, core/sampler.h), so
// nothing drawn before that vertex (a scattering segment, resampling candidates) shifts them.
template <class Spectrum, bool kMedia, bool kRules>
[[gnu::always_inline]] inline Color trace_path_loop(const Scene& scene, const RenderSettings& settings, Ray ray,
                                                    PathState state, Rng& rng, LocalCounters& counters,
                                                    Spectrum path, Sampler* camera = nullptr) {
    auto clamped = [&](const Color& c, bool direct) {
        return kRules ? clamp_contribution(settings, c, direct, state.clamp_beta) : c;
    };
    Color L(0.0f);
    float eta_scale = 1.0f;
    ShaderRay sray;  // what the Light Path node reports for the next hit (scenes with programs)
    sray.camera = state.depth == 0;
    const bool programs = scene.has_programs() || scene.world_has_program();
    // Cycles' per-bounce numbers for the Principled Hair's longitudinal sample, on request only: they
    // are correlated between bounces, which biases multi-bounce hair (lobes/principled_hair.h).
    if (programs && settings.hair_cycles_sampling) sray.path_key = shader_path_key(ray.o, ray.d);
    // Cycles' multiscatter glass walks draw from a per-vertex LCG whose seeds along a path are 16 apart
    // (lobes/multi_glass_walk.h, seed_cycles_glass_walk): the key stands for Cycles' per-path part.
    const uint32_t walk_key = kRules && settings.multiscatter_cycles_walk ? shader_path_key(ray.o, ray.d) : 0u;
    for (;; ++state.depth) {
        SurfaceHit hit;
        bool found;
        // The camera ray's auxiliary passes, when on (aux_passes.h), from its hit: the one the passes'
        // own ray would find unless this ray passed a medium boundary, where theirs stops.
        bool passes_at_hit = false;
        if constexpr (kMedia) {
            RayMedia media;
            found = intersect_through(scene, ray, state.medium, &hit, &media);
            if (counters.camera_media) {  // the camera ray's media for the photon planes' gather
                *counters.camera_media = media;
                counters.camera_media = nullptr;
            }
            if (state.depth == 0 && counters.passes && !media.crossed)
                passes_at_hit = counters.passes->at_camera_ray(scene, found, hit);
            media.plane_segments = state.plane_segments;
            media.plane_keep = state.plane_keep;
            path.emission(L, clamped, scene, settings, ray, found, hit, state, &media, &sray);
            // Single scattering at this bounce (Cycles' volume bounces = 0: no path continues from
            // a scattering vertex, so only its next-event estimate counts).
            if (state.depth <= settings.max_bounces)
                path.scattering(L, scene, ray, media, rng, counters, state.depth == 0 && state.planes_on_camera_ray);
            path.attenuate(media);
            if (add_transparency(settings, state, found, hit, path.transparency_beta(), counters)) break;
            state.medium = media.end_medium;
            if (path.is_black()) break;
        } else {
            found = scene.intersect(ray, &hit);
            if (state.depth == 0 && counters.passes) passes_at_hit = counters.passes->at_camera_ray(scene, found, hit);
            path.emission(L, clamped, scene, settings, ray, found, hit, state, nullptr, &sray);
            if (add_transparency(settings, state, found, hit, path.transparency_beta(), counters)) break;
        }
        // The ray leaving the last allowed bounce only collects emission (Cycles' bounce limits).
        if (!found || (kRules ? beyond_bounce_limits(settings, state) : state.depth > settings.max_bounces)) break;
        if (programs) {
            sray.depth = state.depth;
            sray.length = hit.t;
        }
        ShadingPoint sp = make_shading_point(scene, hit, ray.d, &sray);
        if (passes_at_hit) counters.passes->at_first_hit(scene, sp);  // as shaded, before the path's rules
        if (holdout_ends_path(state, sp, path.transparency_beta(), counters)) break;
        if constexpr (kRules) {
            light_path_lobes(settings, state, sp);
            if (walk_key) sp.bsdf.change_lobes([&](Lobe& l) { seed_cycles_glass_walk(l, walk_key, state.depth); });
            if (state.diffuse_ancestor && scene.has_subsurface()) sp.bsdf.subsurface_as_diffuse();
        }
        if (sp.bsdf.empty()) break;
        path.prepare(sp);
        const VertexSampler numbers(rng, camera);
        camera = nullptr;  // the vertices after this one draw from the stream
        if constexpr (Spectrum::kEndsAtFirstVertex) {
            // Path-space filtering's prefix (psf_rgb.cpp, psf_spectral.cpp): the policy records the
            // first non-specular vertex x1 and the path ends there.
            if (state.first_vertex_ahead && !sp.bsdf.is_delta()) {
                path.first_vertex(sp, state, numbers);
                break;
            }
        }

        // Light-aimed continuations at vertices in fog (glow_directions.h), for the policies that weigh
        // their light sample with state.glow_vertex (kGlowDirections), and not where RIS or ReSTIR
        // weigh it (their weights take the BSDF's density alone). Only in scenes with media.
        [[maybe_unused]] GlowDirections glow;
        if constexpr (kMedia && Spectrum::kGlowDirections) {
            const bool resampled = Spectrum::kResampledLights && kWithResampledLights && state.first_vertex_ahead &&
                                   !sp.bsdf.is_delta() && settings.direct_light != DirectLightStrategy::Nee;
            if (!resampled && !scene.glow_lights().empty() && settings.glow_directions)
                glow = GlowDirections(scene, sp, state.medium);
            state.glow_vertex = glow.on();
        }
        if constexpr (Spectrum::kResampledLights) {
            bool resample = false;
            if (kWithResampledLights && state.first_vertex_ahead && !sp.bsdf.is_delta()) {
                state.first_vertex_ahead = false;
                // RIS, or ReSTIR's stage 1 on spectral paths (the policy records the vertex); the RGB
                // path tracer meets ReSTIR only after this vertex (restir.cpp traces the prefix).
                resample = settings.direct_light != DirectLightStrategy::Nee;
            }
            state.light_pdf_scale = resample ? resampled_light_pdf_scale(settings) : 1.0f;
            if (resample) path.resampled_direct(L, clamped, scene, settings, sp, rng, state);
            else path.direct(L, clamped, scene, settings, sp, numbers, counters, state);
        } else {
            state.light_pdf_scale = 1.0f;
            path.direct(L, clamped, scene, settings, sp, numbers, counters, state);
        }

        // Cycles' glass walks sample from the LCG state their light sample's eval left.
        if (walk_key && !(sp.light_wi == Vec3(0.0f, 0.0f, 0.0f))) after_cycles_light_eval(sp.bsdf, sp.wo, sp.light_wi);
        BsdfSample bs;
        if constexpr (kMedia && Spectrum::kGlowDirections) {
            if (glow.on()) {
                // The vertex's lobe and direction numbers in sample_bsdf's order, then one from the
                // stream for the technique and the light.
                const float u_lobe = numbers.lobe();
                const Point2 u_dir = numbers.direction();
                if (!glow.sample(sp, u_lobe, u_dir, rng.next_float(), &bs)) break;
            } else {
                bs = sample_bsdf(sp, numbers);
            }
        } else {
            bs = sample_bsdf(sp, numbers);
        }
        if constexpr (kRules && Spectrum::kSubsurfaceWalks) {
            if (picks_subsurface(sp, bs)) {
                if (!path.subsurface(L, clamped, scene, settings, sp, bs, rng, counters, state)) break;
            }
        }
        if (!bs.valid()) {
            ++counters.samples_rejected;
            break;
        }
        if (!path.scatter(sp, bs)) break;
        if (bs.transmission) eta_scale *= sqr(bs.eta);
        if (programs) next_shader_ray(sp.bsdf, bs, &sray);
        update_transparent_background(settings, state, sp.bsdf, bs);
        path.after_scatter(state, bs);
        if constexpr (kRules) advance_ray_type(state, sp.bsdf, bs);
        if constexpr (kMedia) state.medium = medium_towards(scene, sp, bs.wi, state.medium);
        state.prev_delta = bs.delta;
        state.prev_pdf = bs.pdf;
        state.prev_p = sp.hit.p;
        ray = kRules ? bounce_ray(sp, bs, state) : Ray{spawn_origin(sp, bs.wi), bs.wi, 0.0f, kInf, hit.time};
        if (!path.roulette(state.depth, eta_scale * state.rr_scale, rng)) break;
    }
    path.finish(counters);
    return L;
}

}  // namespace smis
