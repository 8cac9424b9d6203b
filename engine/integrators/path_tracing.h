// Building blocks of unidirectional path tracing, shared by the path tracer and by the integrators
// that reuse parts of paths (path-space filtering): shading-point set-up, next-event estimation,
// emission found along a ray with its MIS weight, and tracing the rest of a path.
#pragma once
#include <type_traits>

#include "core/sampler.h"
#include "integrators/integrator.h"
#include "scene/lobe_ray_types.h"

namespace smis {

// A surface hit ready for shading: frames facing the incoming direction, as Cycles does.
struct ShadingPoint {
    SurfaceHit hit;
    Vec3 wo;          // towards the previous vertex
    Vec3 ng, ns;      // geometric and shading normals, flipped to the side of wo
    bool backfacing;  // the ray arrived from the back of the triangle (inside a closed glass object)
    Color holdout{0.0f};  // the Holdout closures' weight (node-tree materials)
    Bsdf bsdf;
    // The direction of the vertex's light sample, whether or not it reaches the light (zero: none
    // drawn): Cycles evaluates the BSDF before its shadow test, and that eval moves the LCG its
    // multiscatter glass walks share (multiscatter_cycles_walk; lobes/multi_glass_walk.h). Set only
    // with that setting (sample_direct_through).
    mutable Vec3 light_wi{0.0f, 0.0f, 0.0f};
};
// `ray` describes the ray that found the hit, for materials whose nodes read the Light Path
// (null: a camera ray).
ShadingPoint make_shading_point(const Scene& scene, const SurfaceHit& hit, const Vec3& ray_dir,
                                const ShaderRay* ray = nullptr);
Bsdf program_shading(const Scene& scene, const SurfaceHit& hit, ShadingPoint& sp, const ShaderRay* ray);
// A constant material's BSDF into *bsdf on the normal Cycles 3.4 gives a closure (*closure_ns):
// the interpolated shading normal (flipped to wo's side) turned towards ng just far enough that wo's
// mirror direction stays above the surface (svm_node_closure_bsdf applies it to every closure, not
// only to Bump and Normal Map outputs: near a smooth mesh's sharp rims the interpolated normal can
// face away from the viewer). A turned normal also brings the bump shadowing term of diffuse lobes,
// as any closure normal that differs from N does in Cycles. Out of line: flat-shaded hits, whose
// mirror of wo about ng is always above the surface, keep make_shading_point's short path.
void constant_bsdf_on_closure_normal(const Material& m, Vec3 interpolated_ns, const Vec3& ng, const Vec3& wo,
                                     bool backfacing, const SurfaceAttribs& attr, Bsdf* bsdf, Vec3* closure_ns);
// The Light Path state after the vertex scattered along `bs` (Cycles' path flags and depths).
void next_shader_ray(const Bsdf& bsdf, const BsdfSample& bs, ShaderRay* ray);
// Origin for a ray leaving the shading point in direction d (offset to the correct side).
inline Vec3 spawn_origin(const ShadingPoint& sp, const Vec3& d) {
    return offset_ray_origin(sp.hit.p, dot(d, sp.ng) > 0.0f ? sp.ng : -sp.ng);
}
// Shadow rays start at the offset origin and are aimed at the target point itself, stopping 1e-4 of
// the way short of it. The offset (256 ulps along the normal: 3e-5 at coordinates near 2) brings the
// origin closer to the target's plane, so along the direction from the unoffset point the ray met
// that plane (a mesh light's own triangle) before dist * (1 - 1e-4) whenever the shading point lay
// within up to 0.3 |p| of it (|p| its coordinates, times the normals' cosine): a mesh light 5 cm
// below a ceiling never lit it through light samples, only through the BSDF samples' MIS share.
struct ShadowRay {
    Vec3 o, d;
    float tmax;
    float time = kShutterCentre;  // the path's time in the shutter (motion blur)
};
// From origin o to `target`; (wi, dist) from the unoffset point, used if o is degenerate.
inline ShadowRay shadow_ray_from(const Vec3& o, const Vec3& target, const Vec3& wi, float dist) {
    Vec3 to = target - o;
    float len = length(to);
    if (!(len > 0.0f) || !std::isfinite(len)) return {o, wi, dist * (1.0f - 1e-4f)};
    return {o, to / len, len * (1.0f - 1e-4f)};
}
// From the shading point to the point `dist` along `wi` (a light sample; at infinity when dist is).
inline ShadowRay shadow_ray(const ShadingPoint& sp, const Vec3& wi, float dist) {
    Vec3 o = spawn_origin(sp, wi);
    ShadowRay s = std::isinf(dist) ? ShadowRay{o, wi, kInf} : shadow_ray_from(o, sp.hit.p + wi * dist, wi, dist);
    s.time = sp.hit.time;
    return s;
}
// The same between two surface points: from p (geometric normal ng, either side) to `target`
// (path-space filtering's connections).
inline ShadowRay shadow_ray_between(const Vec3& p, const Vec3& ng, const Vec3& target) {
    Vec3 d = target - p;
    float dist = length(d);
    Vec3 wi = d / dist;
    return shadow_ray_from(offset_ray_origin(p, dot(wi, ng) > 0.0f ? ng : -ng), target, wi, dist);
}
// The stretch a shadow ray leaves out before a mesh light (its last 1e-4) holds the light's own
// triangle, and possibly a wall that meets the light at an edge (a lamp's housing, a box around an
// emissive panel): light points that close to the wall lit whatever lay behind it, through it. The
// first surface in that stretch must be an emitter. Such a wall meets the light along an edge, so
// only light points near an edge are tested (within 10x the stretch: walls down to 6 degrees from
// the light's plane; the test costs a closest hit, 20% of a Cornell box's time when every sample
// paid it); an object standing on the middle of an emissive triangle still leaks along its base.
// Lamps are not geometry: nothing to test.
inline bool reaches_mesh_light(const Scene& scene, const ShadowRay& s, const LightSample& ls) {
    // Lamps and lights at infinity sample no edge (kInf); the comparison is false for them.
    const float len = s.tmax / (1.0f - 1e-4f);
    if (!(ls.edge_distance <= 1e-3f * len)) return true;
    SurfaceHit hit;
    return !scene.intersect(Ray{s.o, s.d, s.tmax, len * (1.0f + 2e-4f), s.time, kRayShadow}, &hit) || hit.light >= 0;
}

// The MIS state carried from one vertex to the next.
struct PathState {
    int depth = 0;           // bounces before the vertex the next ray will find (Cycles' bounce)
    bool prev_delta = true;  // camera rays and Dirac bounces: emission is not MIS-weighted
    float prev_pdf = 0.0f;   // solid-angle pdf of the BSDF sample that produced the ray
    Vec3 prev_p;             // where that ray started (for the triangle lights' pdf)
    // Media (only read when Scene::has_media()): the medium the next ray starts in, and whether
    // photon planes estimate the camera ray's single scattering from their lights, and on which of its
    // media segments. (The pointer first, at offset 24: after the bools it took 16 bytes of padding,
    // and a larger PathState costs every path.)
    const uint32_t* plane_keep = nullptr;  // RayMedia::plane_keep of the camera ray
    int32_t medium = -1;
    bool planes_on_camera_ray = false;
    uint8_t plane_segments = 0xff;  // of those, RayMedia::plane_segments of the camera ray
    // A camera path before its first non-specular vertex, where settings.direct_light applies.
    bool first_vertex_ahead = false;
    // Cycles' PATH_RAY_DIFFUSE_ANCESTOR: the path made a diffuse bounce, and subsurface scattering
    // renders as diffuse from here on (Bsdf::subsurface_as_diffuse). Integrators without subsurface
    // walks start their paths with it set. (Here, in padding: a larger PathState cost every path.)
    bool diffuse_ancestor = false;
    // The previous vertex's light-sampling density, for MIS, as a multiple of the NEE density
    // (pmf x light pdf): M for resampled light sampling (RIS, ReSTIR), see reservoir_contribution;
    // n_light / n_bsdf for n_light light and n_bsdf BSDF samples (path-space filtering's
    // psf_light_samples and extra paths at x1).
    float light_pdf_scale = 1.0f;
    // Throughput of the path before the ray this state starts with (max component, refraction
    // scaling included), for Russian roulette only: a path traced in pieces (path-space filtering's
    // suffix) then stops with the same probabilities as the whole path would.
    float rr_scale = 1.0f;
    // Cycles' PATH_RAY_TRANSPARENT_BACKGROUND: a camera path that has so far only passed through
    // transparent surfaces (cut-outs, Transparent lobes). With Film Transparent, the World it
    // reaches is a hole in the film, not colour: emission_along leaves it out and the path's mean
    // throughput there counts as transparency (alpha = 1 - its mean, Film::resolve); a holdout
    // object it meets is such a hole whatever the film (add_transparency). Any other bounce clears it.
    bool transparent_background = false;
    // The vertex being shaded continues by GlowDirections' mixture (glow_directions.h), so its light
    // sample weighs against that density; set by the path loop per vertex. (In padding: PathState
    // keeps its size.)
    bool glow_vertex = false;
    // Cycles' path flags of the ray this state starts with (ray_visibility.h): kRayCamera, or the
    // last bounce's type (a Transparent lobe keeps the flags), and the bounces of each type so far
    // for the per-type limits (RenderSettings::max_diffuse_bounces ...).
    uint32_t ray_flags = kRayCamera;
    uint16_t diffuse_bounces = 0, glossy_bounces = 0, transmission_bounces = 0, transparent_bounces = 0;
    // Cycles' min_ray_pdf: the smallest density of the non-Dirac BSDF samples (not through
    // Transparent lobes) that led here, for Filter Glossy (blur_glossy_lobes).
    float min_ray_pdf = kInf;
    // The RGB throughput before the ray this state starts with, for clamping only: a path traced in
    // pieces (ReSTIR's and path-space filtering's continuations) clamps each contribution as the
    // whole path would, since Cycles compares throughput x radiance with the limit.
    Color clamp_beta{1.0f};
};
// After the vertex scattered along `bs`: the next ray's flags and the per-type counts, labelled as
// Cycles labels the event (path_state_next): a Dirac or glossy reflection is glossy, a
// transmission of any lobe counts as transmission (and is diffuse or glossy for light visibility).
inline void advance_ray_type(PathState& st, const Bsdf& bsdf, const BsdfSample& bs) {
    const RayLabel label = bs.lobe >= 0 ? lobe_label(bsdf.lobe(bs.lobe)) : RayLabel::Diffuse;
    if (label == RayLabel::Transparent) {
        ++st.transparent_bounces;
        return;
    }
    // Cycles' Dirac closures report a density of 1e6: they never lower min_ray_pdf.
    if (!bs.delta) st.min_ray_pdf = std::min(st.min_ray_pdf, bs.pdf);
    const uint32_t kind = !bs.delta && label == RayLabel::Diffuse ? kRayDiffuse : kRayGlossy;
    st.diffuse_ancestor = st.diffuse_ancestor || kind == kRayDiffuse;
    if (bs.transmission) ++st.transmission_bounces;
    else if (kind == kRayDiffuse) ++st.diffuse_bounces;
    else ++st.glossy_bounces;
    st.ray_flags = bs.transmission ? kind | kRayTransmission : kind;
}
// The ray leaving sp along bs, seen by the objects visible to its type (after advance_ray_type).
inline Ray bounce_ray(const ShadingPoint& sp, const BsdfSample& bs, const PathState& st) {
    return Ray{spawn_origin(sp, bs.wi), bs.wi, 0.0f, kInf, sp.hit.time, ray_mask(st.ray_flags)};
}
// Cycles' bounce limits: the vertex the state's ray finds is shaded (light samples, a new bounce)
// only while the path has made at most max_bounces bounces in all and at most the per-type limit
// of each type; beyond, its ray only collects emission.
inline bool beyond_bounce_limits(const RenderSettings& s, const PathState& st) {
    return st.depth > s.max_bounces || st.diffuse_bounces > s.max_diffuse_bounces ||
           st.glossy_bounces > s.max_glossy_bounces || st.transmission_bounces > s.max_transmission_bounces ||
           st.transparent_bounces > s.max_transparent_bounces;
}
// Whether the scene or the settings use what PathState's ray types serve: an object or light hidden
// from some rays (Scene::has_ray_visibility), per-type bounce limits below max_bounces, clamping or
// a caustics toggle off, Filter Glossy, or subsurface scattering (its walks, and the diffuse
// ancestor). Without, a path that keeps every ray type renders the same image, and the path tracer
// takes its loop without them (trace_path).
inline bool uses_light_path_rules(const Scene& scene, const RenderSettings& s) {
    const int limit = std::min({s.max_diffuse_bounces, s.max_glossy_bounces, s.max_transmission_bounces,
                                s.max_transparent_bounces});
    return scene.has_ray_visibility() || scene.has_subsurface() || limit < s.max_bounces || s.clamp_direct > 0.0f ||
           s.clamp_indirect > 0.0f || !s.caustics_reflective || !s.caustics_refractive || s.filter_glossy > 0.0f ||
           s.multiscatter_cycles_walk || s.beckmann_cycles_sampling;
}
// Cycles' Clamp Direct / Clamp Indirect (0 = off): a contribution whose mean |RGB| exceeds the
// limit is scaled down to it (Cycles compares the sum with 3 x the setting). Direct: light samples
// at the first vertex and emission found by the camera ray or by the first vertex's bounce (path
// depth <= 1, Cycles' bounce - 1 <= 0); everything else is indirect.
// `before`: the throughput of the path before the piece whose contribution c is (PathState::clamp_beta).
inline Color clamp_contribution(const RenderSettings& s, const Color& c, bool direct, const Color& before = Color(1.0f)) {
    const float limit = direct ? s.clamp_direct : s.clamp_indirect;
    if (!(limit > 0.0f)) return c;
    const Color full = c * before;
    const float sum = std::fabs(full.x) + std::fabs(full.y) + std::fabs(full.z);
    return sum > 3.0f * limit ? c * (3.0f * limit / sum) : c;
}
// The same for one of n samples of an estimate, given its share c (its full value / n): the sample
// is clamped as Cycles clamps a single sample, then shared.
inline Color clamp_sample_share(const RenderSettings& s, const Color& c, int n, bool direct) {
    return n == 1 ? clamp_contribution(s, c, direct) : clamp_contribution(s, c * float(n), direct) / float(n);
}
// The state of a camera path starting at `origin`; `subsurface_walks` false for the integrators
// that render subsurface scattering as its diffuse fallback (Bsdf::subsurface_as_diffuse).
inline PathState camera_path_state(const Vec3& origin, bool subsurface_walks = true) {
    PathState st;
    st.prev_p = origin;
    st.transparent_background = true;
    st.diffuse_ancestor = !subsurface_walks;
    return st;
}
// Whether the ray (found: it hit `hit`) ends the camera path as a hole in the film: it escaped to
// the World with Film Transparent, or it met a holdout object. The path's mean throughput (Cycles'
// average(throughput)) is then the sample's transparency; the caller stops a path that met a holdout.
inline bool add_transparency(const RenderSettings& settings, const PathState& st, bool found, const SurfaceHit& hit,
                             const Color& beta, LocalCounters& c) {
    if (!st.transparent_background || (found ? !hit.holdout : !settings.film_transparent)) return false;
    c.sample_transparency += average(beta);
    return found;
}
// Cycles' Holdout closure (integrate_surface_holdout): on a camera path that so far only passed
// through transparent surfaces, the holdout weight times the throughput becomes the sample's
// transparency (a hole in the film, whatever Film Transparent says); the surface's other closures
// still scatter, and a full holdout ends the path. Other paths see the closure as black.
inline bool holdout_ends_path(const PathState& st, const ShadingPoint& sp, const Color& beta, LocalCounters& c) {
    if (!st.transparent_background || !(max_component(sp.holdout) > 0.0f)) return false;
    c.sample_transparency += average(sp.holdout * beta);
    return min_component(sp.holdout) >= 1.0f;
}
// After a bounce: only a Transparent lobe keeps the background transparent (Cycles clears the flag
// on every reflection and on every transmission but LABEL_TRANSMIT_TRANSPARENT), and, with
// Transparent Glass, a refraction through glass (or a Refraction BSDF, and rough Glass's refraction
// lobe, the Principled transmission's refraction) at most that rough (Cycles' bsdf_sample: alpha^2 at
// most the threshold roughness^2).
inline void update_transparent_background(const RenderSettings& settings, PathState& st, const Bsdf& bsdf,
                                          const BsdfSample& bs) {
    if (!st.transparent_background) return;
    const Lobe* lobe = bs.lobe >= 0 ? &bsdf.lobe(bs.lobe) : nullptr;
    st.transparent_background =
        lobe && (lobe->kind == LobeKind::Transparent ||
                 (settings.film_transparent && bs.transmission &&
                  (((lobe->kind == LobeKind::Dielectric || lobe->kind == LobeKind::Refraction ||
                     lobe->kind == LobeKind::MultiGlass || lobe->kind == LobeKind::GlassMultiple ||
                     lobe->kind == LobeKind::MultiGlassWalk) &&
                    lobe->alpha <= settings.film_transparent_glass) ||
                   (lobe->kind == LobeKind::PrincipledGlass && lobe->alpha_y <= settings.film_transparent_glass))));
}
struct RayMedia;
// Transmittance along a ray's media up to t / to its end (defined with RayMedia in volume.cpp).
Color media_transmittance(const RayMedia& media, const Scene& scene, float t);
Color media_transmittance_to_end(const RayMedia& media);

// Next-event estimation at a shading point: one light chosen by power, one point on it.
struct DirectSample {
    Vec3 wi;
    Color weighted{0.0f};  // Le * w_light / pdf_light: multiply by bsdf.eval(wo, wi) for the contribution
    uint32_t light = 0;    // which light (spectral rendering looks up its spectrum)
    bool valid = false;
    // The ray types the light is hidden from (Light::visibility): the lobes of those classes take
    // no part in the sample (direct_eval), as in Cycles.
    uint32_t hidden = 0;
};
// The lobes a light hidden from the ray types `hidden` lights (Cycles: its samples leave out the
// closures of those classes): their value and their mixture density towards wi, and whether any
// non-Dirac lobe is left. Out of line: the common case (a light every ray sees) never builds them.
[[gnu::noinline]] Color hidden_light_eval(const Bsdf& bsdf, uint32_t hidden, const Vec3& wo, const Vec3& wi);
[[gnu::noinline]] float hidden_light_pdf(const Bsdf& bsdf, uint32_t hidden, const Vec3& wo, const Vec3& wi);
[[gnu::noinline]] bool hidden_light_lights_nothing(const Bsdf& bsdf, uint32_t hidden);
// The shading point with only the lobes the light sample lights (for the spectral evaluation).
[[gnu::noinline]] ShadingPoint lit_lobes(const ShadingPoint& sp, const DirectSample& ds);
// bsdf.eval towards the light sample, over the lobes it lights.
inline Color direct_eval(const ShadingPoint& sp, const DirectSample& ds) {
    return ds.hidden ? hidden_light_eval(sp.bsdf, ds.hidden, sp.wo, ds.wi) : sp.bsdf.eval(sp.wo, ds.wi);
}
// Cycles' caustics toggles at a vertex the state's ray found (lobe_is_caustic).
inline void drop_caustic_lobes(const RenderSettings& s, const PathState& st, ShadingPoint& sp) {
    if (!(st.ray_flags & kRayDiffuse) || (s.caustics_reflective && s.caustics_refractive)) return;
    const bool reflective_off = !s.caustics_reflective, refractive_off = !s.caustics_refractive;
    sp.bsdf = sp.bsdf.only([&](const Lobe& l) { return !lobe_is_caustic(l, reflective_off, refractive_off); });
    sp.bsdf.change_lobes([&](Lobe& l) { glass_half_left(l, reflective_off, refractive_off); });
}
// Cycles' Filter Glossy (surface_shader_prepare_closures, with filter_glossy = 1 / blur_glossy): at
// a vertex whose path's min_ray_pdf times 1 / blur_glossy is below 1, the microfacet lobes' alpha
// is raised to at least sqrt(1 - that) / 2 (blur_lobe). Camera rays and paths of Dirac and sharp
// bounces only (min_ray_pdf infinite or large) keep their lobes.
inline void blur_glossy_lobes(const RenderSettings& s, const PathState& st, ShadingPoint& sp) {
    if (!(s.filter_glossy > 0.0f)) return;
    const float blur_pdf = st.min_ray_pdf / s.filter_glossy;
    if (!(blur_pdf < 1.0f)) return;
    const float alpha = 0.5f * std::sqrt(1.0f - blur_pdf);
    sp.bsdf.change_lobes([alpha](Lobe& lobe) { blur_lobe(lobe, alpha); });
}
// The setting multiscatter_cycles_walk: the Glossy and Anisotropic BSDFs' Multiscatter GGX and the
// Multiscatter GGX glass as Cycles estimates them, one lobe in place of each consistent pair
// (lobes/multiscatter_walk.h, multi_glass_walk.h).
inline void cycles_multiscatter_lobes(const RenderSettings& s, ShadingPoint& sp) {
    if (!s.multiscatter_cycles_walk) return;
    Lobe* glass = nullptr;
    sp.bsdf.change_lobes([&](Lobe& l) {
        to_cycles_walk(l);
        to_cycles_glass_walk(l, &glass);
    });
    sp.bsdf = sp.bsdf.only([](const Lobe& l) { return !replaced_by_cycles_walk(l) && !replaced_by_cycles_glass_walk(l); });
}
// The setting beckmann_cycles_sampling: the Anisotropic BSDF's Beckmann sampled as Cycles 3.4 samples
// it (lobes/anisotropic.h, kCyclesSampler).
inline void cycles_beckmann_lobes(const RenderSettings& s, ShadingPoint& sp) {
    if (!s.beckmann_cycles_sampling) return;
    sp.bsdf.change_lobes([](Lobe& l) {
        if (l.kind == LobeKind::AnisoBeckmann) l.variant = AnisoBeckmannLobe::kCyclesSampler;
    });
}
// Cycles evaluates the BSDF towards the vertex's light sample (world-space wo, wi) before its shadow
// test (shade_surface.h, integrate_surface_direct_light), and its BSDF sample then draws on from where
// that eval left the LCG: the glass walk lobes' states move on by the numbers their eval takes.
inline void after_cycles_light_eval(Bsdf& bsdf, const Vec3& wo, const Vec3& wi) {
    const Vec3 o = bsdf.frame().to_local(wo), i = bsdf.frame().to_local(wi);
    bsdf.change_lobes([&](Lobe& l) {
        uint32_t state;
        if (l.kind != LobeKind::MultiGlassWalk || !cycles_lcg_of(l, &state)) return;
        CyclesLcg rand{state};
        MultiGlassWalkLobe::walk_eval_with(l, o, i, l.f0, rand);
        set_cycles_lcg(l, rand.x);
    });
}
// The Light Paths rules that change a vertex's lobes: the caustics toggles, Filter Glossy, and
// Cycles' multiscatter and anisotropic Beckmann estimators on request.
inline void light_path_lobes(const RenderSettings& s, const PathState& st, ShadingPoint& sp) {
    drop_caustic_lobes(s, st, sp);
    blur_glossy_lobes(s, st, sp);
    cycles_multiscatter_lobes(s, sp);
    cycles_beckmann_lobes(s, sp);
}
// With media (Scene::has_media()), `medium` is the medium the path arrived in and the shadow ray
// carries transmittance; without, it is ignored and the shadow ray is a plain occlusion test.
// `light_samples` and `bsdf_samples`: how many light and BSDF samples the vertex takes (Veach's
// multi-sample MIS: each density counted that many times in the weights); `weighted` is then one
// light sample's share, to be summed over the light samples. The light choice and point are u.light()
// (core/sampler.h); the Rng overload draws them from the stream.
// `glow`: the vertex continues by GlowDirections' mixture (glow_directions.h), whose density then
// stands for the BSDF's in the MIS weight.
DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                           VertexSampler u, LocalCounters& counters, int32_t medium = -1, int light_samples = 1,
                           int bsdf_samples = 1, bool glow = false);
inline DirectSample sample_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                                  LocalCounters& counters, int32_t medium = -1, int light_samples = 1,
                                  int bsdf_samples = 1) {
    return sample_direct(scene, settings, sp, VertexSampler(rng), counters, medium, light_samples, bsdf_samples);
}

// The light index for_each_emission_along passes for emission found on a strand (no light).
constexpr uint32_t kStrandLight = ~0u;
// Emission reaching the ray's origin from lights that are not geometry (area, point, spot) in front
// of the first hit, from that hit if it emits, or from lights at infinity when nothing is hit;
// MIS-weighted against next-event estimation from the previous vertex, attenuated by `media` when
// given. Calls add(light index, weighted radiance) once per light found (spectral rendering needs
// to know which light; kStrandLight for an emissive strand); an `add` that also takes a distance,
// add(light, radiance, t), is called with the radiance before the media and how far along the ray it
// was found (kInf: at the ray's end), to attenuate it per wavelength itself. `kind`: the ray's Light Path state, for a World program that reads it (a
// backplate seen by camera rays only); null: a camera ray at depth 0, an indirect ray after.
template <class Add>
void for_each_emission_along(const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                             const SurfaceHit& hit, const PathState& state, Add&& add,
                             const RayMedia* media = nullptr, const ShaderRay* kind = nullptr) {
    constexpr bool kAttenuates = std::is_invocable_v<Add&, uint32_t, const Color&, float>;
    auto weight = [&](float light_pmf, float light_pdf) {
        return state.prev_delta ? 1.0f
                                : mis_weight(settings.mis, state.prev_pdf, state.light_pdf_scale * light_pmf * light_pdf);
    };
    Ray to_hit = ray;
    to_hit.tmax = found ? hit.t : kInf;
    // Area, point and spot lights are not in the BVH (as in Cycles): test them separately.
    scene.for_each_light_hit(to_hit, [&](uint32_t i, const LightHit& h) {
        const Light& light = scene.light(i);
        if ((state.ray_flags & kRayCamera) ? !light.visible_to_camera
                                           : !light.use_mis || light_hidden_from(light.visibility, state.ray_flags))
            return;
        Color Le = h.L * weight(scene.light_pmf(i), h.pdf);
        if constexpr (kAttenuates) add(i, Le, h.t);
        else add(i, media ? Le * media_transmittance(*media, scene, h.t) : Le);
    });
    // Emission at the end of the ray is attenuated by the whole ray's media.
    auto far = [&](uint32_t i, const Color& Le) {
        if constexpr (kAttenuates) add(i, Le, kInf);
        else add(i, media ? Le * media_transmittance_to_end(*media) : Le);
    };
    if (!found) {
        LightHit h;
        ShaderRay k = kind ? *kind : ShaderRay{};
        if (!kind) k.camera = state.depth == 0;
        k.depth = state.depth;
        k.length = 0.0f;  // Cycles' background shader data
        for (uint32_t i : scene.infinite_lights())
            if (((state.ray_flags & kRayCamera) ? scene.light(i).visible_to_camera
                                                : !light_hidden_from(scene.light(i).visibility, state.ray_flags)) &&
                scene.light(i).use_mis &&
                !(settings.film_transparent && state.transparent_background && scene.light(i).is_background()) &&
                scene.light(i).intersect_as(to_hit, k, &h))
                far(i, h.L * weight(scene.light_pmf(i), h.pdf));
    } else if (hit.light >= 0 && !(hit.holdout && state.transparent_background)) {
        auto& tri = static_cast<const TriangleLight&>(scene.light(hit.light));
        far(uint32_t(hit.light), scene.emission_at(hit, -ray.d) *
                                     weight(scene.light_pmf(hit.light), tri.pdf_at(state.prev_p, hit.p, hit.time)));
    } else if (hit.light == kStrandEmission && !(hit.holdout && state.transparent_background)) {
        // An emissive strand: no light sample reaches it, so the ray's hit is its only estimator
        // (MIS weight 1, as Cycles weighs curve emission).
        far(kStrandLight, scene.emission_at(hit, -ray.d));
    }
}
inline Color emission_along(const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                            const SurfaceHit& hit, const PathState& state, const RayMedia* media = nullptr,
                            const ShaderRay* kind = nullptr) {
    Color L(0.0f);
    for_each_emission_along(
        scene, settings, ray, found, hit, state, [&](uint32_t, const Color& c) { L += c; }, media, kind);
    return L;
}

// Whether BSDF sample bs at sp picked a Subsurface lobe (the path walks inside the object next).
inline bool picks_subsurface(const ShadingPoint& sp, const BsdfSample& bs) {
    return bs.delta && bs.lobe >= 0 && sp.bsdf.lobe(bs.lobe).kind == LobeKind::Subsurface;
}
// The subsurface step for such a sample (subsurface_walk.h, subsurface_disk.h): beta takes the
// lobe's weight over its pick probability and the walk's (disk's) weight, and sp becomes the exit,
// whose own light and BSDF samples follow at the entry's depth. False: no exit, the path ends.
bool subsurface_step(const Scene& scene, ShadingPoint& sp, const BsdfSample& bs, Color& beta, Rng& rng);
// The path tracer's estimate from such a sample on, for integrators that keep it per pixel (path-space
// filtering): the step, the exit's light sample, its BSDF sample and the path tracer from there, all
// under the throughput beta at the entry; `state` is the path's at the entry.
Color trace_subsurface(const Scene& scene, const RenderSettings& settings, ShadingPoint sp, BsdfSample bs,
                       PathState state, Color beta, Rng& rng, LocalCounters& counters);

// Radiance arriving at ray.o along -ray.d: the path tracer from `state` on (NEE + BSDF sampling with
// MIS, Russian roulette, Cycles' bounce limit). `camera`: the pixel sample's Sampler when the path
// starts at the camera (rng is then its stream): the first vertex asks it for its numbers by name.
Color trace_path(const Scene& scene, const RenderSettings& settings, Ray ray, PathState state, Rng& rng,
                 LocalCounters& counters, Sampler* camera = nullptr);

// Russian roulette after a few bounces on the largest throughput component max_beta: returns the
// probability with which the path survives (divide the throughput by it), or 0 to stop the path.
// A BSDF sample at sp with the vertex's named numbers (core/sampler.h): the lobe choice first, then
// the 2D point (one order everywhere, so every vertex that draws from the stream consumes it the
// same way). The Rng overload draws them from the stream.
inline BsdfSample sample_bsdf(const ShadingPoint& sp, VertexSampler u) {
    const float u_lobe = u.lobe();
    return sp.bsdf.sample(sp.wo, u.direction(), u_lobe);
}
inline BsdfSample sample_bsdf(const ShadingPoint& sp, Rng& rng) { return sample_bsdf(sp, VertexSampler(rng)); }

float russian_roulette_survival(int depth, float max_beta, float eta_scale, Rng& rng);
// The same for an RGB throughput: returns false to stop, else rescales beta.
inline bool russian_roulette(int depth, Color& beta, float eta_scale, Rng& rng) {
    float survival = russian_roulette_survival(depth, max_component(beta), eta_scale, rng);
    if (survival == 0.0f) return false;
    beta = beta / survival;
    return true;
}

}  // namespace smis
