// The spectral path's state and its spectrum policy for the path loop (path_loop.h), shared by the
// spectral path tracer (spectral_path.cpp) and spectral path-space filtering (psf_spectral.cpp).
// Internal to those two files.
#pragma once
#include "core/pixel_sequence.h"
#include "integrators/path_loop.h"
#include "integrators/restir.h"
#include "integrators/subsurface_disk.h"
#include "spectral/spectral_scene.h"
#include "spectral/wavelength_sampling.h"

namespace smis {
namespace spectral_paths {

using namespace spectral;


// The Fresnel factor of lobe `lobe` at one wavelength (1 for lobes without one, see LobeTerms).
inline float spectral_fresnel(const Lobe& lobe, const SpectralLobe& s, float lambda, float cos_d) {
    if (lobe_spectral_fresnel(lobe) != SpectralFresnel::Tinted) return 1.0f;
    if (s.metal) return fresnel_conductor(cos_d, metal_ior(*s.metal, lambda));
    return lobe_spectral_colour(lobe, [&] { return s.f0(lambda); }, cos_d);
}

// The spectral data of a hit's lobe: the material's, upsampled once per render, or for a textured
// lobe (Image Texture, Object Info colour) the hit's own colour, upsampled here from the table.
inline const SpectralLobe& hit_lobe(const Lobe& lobe, const SpectralMaterial& sm, SpectralLobe* scratch) {
    const SpectralLobe& s = sm.lobes[lobe.index];
    if (!s.varies) return s;
    *scratch = s;
    scratch->weight = rgb_spectrum_table(lobe.weight);
    if (lobe_colour_f0(lobe)) scratch->f0 = rgb_spectrum_table(lobe.f0);
    return *scratch;
}

// The state of one path across its n wavelengths.
struct SpectralPath {
    WavelengthSet ws;
    float beta[kMaxWavelengths];     // f(x, l_i) / p(x | l_c)
    float r[kMaxWavelengths];        // p(x | l_i) / p(x | l_c)
    Color response[kMaxWavelengths];  // rgb_response(l_i) / q_i
    float inv_mix = 1.0f;            // 1 / sum_j a_j r_j
    int n = 0, c = 0;
    float* out = nullptr;  // see emission()

    void start(const WavelengthSampler& sampler, float u, float v, Rng& rng) {
        sampler.sample(u, v, rng, &ws);
        n = ws.n;
        c = ws.conditioning;
        for (int i = 0; i < n; ++i) {
            beta[i] = 1.0f;
            r[i] = 1.0f;
            response[i] = rgb_response(ws.lambda[i]) / ws.q[i];
        }
        update_mix();
    }
    // One wavelength, neither sampled nor weighted by a response: the radiance itself, in every channel.
    void start_at(float lambda) {
        n = 1;
        c = 0;
        ws.n = 1;
        ws.conditioning = 0;
        ws.lambda[0] = lambda;
        ws.q[0] = 1.0f;
        ws.a[0] = 1.0f;
        beta[0] = 1.0f;
        r[0] = 1.0f;
        response[0] = Color(1.0f);
        update_mix();
    }
    void update_mix() {
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += double(ws.a[i]) * r[i];
        inv_mix = sum > 0.0 ? float(1.0 / sum) : 0.0f;
    }
    float lambda_c() const { return ws.lambda[c]; }
    float max_beta() const {
        float m = 0.0f;
        for (int i = 0; i < n; ++i) m = std::max(m, beta[i]);
        return m;
    }
    // RGB of the emission `scale` * e(l_i) (times f_i when given) arriving along the path.
    // With `out` set (spectral path-space filtering's suffixes, psf_spectral.cpp) each wavelength's
    // weighted radiance is added to out[i] instead, and the RGB returned is 0.
    Color emission(const EmitterSpectrum& e, float scale, const float* f = nullptr) const {
        if (out) {
            for (int i = 0; i < n; ++i)
                if (beta[i] != 0.0f) out[i] += beta[i] * e(ws.lambda[i]) * (f ? f[i] : 1.0f) * (scale * inv_mix);
            return Color(0.0f);
        }
        Color sum(0.0f);
        for (int i = 0; i < n; ++i) {
            if (beta[i] == 0.0f) continue;
            float v = beta[i] * e(ws.lambda[i]);
            if (f) v *= f[i];
            sum += response[i] * v;
        }
        return sum * (scale * inv_mix);
    }
};

// f(wo, wi) |cos| at every wavelength of the path; false when the BSDF is zero for wi.
// The same for a BSDF seen from wo at the n wavelengths `lambda`.
inline bool eval_spectral(const Bsdf& bsdf, const Vec3& wo, const SpectralMaterial& sm, int n, const float* lambda,
                          const Vec3& wi, float* f) {
    LobeTerms terms[Bsdf::kMaxLobes];
    if (!bsdf.eval_terms(wo, wi, terms)) return false;
    for (int i = 0; i < n; ++i) f[i] = 0.0f;
    bool any = false;
    for (int l = 0; l < bsdf.lobe_count(); ++l) {
        if (!(terms[l].geom > 0.0f)) continue;
        any = true;
        const Lobe& lobe = bsdf.lobe(l);
        SpectralLobe scratch;
        const SpectralLobe& s = hit_lobe(lobe, sm, &scratch);
        for (int i = 0; i < n; ++i) {
            float lambda_i = lambda[i];
            f[i] += s.weight(lambda_i) * spectral_fresnel(lobe, s, lambda_i, terms[l].cos_d) * terms[l].geom;
        }
    }
    return any;
}
inline bool eval_spectral(const ShadingPoint& sp, const SpectralMaterial& sm, const SpectralPath& p, const Vec3& wi,
                          float* f) {
    return eval_spectral(sp.bsdf, sp.wo, sm, p.n, p.ws.lambda, wi, f);
}

// The hit's BSDF with the dispersive lobes' IOR at the conditioning wavelength, which drives sampling.
inline Bsdf dispersed_bsdf(const ShadingPoint& sp, const SpectralMaterial& sm, float lambda) {
    Bsdf b(sp.bsdf.frame(), sp.bsdf.ng());
    for (int l = 0; l < sp.bsdf.lobe_count(); ++l) {
        Lobe lobe = sp.bsdf.lobe(l);
        const Dispersion& d = sm.lobes[lobe.index].dispersion;
        if (d.active()) lobe.eta = sp.backfacing ? 1.0f / d.eta(lambda) : d.eta(lambda);
        b.add(lobe);
    }
    return b;
}

// Throughput update for a Dirac event (mirror, smooth glass). Non-dispersive events scale every
// wavelength by its own weight and Fresnel over the wavelength-independent selection probability.
// A dispersive refraction exists for l_c only: the other wavelengths get zero contribution and zero
// density (r_j = 0). A dispersive reflection is valid for all, but its probability F(l) depends on
// the wavelength, so r_j picks up F_j / F_c. Returns false when no wavelength survives.
inline bool delta_event(const ShadingPoint& sp, const SpectralMaterial& sm, const BsdfSample& bs, SpectralPath& p) {
    const Lobe& lobe = sp.bsdf.lobe(bs.lobe);
    SpectralLobe scratch;
    const SpectralLobe& s = hit_lobe(lobe, sm, &scratch);
    float prob = sp.bsdf.fix_wo(sp.wo).probs[bs.lobe];
    if (!(prob > 0.0f)) return false;
    float cos_o = sp.bsdf.frame().to_local(sp.wo).z;
    SpectralFresnel fresnel_kind = lobe_spectral_fresnel(lobe);
    // Glass left with one event by a caustics toggle: its Fresnel factor no longer cancels with the
    // event's probability (1), so the throughput keeps it (the sampled IOR's for a refraction, each
    // wavelength's own for a dispersive reflection).
    const bool one_event = (lobe.kind == LobeKind::Dielectric || lobe.kind == LobeKind::PrincipledGlass) &&
                           lobe.glass_events != kGlassBoth;
    auto event_fresnel = [&](float F) { return one_event ? (bs.transmission ? 1.0f - F : F) : 1.0f; };
    if (fresnel_kind == SpectralFresnel::Tinted) {
        // A refraction's colour is at cos_d < 0 (principled_glass.h), with the radiance scaling.
        float cos_d = bs.transmission ? -1.0f : cos_o;
        float scale = bs.transmission ? 1.0f / (bs.eta * bs.eta) : 1.0f;
        if (one_event) scale *= event_fresnel(fresnel_dielectric(std::fabs(cos_o), cos_o > 0.0f ? lobe.eta : 1.0f / lobe.eta));
        for (int i = 0; i < p.n; ++i) {
            float lambda = p.ws.lambda[i];
            p.beta[i] *= s.weight(lambda) * spectral_fresnel(lobe, s, lambda, cos_d) * scale / prob;
        }
        return true;
    }
    if (fresnel_kind == SpectralFresnel::Fixed) {  // e.g. a smooth coat: its Fresnel (fixed IOR) is not spectral
        float f = fresnel_dielectric(cos_o, lobe.eta);
        for (int i = 0; i < p.n; ++i) p.beta[i] *= s.weight(p.ws.lambda[i]) * f / prob;
        return true;
    }
    float radiance_scale = bs.transmission ? 1.0f / (bs.eta * bs.eta) : 1.0f;
    if (!s.dispersion.active()) {
        if (one_event)
            radiance_scale *= event_fresnel(fresnel_dielectric(std::fabs(cos_o), cos_o > 0.0f ? lobe.eta : 1.0f / lobe.eta));
        for (int i = 0; i < p.n; ++i) p.beta[i] *= s.weight(p.ws.lambda[i]) * (radiance_scale / prob);
        return true;
    }
    auto fresnel = [&](float lambda) {
        float e = sp.backfacing ? 1.0f / s.dispersion.eta(lambda) : s.dispersion.eta(lambda);
        return fresnel_dielectric(std::fabs(cos_o), cos_o > 0.0f ? e : 1.0f / e);
    };
    if (bs.transmission) {
        for (int i = 0; i < p.n; ++i)
            if (i != p.c) p.beta[i] = p.r[i] = 0.0f;
        p.beta[p.c] *= s.weight(p.lambda_c()) * (radiance_scale * event_fresnel(fresnel(p.lambda_c())) / prob);
    } else if (one_event) {  // reflection alone: chosen with probability 1 at every wavelength
        for (int i = 0; i < p.n; ++i) p.beta[i] *= s.weight(p.ws.lambda[i]) * fresnel(p.ws.lambda[i]) / prob;
    } else {
        float fc = fresnel(p.lambda_c());
        if (!(fc > 0.0f)) return false;
        for (int i = 0; i < p.n; ++i) {
            float fi = i == p.c ? fc : fresnel(p.ws.lambda[i]);
            p.beta[i] *= s.weight(p.ws.lambda[i]) * fi / (prob * fc);
            p.r[i] *= fi / fc;
        }
    }
    p.update_mix();
    return p.inv_mix > 0.0f;
}

static_assert(SpectralSubsurface::kCapacity >= kMaxWavelengths, "a subsurface step carries every wavelength");

// The exit lobe of a subsurface step (subsurface_exit: weight 1, its index 0) as the spectral
// material every exit vertex is evaluated with.
inline const SpectralMaterial& subsurface_exit_material() {
    static const SpectralMaterial exit = [] {
        SpectralMaterial m;
        m.lobes.emplace_back();
        m.lobes[0].weight = rgb_spectrum(Color(1.0f));
        return m;
    }();
    return exit;
}

// Optical depth of `media` over [0, t) at wavelength lambda (t = kInf: the whole ray), from its
// stored segments (RayMedia keeps the first kMaxSegments; RGB's tau_end counts the rest too).
inline float spectral_optical_depth(const SpectralScene& spectral, const RayMedia& media, float t, float lambda) {
    float tau = 0.0f;
    for (int i = 0; i < media.count && media.seg[i].t0 < t; ++i) {
        const float sigma = spectral.medium(media.seg[i].medium).sigma_t(lambda);
        if (sigma > 0.0f) tau += sigma * (std::min(t, media.seg[i].t1) - media.seg[i].t0);  // 0 * inf = 0
    }
    return tau;
}

}  // namespace spectral_paths

// ReSTIR's stage 1 on a spectral path (SpectralPathIntegrator::trace_restir_pixel): where the first
// vertex goes, and the camera distance summed on the way.
struct SpectralRestirRecord {
    RestirPixel& vertex;
    float* lambda;
    Color* weight;
};

namespace spectral_paths {

// The spectral path tracer's spectrum (path_loop.h describes the policy): the n wavelengths of a
// SpectralPath. Directions are sampled as in RGB rendering; every BSDF, light and emission is
// evaluated at all n wavelengths. With RIS (settings.direct_light) the first vertex resamples its
// light sample with the RGB target and evaluates the chosen one at every wavelength
// (direct_lighting.h, resampled_weight); for ReSTIR (a SpectralRestirRecord) it records that vertex
// and its initial reservoir instead, and the reuse shades it later (restir.cpp). Subsurface
// scattering walks (or samples Christensen-Burley's disk) with the path's wavelengths as its
// channels: each flight (or radius) is drawn from one wavelength and weighed by the mixture density
// over all of them, a density that depends on the wavelength set only, so the relative densities r_j
// stay as they are.
// Media (spectral/spectral_scene.h, SpectralMedium): each wavelength has its own transmittance along
// rays and shadow rays. No direction of the path depends on a medium (volume bounces = 0: a path
// never continues from a scattering vertex), so media leave the relative densities r_j as they are;
// the distance of a single-scattering sample is drawn from the one-sample mixture over the path's
// wavelengths of their truncated exponentials (as RGB mixes its three channels), a density that is
// positive wherever any wavelength's integrand is, so the estimate is unbiased at every wavelength.
class SpectralThroughput {
public:
    static constexpr bool kResampledLights = true;
    static constexpr bool kSubsurfaceWalks = true;
    static constexpr bool kGlowDirections = true;
    static constexpr bool kEndsAtFirstVertex = false;
    SpectralThroughput(const SpectralScene& spectral, SpectralPath& p, SpectralRestirRecord* restir = nullptr)
        : spectral_(spectral), p_(p), restir_(restir) {}

    template <class Clamp>
    void emission(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, const Ray& ray,
                  bool found, const SurfaceHit& hit, const PathState& state, const RayMedia* media,
                  const ShaderRay* sray) {
        for_each_emission_along(
            scene, settings, ray, found, hit, state,
            [&](uint32_t light, const Color& weighted, float t) {
                float lum = luminance(weighted);
                if (!(lum > 0.0f)) return;
                if (media) transmittances(*media, t, f_);
                const float* f = media ? f_ : nullptr;
                if (light == kStrandLight)
                    L += clamped(p_.emission(spectral_.strand_emitter(hit.material, weighted), lum, f), state.depth <= 1);
                else
                    L += clamped(p_.emission(spectral_.emitter(light), lum, f), state.depth <= 1);
            },
            media, sray);
    }
    // The ray's single scattering, every wavelength with its own coefficients (see above).
    void scattering(Color& L, const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                    LocalCounters& counters, bool skip_plane_lights) {
        Scattering channels{*this, scene, media, L};
        scattering_samples(scene, ray, media, rng, counters, skip_plane_lights, RectangleSampling::kSolidAngle,
                           channels);
    }
    void attenuate(const RayMedia& media) {
        for (int i = 0; i < p_.n; ++i)
            if (p_.beta[i] != 0.0f) p_.beta[i] *= std::exp(-spectral_optical_depth(spectral_, media, kInf, p_.ws.lambda[i]));
        transparent_beta_ *= media.transmittance_to_end();
    }
    // Film Transparent: the RGB throughput of the camera path while it passes through transparent
    // surfaces only (their colour is RGB), for the transparency it adds where it reaches the World.
    const Color& transparency_beta() const { return transparent_beta_; }
    bool is_black() const {
        for (int i = 0; i < p_.n; ++i)
            if (p_.beta[i] != 0.0f) return false;
        return true;
    }
    void prepare(ShadingPoint& sp) {
        at_material(sp);
        if (restir_ && !restir_->vertex.has_vertex) restir_->vertex.distance += sp.hit.t;
        if (sm_->dispersive) sp.bsdf = dispersed_bsdf(sp, *sm_, p_.lambda_c());
    }
    // In media the shadow ray's RGB transmittance is left out of ds.weighted (a stand-in 1 or 0)
    // and each wavelength's own multiplies f.
    template <class Clamp>
    void direct(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                VertexSampler u, LocalCounters& counters, const PathState& state, int light_samples = 1,
                int bsdf_samples = 1) {
        bool shadowed = false;
        auto transmittance = [&](const ShadowRay& shadow, int32_t medium) {
            shadowed = true;
            return shadow_transmittances(scene, shadow.o, shadow.d, shadow.tmax, medium) ? Color(1.0f) : Color(0.0f);
        };
        const DirectSample ds =
            state.glow_vertex ? sample_direct_through<true>(scene, settings, sp, u, counters, state.medium, light_samples,
                                                            bsdf_samples, transmittance)
                              : sample_direct_through(scene, settings, sp, u, counters, state.medium, light_samples,
                                                      bsdf_samples, transmittance);
        if (ds.valid && (ds.hidden ? eval_spectral(lit_lobes(sp, ds), *sm_, p_, ds.wi, f_)
                                   : eval_spectral(sp, *sm_, p_, ds.wi, f_))) {
            float lum = luminance(ds.weighted);
            if (shadowed)
                for (int i = 0; i < p_.n; ++i) f_[i] *= tr_[i];
            if (lum > 0.0f) L += clamped(p_.emission(spectral_.emitter(ds.light), lum, f_), state.depth == 0);
        }
    }
    template <class Clamp>
    void resampled_direct(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings,
                          const ShadingPoint& sp, Rng& rng, const PathState& state) {
        if (restir_) return record_restir_vertex(scene, settings, sp, rng, state);
        const ResampledLight s = ris_light(scene, settings, sp, rng);
        if (s.weight > 0.0f)
            L += clamped(light_sample(scene, sp, s.e, s.weight, state.medium), state.depth == 0);
    }
    // The light sample e (evaluated at sp) at the path's wavelengths: f(l) Le(l) T(l) / pdf times
    // `weight`, through its shadow ray from `medium`, as RGB. `visible`: known to be visible from sp
    // (ReSTIR's MIS traced it), so a scene without media needs no shadow ray.
    Color light_sample(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e, float weight,
                       int32_t medium, bool visible = false) {
        const Light& light = scene.light(e.light);
        DirectSample lit;
        lit.hidden = ~light.visibility & kRayBounceTypes;
        if (!(lit.hidden ? eval_spectral(lit_lobes(sp, lit), *sm_, p_, e.ls.wi, f_) : eval_spectral(sp, *sm_, p_, e.ls.wi, f_)))
            return Color(0.0f);
        // Cycles' Cast Shadow off: no shadow ray, nor the media on the way.
        if (light.cast_shadow && !(visible && !scene.has_media())) {
            const ShadowRay shadow = shadow_ray(sp, e.ls.wi, e.ls.dist);
            if (!scene.has_media()) {
                if (scene.occluded(shadow.o, shadow.d, shadow.tmax, shadow.time)) return Color(0.0f);
            } else {
                if (!shadow_transmittances(scene, shadow.o, shadow.d, shadow.tmax,
                                           medium_towards(scene, sp, e.ls.wi, medium)))
                    return Color(0.0f);
                for (int i = 0; i < p_.n; ++i) f_[i] *= tr_[i];
            }
            if (!reaches_mesh_light(scene, shadow, e.ls)) return Color(0.0f);
        }
        const float scale = luminance(e.ls.L) * weight / e.ls.pdf;
        return scale > 0.0f ? p_.emission(spectral_.emitter(e.light), scale, f_) : Color(0.0f);
    }
    // The spectral material of the shading point (which prepare() made the BSDF of).
    void at_material(const ShadingPoint& sp) { sm_ = &spectral_.material(sp.hit.material); }
    // The subsurface bounce at sp, whose sample bs picked a Subsurface lobe (path_tracing.cpp's
    // subsurface_bounce, per wavelength): the lobe's weight over its pick probability, the walk or
    // disk step to the exit, which becomes sp with the exit material, the exit's light sample and
    // its BSDF sample (bs), at the entry's depth. False: the path ends.
    template <class Clamp>
    bool subsurface(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, ShadingPoint& sp,
                    BsdfSample& bs, Rng& rng, LocalCounters& counters, const PathState& state) {
        const Lobe entry = sp.bsdf.lobe(bs.lobe);
        SpectralLobe scratch;
        const SpectralLobe& s = hit_lobe(entry, *sm_, &scratch);
        // A textured albedo or radius is upsampled per hit from the table, as hit_lobe's weight.
        const RgbSpectrum albedo = s.varies ? rgb_spectrum_table(entry.f0) : s.albedo;
        const RgbSpectrum radius = s.varies ? rgb_spectrum_table(entry.kind_colour) : s.radius;
        SpectralSubsurface ch;
        ch.n = p_.n;
        const float inv_pdf = 1.0f / bs.pdf;
        for (int i = 0; i < p_.n; ++i) {
            const float lambda = p_.ws.lambda[i];
            ch.beta[i] = p_.beta[i] * s.weight(lambda) * inv_pdf;
            ch.albedo[i] = albedo(lambda);
            ch.radius[i] = radius(lambda);
        }
        const bool exited = (entry.variant & SubsurfaceLobe::kDisk) ? subsurface_disk(scene, sp, entry, rng, ch, &sp)
                                                                    : subsurface_walk(scene, sp, entry, rng, ch, &sp);
        if (!exited) return false;
        std::copy(ch.beta, ch.beta + p_.n, p_.beta);
        sm_ = &subsurface_exit_material();
        direct(L, clamped, scene, settings, sp, VertexSampler(rng), counters, state);
        bs = sample_bsdf(sp, rng);
        return true;
    }
    bool scatter(const ShadingPoint& sp, const BsdfSample& bs) {
        if (bs.delta) return delta_event(sp, *sm_, bs, p_);
        if (!eval_spectral(sp, *sm_, p_, bs.wi, f_)) return false;
        float inv_pdf = 1.0f / bs.pdf;
        for (int i = 0; i < p_.n; ++i) p_.beta[i] *= f_[i] * inv_pdf;
        return true;
    }
    void after_scatter(const PathState& state, const BsdfSample& bs) {
        if (state.transparent_background) transparent_beta_ *= bs.value / bs.pdf;
    }
    bool roulette(int depth, float eta_scale, Rng& rng) {
        float survival = russian_roulette_survival(depth, p_.max_beta(), eta_scale, rng);
        if (survival == 0.0f) return false;
        transparent_beta_ = transparent_beta_ / survival;
        bool alive = false;
        for (int i = 0; i < p_.n; ++i) alive |= (p_.beta[i] /= survival) > 0.0f;
        return alive;
    }
    // Diagnostic pass: the wavelengths this path still carried at its end (n, or 1 after a
    // dispersive refraction kept only the conditioning wavelength).
    void finish(LocalCounters& counters) const {
        int alive = 0;
        for (int i = 0; i < p_.n; ++i) alive += p_.r[i] > 0.0f;
        counters.sample_diagnostic = float(alive);
    }

    // Transmittance of `media` over [0, t) at each wavelength of the path, into out.
    void transmittances(const RayMedia& media, float t, float* out) const {
        for (int i = 0; i < p_.n; ++i) out[i] = std::exp(-spectral_optical_depth(spectral_, media, t, p_.ws.lambda[i]));
    }
    // The shadow ray's transmittance at each wavelength into tr_; false when it is zero at all.
    bool shadow_transmittances(const Scene& scene, const Vec3& o, const Vec3& d, float tmax, int32_t medium) {
        RayMedia media;
        if (!shadow_media(scene, o, d, tmax, medium, &media)) return false;
        transmittances(media, kInf, tr_);
        bool any = false;
        for (int i = 0; i < p_.n; ++i) any |= tr_[i] > 0.0f;
        return any;
    }

    // Wavelength i's transmittance along the last shadow ray (shadow_transmittances).
    float transmittance(int i) const { return tr_[i]; }
private:
    // single_scattering's channels (volume.h, scattering_samples): the path's wavelengths.
    struct Scattering {
        SpectralThroughput& path;
        const Scene& scene;
        const RayMedia& media;
        Color& L;

        float sigma_t(int32_t medium, int i) const {
            return path.spectral_.medium(medium).sigma_t(path.p_.ws.lambda[i]);
        }
        DistanceSample sample_distance(int32_t medium, float len, float u_channel, float u) const {
            DistanceSample ds;
            if (!(len > 0.0f)) return ds;
            const float sigma = sigma_t(medium, std::min(path.p_.n - 1, int(u_channel * float(path.p_.n))));
            if (sample_truncated_exponential(sigma, len, u, &ds.t)) ds.pdf = truncated_exponential_pdf(sigma, len, ds.t);
            return ds;
        }
        float distance_pdf(int32_t medium, float len, float t) const {
            float sum = 0.0f;
            for (int i = 0; i < path.p_.n; ++i) sum += truncated_exponential_pdf(sigma_t(medium, i), len, t);
            return sum / float(path.p_.n);
        }
        bool transmit(const Vec3& x, const Vec3& wi, float tmax, int32_t medium, bool cast_shadow) {
            if (cast_shadow) return path.shadow_transmittances(scene, x, wi, tmax, medium);
            std::fill(path.tr_, path.tr_ + path.p_.n, 1.0f);
            return true;
        }
        void add(const RayMedia::Segment& s, float t, uint32_t light, const LightSample& ls, float weight) {
            const float lum = luminance(ls.L);
            if (!(lum > 0.0f)) return;
            const SpectralMedium& med = path.spectral_.medium(s.medium);
            const SpectralPath& p = path.p_;
            for (int i = 0; i < p.n; ++i) {
                const float lambda = p.ws.lambda[i];
                const float tau = spectral_optical_depth(path.spectral_, media, s.t0, lambda) + med.sigma_t(lambda) * t;
                path.f_[i] = std::exp(-tau) * med.sigma_s(lambda) * path.tr_[i];
            }
            L += p.emission(path.spectral_.emitter(light), lum * weight, path.f_);
        }
    };

    // ReSTIR's first vertex (restir.cpp, trace_pixel for RGB): the shading point, its initial RIS
    // reservoir (visibility reuse as settings say) and the path's RGB weight of each wavelength.
    void record_restir_vertex(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                              const PathState& state) {
        RestirPixel& px = restir_->vertex;
        px.has_vertex = true;
        px.camera_hit = state.depth == 0;
        px.sp = sp;
        px.medium = state.medium;
        px.r = ris_reservoir(scene, sp, settings.ris_candidates, settings.restir_visibility_reuse, rng, &px.eval,
                             state.medium);
        for (int i = 0; i < p_.n; ++i) {
            restir_->lambda[i] = p_.ws.lambda[i];
            restir_->weight[i] = p_.beta[i] == 0.0f ? Color(0.0f) : p_.response[i] * (p_.beta[i] * p_.inv_mix);
        }
    }
    const SpectralScene& spectral_;
    SpectralPath& p_;
    Color transparent_beta_{1.0f};
    SpectralRestirRecord* restir_;
    const SpectralMaterial* sm_ = nullptr;  // the current vertex's spectral material (prepare)
    float f_[kMaxWavelengths];              // scratch: f(wo, wi) |cos| (or transmittance) per wavelength
    float tr_[kMaxWavelengths];             // the last shadow ray's transmittance per wavelength
};

// The offset u and the conditioning number v of pixel (px, py)'s sample s (WavelengthSampler::sample):
// from wavelength_rng, or stratified over the samples of the pixel (settings.spectral_pixel_sequence).
// u from the pixel sequence of s, so that all the wavelengths of the pixel's samples stratify (for
// SMIS the samples' lattices interleave into one of n x spp points). The conditioning index
// c_s = (s + s / n + k) mod n, k random per pixel: every run of n consecutive samples gets n different
// indices, and so do the samples s = r, r + n, r + 2n, ... whose offsets u lie in the same 1/n-wide
// slot, so the conditioning wavelengths P^-1((c_s + u_s) / n), all that survives a dispersive
// refraction, stratify too (at 4 spp already: one per quarter of the CDF). Each sample's c is uniform
// and independent of its u (k and the rotation of u are independent).
constexpr uint32_t kWavelengthStream = 0x3a7e1c55u;  // the seed's salt for wavelength_rng
inline void wavelength_offsets(const WavelengthSampler& sampler, const RenderSettings& settings, uint32_t px,
                               uint32_t py, uint32_t s, Rng& wavelength_rng, float* u, float* v) {
    if (!settings.spectral_pixel_sequence || !sampler.follows_offsets()) {
        *u = wavelength_rng.next_float();
        *v = wavelength_rng.next_float();
        return;
    }
    constexpr uint64_t kOffsetDimension = 0x5be7a1, kConditioningDimension = 0xc0d1;
    const uint32_t seed = settings.seed, n = uint32_t(sampler.count());
    *u = pixel_sequence(px, py, s, seed, kOffsetDimension);
    const uint32_t k = std::min(uint32_t(pixel_sequence(px, py, 0, seed, kConditioningDimension) * float(n)), n - 1);
    *v = (float((s + s / n + k) % n) + 0.5f) / float(n);
}

}  // namespace spectral_paths
}  // namespace smis
