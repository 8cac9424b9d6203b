#include "integrators/path_tracing.h"

#include "integrators/rgb_throughput.h"
#include "integrators/volume.h"
#include "integrators/direct_lighting.h"
#include "integrators/subsurface_disk.h"
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

namespace {
// A lowered program's BSDF (scene/image_closure.h) where the hit's frame is its program's
// (Scene::hit_has_program_frame), as Scene::program_bsdf makes it: the closure normal is the
// interpolated one turned by ensure_valid_reflection, or that one where the turn fails (on every
// hit, flat ones too, unlike constant materials), and the closure has no holdout.
Bsdf image_closure_shading(const ImageClosure& closure, const SurfaceHit& hit, ShadingPoint& sp) {
    const Vec3 ns = shading::closure_normal(sp.ng, sp.wo, sp.ns, sp.ns);
    Bsdf bsdf = closure.bsdf(Frame(ns), sp.ng, sp.backfacing, hit.attr.uv);
    if (!(ns == sp.ns)) bsdf.set_bump_base(sp.ns);
    sp.ns = ns;
    return bsdf;
}
}  // namespace

// Out of line: the constant materials' path through make_shading_point stays as small as it was.
[[gnu::noinline]] Bsdf program_shading(const Scene& scene, const SurfaceHit& hit, ShadingPoint& sp,
                                       const ShaderRay* ray) {
    const Material& m = scene.material(hit.material);
    if (m.image_closure && scene.hit_has_program_frame(hit)) return image_closure_shading(*m.image_closure, hit, sp);
    return scene.program_bsdf(hit.material, hit.attr, sp.wo, sp.backfacing, ray ? *ray : ShaderRay{}, &sp.ns,
                              &sp.holdout);
}

DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, VertexSampler u,
                           LocalCounters& counters, int32_t medium, int light_samples, int bsdf_samples, bool glow) {
    auto transmittance = [&](const ShadowRay& shadow, int32_t towards) {
        return shadow_transmittance(scene, shadow.o, shadow.d, shadow.tmax, towards);
    };
    if (glow)
        return sample_direct_through<true>(scene, settings, sp, u, counters, medium, light_samples, bsdf_samples, transmittance);
    return sample_direct_through(scene, settings, sp, u, counters, medium, light_samples, bsdf_samples, transmittance);
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

bool subsurface_step(const Scene& scene, ShadingPoint& sp, const BsdfSample& bs, Color& beta, Rng& rng) {
    beta *= bs.value / bs.pdf;
    const Lobe entry = sp.bsdf.lobe(bs.lobe);
    return (entry.variant & SubsurfaceLobe::kDisk) ? subsurface_disk(scene, sp, entry, rng, &beta, &sp)
                                                   : subsurface_walk(scene, sp, entry, rng, &beta, &sp);
}

bool subsurface_bounce(const Scene& scene, const RenderSettings& settings, ShadingPoint& sp, BsdfSample& bs,
                       Color& beta, Rng& rng, LocalCounters& counters, int32_t medium, Color* direct) {
    if (!subsurface_step(scene, sp, bs, beta, rng)) return false;
    DirectSample ds = sample_direct(scene, settings, sp, rng, counters, medium);
    *direct = ds.valid ? beta * direct_eval(sp, ds) * ds.weighted : Color(0.0f);
    bs = sample_bsdf(sp, rng);
    return true;
}

Color trace_subsurface(const Scene& scene, const RenderSettings& settings, ShadingPoint sp, BsdfSample bs,
                       PathState state, Color beta, Rng& rng, LocalCounters& counters) {
    Color direct;
    if (!subsurface_bounce(scene, settings, sp, bs, beta, rng, counters, state.medium, &direct)) return Color(0.0f);
    Color L = clamp_contribution(settings, direct, state.depth == 0);
    if (!bs.valid()) {
        ++counters.samples_rejected;
        return L;
    }
    beta *= bs.value / bs.pdf;
    advance_ray_type(state, sp.bsdf, bs);
    if (scene.has_media()) state.medium = medium_towards(scene, sp, bs.wi, state.medium);
    state.prev_delta = bs.delta;
    state.prev_pdf = bs.pdf;
    state.prev_p = sp.hit.p;
    state.light_pdf_scale = 1.0f;
    state.transparent_background = false;
    const Ray ray = bounce_ray(sp, bs, state);
    ++state.depth;
    state.clamp_beta = beta;
    state.rr_scale = max_component(beta);
    return L + beta * trace_path(scene, settings, ray, state, rng, counters);
}

namespace {

template <bool kMedia, bool kRules>
Color trace_path_impl(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                      LocalCounters& counters, Sampler* camera) {
    return trace_path_loop<RgbThroughput, kMedia, kRules>(scene, settings, ray, state, rng, counters, RgbThroughput{},
                                                          camera);
}

// The loops with the light path rules, out of line: they leave trace_path's inlining budget to
// the plain loop, which every path of a scene without them takes (cornell, 8 spp: 1,376.1M
// instructions in the render loop against 1,377.8M before subsurface scattering).
[[gnu::noinline]] Color trace_path_with_rules(const Scene& scene, const RenderSettings& settings, Ray ray,
                                              PathState state, Rng& rng, LocalCounters& counters, Sampler* camera) {
    return scene.has_media() ? trace_path_impl<true, true>(scene, settings, ray, state, rng, counters, camera)
                             : trace_path_impl<false, true>(scene, settings, ray, state, rng, counters, camera);
}

}  // namespace

Color trace_path(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                 LocalCounters& counters, Sampler* camera) {
    if (uses_light_path_rules(scene, settings))
        return trace_path_with_rules(scene, settings, ray, state, rng, counters, camera);
    return scene.has_media() ? trace_path_impl<true, false>(scene, settings, ray, state, rng, counters, camera)
                             : trace_path_impl<false, false>(scene, settings, ray, state, rng, counters, camera);
}

}  // namespace smis
