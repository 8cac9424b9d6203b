#include "integrators/spectral_path.h"

#include "core/pixel_sequence.h"
#include "integrators/path_tracing.h"

namespace smis {

using namespace spectral;

namespace {

// The Fresnel factor of lobe `lobe` at one wavelength (1 for lobes without one, see LobeTerms).
float spectral_fresnel(const Lobe& lobe, const SpectralLobe& s, float lambda, float cos_d) {
    if (lobe_spectral_fresnel(lobe) != SpectralFresnel::Tinted) return 1.0f;
    if (s.metal) return fresnel_conductor(cos_d, metal_ior(*s.metal, lambda));
    return lobe_spectral_colour(lobe, [&] { return s.f0(lambda); }, cos_d);
}

// The spectral data of a hit's lobe: the material's, upsampled once per render, or for a textured
// lobe (Image Texture, Object Info colour) the hit's own colour, upsampled here from the table.
const SpectralLobe& hit_lobe(const Lobe& lobe, const SpectralMaterial& sm, SpectralLobe* scratch) {
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
    Color emission(const EmitterSpectrum& e, float scale, const float* f = nullptr) const {
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
bool eval_spectral(const ShadingPoint& sp, const SpectralMaterial& sm, const SpectralPath& p, const Vec3& wi,
                   float* f) {
    LobeTerms terms[Bsdf::kMaxLobes];
    if (!sp.bsdf.eval_terms(sp.wo, wi, terms)) return false;
    for (int i = 0; i < p.n; ++i) f[i] = 0.0f;
    bool any = false;
    for (int l = 0; l < sp.bsdf.lobe_count(); ++l) {
        if (!(terms[l].geom > 0.0f)) continue;
        any = true;
        const Lobe& lobe = sp.bsdf.lobe(l);
        SpectralLobe scratch;
        const SpectralLobe& s = hit_lobe(lobe, sm, &scratch);
        for (int i = 0; i < p.n; ++i) {
            float lambda = p.ws.lambda[i];
            f[i] += s.weight(lambda) * spectral_fresnel(lobe, s, lambda, terms[l].cos_d) * terms[l].geom;
        }
    }
    return any;
}

// The hit's BSDF with the dispersive lobes' IOR at the conditioning wavelength, which drives sampling.
Bsdf dispersed_bsdf(const ShadingPoint& sp, const SpectralMaterial& sm, float lambda) {
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
bool delta_event(const ShadingPoint& sp, const SpectralMaterial& sm, const BsdfSample& bs, SpectralPath& p) {
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

}  // namespace

SpectralPathIntegrator::SpectralPathIntegrator(const Scene& scene, SpectralMode mode, int wavelengths,
                                               float fixed_wavelength)
    : spectral_(scene), sampler_(mode, wavelengths, spectral_.importance()), fixed_wavelength_(fixed_wavelength) {}

std::map<std::string, double> SpectralPathIntegrator::stats() const {
    return {{"wavelengths_per_path", double(sampler_.count())}};
}

Color SpectralPathIntegrator::Li(const Scene& scene, const RenderSettings& settings, Ray ray, Rng& rng,
                                 LocalCounters& counters) const {
    float u = rng.next_float();
    float v = rng.next_float();
    return trace(scene, settings, ray, u, v, rng, rng, counters);
}

// The offsets of sample s. u from the pixel sequence of s, so that all the wavelengths of the pixel's
// samples stratify (for SMIS the samples' lattices interleave into one of n x spp points). The
// conditioning index c_s = (s + s / n + k) mod n, k random per pixel: every run of n consecutive
// samples gets n different indices, and so do the samples s = r, r + n, r + 2n, ... whose offsets u
// lie in the same 1/n-wide slot, so the conditioning wavelengths P^-1((c_s + u_s) / n), all that
// survives a dispersive refraction, stratify too (at 4 spp already: one per quarter of the CDF).
// Each sample's c is uniform and independent of its u (k and the rotation of u are independent).
Color SpectralPathIntegrator::pixel_sample(const RenderContext& ctx, uint32_t px, uint32_t py, uint32_t s,
                                           const Ray& ray, Rng& rng, LocalCounters& counters) const {
    // The wavelengths draw from a stream of their own, so that in every mode the path is driven by
    // the pixel sample's stream and its stratified prefix (core/stratified.h) alike: modes differ
    // only in how they choose wavelengths.
    Rng wavelength_rng = pixel_sample_rng(px, py, s, ctx.settings.seed ^ 0x3a7e1c55u);
    if (!ctx.settings.spectral_pixel_sequence || !sampler_.follows_offsets()) {
        float u = wavelength_rng.next_float();
        float v = wavelength_rng.next_float();
        return trace(ctx.scene, ctx.settings, ray, u, v, wavelength_rng, rng, counters);
    }
    constexpr uint64_t kOffsetDimension = 0x5be7a1, kConditioningDimension = 0xc0d1;
    uint32_t seed = ctx.settings.seed, n = uint32_t(sampler_.count());
    float u = pixel_sequence(px, py, s, seed, kOffsetDimension);
    uint32_t k = std::min(uint32_t(pixel_sequence(px, py, 0, seed, kConditioningDimension) * float(n)), n - 1);
    float v = (float((s + s / n + k) % n) + 0.5f) / float(n);
    return trace(ctx.scene, ctx.settings, ray, u, v, wavelength_rng, rng, counters);
}

Color SpectralPathIntegrator::trace(const Scene& scene, const RenderSettings& settings, Ray ray, float u, float v,
                                    Rng& wavelength_rng, Rng& rng, LocalCounters& counters) const {
    SpectralPath p;
    if (fixed_wavelength_ > 0.0f) p.start_at(fixed_wavelength_);
    else p.start(sampler_, u, v, wavelength_rng);
    float f[kMaxWavelengths];
    Color L(0.0f);
    PathState state = camera_path_state(ray.o);
    float eta_scale = 1.0f;
    // Film Transparent: the RGB throughput of the camera path while it passes through transparent
    // surfaces only (their colour is RGB), for the transparency it adds where it reaches the World.
    Color transparent_beta(1.0f);
    auto add_emission = [&](uint32_t light, const Color& weighted) {
        float lum = luminance(weighted);
        if (lum > 0.0f) L += clamp_contribution(settings, p.emission(spectral_.emitter(light), lum), state.depth <= 1);
    };
    ShaderRay sray;  // what the Light Path node reports for the next hit (scenes with programs)
    sray.camera = state.depth == 0;
    const bool programs = scene.has_programs();
    for (;; ++state.depth) {
        SurfaceHit hit;
        bool found = scene.intersect(ray, &hit);
        for_each_emission_along(scene, settings, ray, found, hit, state, add_emission);
        if (add_transparency(settings, state, found, hit, transparent_beta, counters)) break;
        if (!found || beyond_bounce_limits(settings, state)) break;
        if (programs) {
            sray.depth = state.depth;
            sray.length = hit.t;
        }
        ShadingPoint sp = make_shading_point(scene, hit, ray.d, &sray);
        subsurface_fallback(scene, sp);
        if (holdout_ends_path(state, sp, transparent_beta, counters)) break;
        light_path_lobes(settings, state, sp);
        if (sp.bsdf.empty()) break;
        const SpectralMaterial& sm = spectral_.material(hit.material);
        if (sm.dispersive) sp.bsdf = dispersed_bsdf(sp, sm, p.lambda_c());

        DirectSample ds = sample_direct(scene, settings, sp, rng, counters);
        if (ds.valid && (ds.hidden ? eval_spectral(lit_lobes(sp, ds), sm, p, ds.wi, f)
                                   : eval_spectral(sp, sm, p, ds.wi, f))) {
            float lum = luminance(ds.weighted);
            if (lum > 0.0f) L += clamp_contribution(settings, p.emission(spectral_.emitter(ds.light), lum, f), state.depth == 0);
        }

        BsdfSample bs = sample_bsdf(sp, rng);
        if (!bs.valid()) {
            ++counters.samples_rejected;
            break;
        }
        if (bs.delta) {
            if (!delta_event(sp, sm, bs, p)) break;
        } else {
            if (!eval_spectral(sp, sm, p, bs.wi, f)) break;
            float inv_pdf = 1.0f / bs.pdf;
            for (int i = 0; i < p.n; ++i) p.beta[i] *= f[i] * inv_pdf;
        }
        if (bs.transmission) eta_scale *= sqr(bs.eta);
        if (programs) next_shader_ray(sp.bsdf, bs, &sray);
        update_transparent_background(settings, state, sp.bsdf, bs);
        if (state.transparent_background) transparent_beta *= bs.value / bs.pdf;
        advance_ray_type(state, sp.bsdf, bs);
        state.prev_delta = bs.delta;
        state.prev_pdf = bs.pdf;
        state.prev_p = hit.p;
        ray = bounce_ray(sp, bs, state);
        float survival = russian_roulette_survival(state.depth, p.max_beta(), eta_scale, rng);
        if (survival == 0.0f) break;
        transparent_beta = transparent_beta / survival;
        bool alive = false;
        for (int i = 0; i < p.n; ++i) alive |= (p.beta[i] /= survival) > 0.0f;
        if (!alive) break;
    }
    // Diagnostic pass: the wavelengths this path still carried at its end (n, or 1 after a
    // dispersive refraction kept only the conditioning wavelength).
    int alive = 0;
    for (int i = 0; i < p.n; ++i) alive += p.r[i] > 0.0f;
    counters.sample_diagnostic = float(alive);
    return L;
}

}  // namespace smis
