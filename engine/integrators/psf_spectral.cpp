#include "integrators/psf_spectral.h"

#include <algorithm>
#include <stdexcept>

#include "integrators/tiles.h"
#include "integrators/spectral_throughput.h"

namespace smis {

using namespace psf_detail;
using namespace spectral;
using namespace spectral_paths;

namespace {

// The spectral path tracer's policy, ending the path at its first non-specular vertex (x1): the loop
// (path_loop.h) traces the prefix with every feature of the spectral path tracer (media, dispersion,
// holdouts, Film Transparent) and collects its emission; x1 is recorded for stage 1.
class PrefixThroughput : public CameraPrefix<SpectralThroughput> {
public:
    PrefixThroughput(const SpectralScene& spectral, SpectralPath& p, X1PrefixEnd* end)
        : CameraPrefix(end, spectral, p), end_(end) {}
    void first_vertex(const ShadingPoint& sp, const PathState& state, const VertexSampler& numbers) {
        CameraPrefix::first_vertex(sp, state, numbers);
        end_->sp = sp;
    }

private:
    X1PrefixEnd* end_;
};

// Which prefixes may share suffixes (their stored L_out carries the wavelength MIS weight of the
// whole path, which depends on r_j(prefix)): r = 1 at every wavelength (no dispersive event), r = 1
// at the conditioning wavelength alone (a dispersive refraction kept it only), or anything else
// (a dispersive reflection: r_j = F_j / F_c), which no other prefix has: its pixel keeps its suffixes.
uint8_t spectral_class(const SpectralPath& p) {
    bool ones = true, conditioning_only = true;
    for (int i = 0; i < p.n; ++i) {
        ones &= p.r[i] == 1.0f;
        conditioning_only &= p.r[i] == (i == p.c ? 1.0f : 0.0f);
    }
    return ones ? kSharedClass : conditioning_only ? kSharedClass + 1 : kPrivateClass;
}

// The factor clamping scales a contribution by (path_tracing.h, clamp_contribution), given its RGB.
float clamp_scale(const RenderSettings& settings, const Color& c, bool direct) {
    const float limit = direct ? settings.clamp_direct : settings.clamp_indirect;
    if (!(limit > 0.0f)) return 1.0f;
    const float sum = std::fabs(c.x) + std::fabs(c.y) + std::fabs(c.z);
    return sum > 3.0f * limit ? 3.0f * limit / sum : 1.0f;
}

}  // namespace

struct PsfSpectrum::Impl {
    SpectralScene spectral;
    WavelengthSampler sampler;
    WavelengthSet set;
    Color response[kMaxWavelengths];
    int n = 0;
    bool exact = false, media = false;
    // Per record, n floats each: the prefix throughput, the suffix radiance, and for the unbiased
    // gather z1's two estimators and the own segment's transmittance.
    // Written by stage 1 (each record its own slice of n, so threads never share one).
    mutable std::vector<float> beta, L_out, nee, next, tr;

    Impl(const Scene& scene, SpectralMode mode, int wavelengths)
        : spectral(scene), sampler(mode, wavelengths, spectral.importance()) {}

    // The iteration's wavelengths with unit throughput.
    void start(SpectralPath& p) const {
        p.n = n;
        p.c = set.conditioning;
        p.ws.n = n;
        p.ws.conditioning = set.conditioning;
        for (int i = 0; i < n; ++i) {
            p.ws.lambda[i] = set.lambda[i];
            p.ws.q[i] = set.q[i];
            p.ws.a[i] = set.a[i];
            p.beta[i] = 1.0f;
            p.r[i] = 1.0f;
            p.response[i] = response[i];
        }
        p.update_mix();
    }
    // p's state (wavelengths, relative densities, mixture) with throughput `beta` (null: 1).
    void continue_from(const SpectralPath& from, SpectralPath& p, const float* beta) const {
        start(p);
        for (int i = 0; i < n; ++i) {
            p.r[i] = from.r[i];
            p.beta[i] = beta ? beta[i] : 1.0f;
        }
        p.inv_mix = from.inv_mix;
    }
    // The RGB of sum_i response_i w_i v_i.
    Color rgb(const float* w, const float* v) const {
        Color sum(0.0f);
        for (int i = 0; i < n; ++i)
            if (w[i] != 0.0f) sum += response[i] * (w[i] * v[i]);
        return sum;
    }

    template <bool kMedia>
    SuffixSample trace_suffix(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                              const PathState& prefix, const SpectralPath& p, const BsdfSample& bs, int light_samples,
                              int own_samples, bool dirac_z1_per_pixel, Rng& rng, LocalCounters& counters,
                              float* L_out_k, float* nee_k, float* next_k, float* tr_k) const;
    template <bool kMedia>
    PathRecord trace_record(size_t k, const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                            LocalCounters& counters, const Camera& camera, RecordAttribs* attribs,
                            TechniqueDensity* model, const PixelStrata* strata, int extra_paths, PrivateSuffix* extra,
                            bool dirac_z1_per_pixel, RecordMedia* record_media) const;
};

// A Dirac lobe or a Subsurface lobe sampled at x1: the pixel keeps the rest of the path, traced as
// the spectral path tracer would from there (path p, scaled by 1 / own_samples).
template <bool kMedia>
Color continue_privately(const SpectralScene& spectral, const Scene& scene, const RenderSettings& settings,
                         ShadingPoint sp, BsdfSample bs, PathState st, SpectralPath& p, Rng& rng,
                         LocalCounters& counters) {
    Color L(0.0f);
    SpectralThroughput path(spectral, p);
    path.at_material(sp);
    auto unclamped = [](const Color& c, bool) { return c; };
    if (picks_subsurface(sp, bs)) {
        // The walk to the exit, the exit's light sample and its BSDF sample (bs) at x1's depth.
        PathState at_x1 = st;
        --at_x1.depth;
        if (!path.subsurface(L, unclamped, scene, settings, sp, bs, rng, counters, at_x1) || !bs.valid()) return L;
        st = PathState{at_x1.depth + 1, bs.delta, bs.pdf, sp.hit.p};
        st.ray_flags = at_x1.ray_flags, st.min_ray_pdf = at_x1.min_ray_pdf;
        st.diffuse_bounces = at_x1.diffuse_bounces, st.glossy_bounces = at_x1.glossy_bounces;
        st.transmission_bounces = at_x1.transmission_bounces, st.transparent_bounces = at_x1.transparent_bounces;
        st.medium = at_x1.medium;
        advance_ray_type(st, sp.bsdf, bs);
    }
    if (!path.scatter(sp, bs)) return L;
    if constexpr (kMedia) st.medium = medium_towards(scene, sp, bs.wi, st.medium);
    return L + trace_path_loop<SpectralThroughput, kMedia, true>(scene, settings, bounce_ray(sp, bs, st), st, rng,
                                                                 counters, SpectralThroughput(spectral, p));
}

namespace {

// What the suffix's loop leaves beside its SuffixSample (see SpectralSuffix).
struct SpectralSuffixParts {
    SuffixSample out;
    float seg_tr[kMaxWavelengths];  // the segment x1 -> z1's transmittance per wavelength (media)
    bool z1_sampled = false;        // z1 took a valid BSDF sample bs1
    bool tail_traced = false;       // and the path went on from it
    BsdfSample bs1;
    float f1[kMaxWavelengths];      // z1's BSDF towards bs1 (a non-Dirac bs1)
    float L_in[kMaxWavelengths];    // the radiance the rest of the path brought back along bs1, at unit throughput
};

// The suffix's policy for the path loop (path_loop.h), psf_rgb.cpp's RgbSuffix at the iteration's
// wavelengths: the loop starts with the ray of x1's BSDF sample, its first shaded vertex is z1.
//   x1 -> z1: the emission found (clamped as one of own_samples samples) and, in media, the single
//     scattering go to the pixel's own part, in RGB, under path `segment` (x1's share of the
//     sample's throughput); the segment's transmittance per wavelength is kept apart (seg_tr).
//   z1: its light sample per wavelength into L_out (and its estimator into nee, for the unbiased
//     gather), clamped as this pixel's path would be; its BSDF sample is kept (parts).
//   after z1: the rest of the path at unit throughput (path tail, its emission per wavelength into
//     L_in through SpectralPath::out), clamped and stopped by Russian roulette under the whole
//     path's throughput, as the spectral path tracer would.
class SpectralSuffix {
public:
    static constexpr bool kResampledLights = false;
    static constexpr bool kSubsurfaceWalks = false;  // the suffix starts with the diffuse ancestor set
    static constexpr bool kGlowDirections = false;   // its direct() weighs by the BSDF's density alone
    static constexpr bool kEndsAtFirstVertex = false;
    // w: the whole path's throughput up to z1 per wavelength; eta1: the radiance scaling of x1's
    // sample; L_out, nee: the record's per-wavelength storage (nee may be null).
    SpectralSuffix(const SpectralScene& spectral, SpectralPath& segment, SpectralPath& tail, SpectralSuffixParts* parts,
                   const float* w, int own_samples, float eta1, float* L_out, float* nee)
        : spectral_(spectral), segment_(spectral, segment), tail_(spectral, tail), tail_path_(tail), parts_(parts),
          w_(w), L_out_(L_out), nee_(nee), own_samples_(own_samples), eta1_(eta1) {
        tail.out = parts->L_in;
    }

    template <class Clamp>
    void emission(Color&, Clamp&&, const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                  const SurfaceHit& hit, const PathState& state, const RayMedia* media, const ShaderRay* sray) {
        if (!on_segment()) {
            return into_tail(settings, state.depth <= 1, [&](Color& unused) {
                tail_.emission(unused, unclamped, scene, settings, ray, found, hit, state, media, sray);
            });
        }
        auto share = [&](const Color& c, bool) { return clamp_sample_share(settings, c, own_samples_, state.depth <= 1); };
        segment_.emission(parts_->out.fixed, share, scene, settings, ray, found, hit, state, media, nullptr);
    }
    void scattering(Color&, const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                    LocalCounters& counters, bool skip_plane_lights) {
        Color unused(0.0f);
        // The single scattering along x1 -> z1 is this pixel's alone (path_space_filtering.cpp).
        if (on_segment()) segment_.scattering(parts_->out.fixed, scene, ray, media, rng, counters, skip_plane_lights);
        else tail_.scattering(unused, scene, ray, media, rng, counters, skip_plane_lights);
    }
    // The segment's transmittance is kept apart, folded into L_out after the loop (what arrives at x1).
    void attenuate(const RayMedia& media) {
        if (on_segment()) segment_.transmittances(media, kInf, parts_->seg_tr);
        else tail_.attenuate(media);
    }
    const Color& transparency_beta() const { return segment_.transparency_beta(); }
    bool is_black() const { return !on_segment() && tail_.is_black(); }
    void prepare(ShadingPoint& sp) {
        tail_.prepare(sp);
        if (++vertex_ != 1) return;
        parts_->out.found_z1(sp.hit);
        z1_material_ = &spectral_.material(sp.hit.material);
    }
    // z1's light sample per wavelength: Le T w_light / pdf times the path's wavelength weight (the
    // mixture of the prefix: x1 and z1 are non-Dirac here, r unchanged), kept as an estimator and
    // clamped as this pixel's path would be (neighbours reuse it under their own throughput).
    template <class Clamp>
    void direct(Color&, Clamp&&, const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                VertexSampler u, LocalCounters& counters, const PathState& state) {
        if (!at_z1()) {
            return into_tail(settings, state.depth == 0, [&](Color& unused) {
                tail_.direct(unused, unclamped, scene, settings, sp, u, counters, state);
            });
        }
        bool shadowed = false;
        const DirectSample ds = sample_direct_through(
            scene, settings, sp, u, counters, state.medium, 1, 1, [&](const ShadowRay& shadow, int32_t medium) {
                shadowed = true;
                return tail_.shadow_transmittances(scene, shadow.o, shadow.d, shadow.tmax, medium) ? Color(1.0f)
                                                                                                    : Color(0.0f);
            });
        if (!ds.valid) return;
        const SpectralPath& p = tail_path_;  // the prefix's wavelengths and mixture, as z1 has not scattered yet
        const int n = p.n;
        const float lum = luminance(ds.weighted);
        const EmitterSpectrum& e = spectral_.emitter(ds.light);
        float nee[kMaxWavelengths], f[kMaxWavelengths], v[kMaxWavelengths];
        for (int i = 0; i < n; ++i) nee[i] = lum * e(p.ws.lambda[i]) * (shadowed ? tail_.transmittance(i) : 1.0f) * p.inv_mix;
        parts_->out.nee_dir = ds.wi;
        if (nee_) std::copy(nee, nee + n, nee_);
        if (ds.hidden ? eval_spectral(lit_lobes(sp, ds), *z1_material_, p, ds.wi, f)
                      : eval_spectral(sp, *z1_material_, p, ds.wi, f)) {
            Color rgb(0.0f);  // the whole path's contribution: sum_i response_i w_i v_i
            for (int i = 0; i < n; ++i) {
                v[i] = f[i] * nee[i];
                if (w_[i] != 0.0f) rgb += p.response[i] * (w_[i] * v[i]);
            }
            const float scale = clamp_scale(settings, rgb, false);
            for (int i = 0; i < n; ++i) L_out_[i] += v[i] * scale;
        }
    }
    // At z1 the rest of the path starts at unit throughput (a Dirac lobe's weights go into it);
    // Russian roulette after z1 sees the whole path's throughput, as in the spectral path tracer.
    bool scatter(const ShadingPoint& sp, const BsdfSample& bs) {
        if (!at_z1()) {
            if (!tail_.scatter(sp, bs)) return false;
            if (bs.transmission) tail_eta_ *= sqr(bs.eta);
            return true;
        }
        SpectralPath& tail = tail_path_;
        const int n = tail.n;
        parts_->z1_sampled = true;
        parts_->bs1 = bs;
        float* f = parts_->f1;
        bool alive = true;
        if (bs.delta) alive = delta_event(sp, *z1_material_, bs, tail);
        else if (!eval_spectral(sp, *z1_material_, tail, bs.wi, f)) std::fill(f, f + n, 0.0f);
        if (!alive) return false;
        const float eta2 = eta1_ * (bs.transmission ? sqr(bs.eta) : 1.0f);
        float whole = 0.0f;
        for (int i = 0; i < n; ++i) {
            clamp_w_[i] = w_[i] * (bs.delta ? 1.0f : f[i] / bs.pdf);
            whole = std::max(whole, clamp_w_[i]);
        }
        rr_scale_ = whole * eta2;
        parts_->tail_traced = true;
        return true;
    }
    void after_scatter(const PathState& state, const BsdfSample& bs) { tail_.after_scatter(state, bs); }
    bool roulette(int depth, float, Rng& rng) { return at_z1() || tail_.roulette(depth, tail_eta_ * rr_scale_, rng); }
    void finish(LocalCounters& counters) const {
        if (parts_->tail_traced) tail_.finish(counters);
    }

private:
    static Color unclamped(const Color& c, bool) { return c; }
    // One of the tail's estimates (its emission along a ray, or a light sample), added by `add` to
    // L_in, clamped as the whole path's contribution (clamp_w_ times it, as RGB): RgbSuffix clamps it
    // under the whole path's clamp_beta, the spectral path tracer under the path's throughput.
    template <class Add>
    void into_tail(const RenderSettings& settings, bool direct, Add&& add) {
        Color unused(0.0f);
        const bool clamps = (direct ? settings.clamp_direct : settings.clamp_indirect) > 0.0f;
        SpectralPath& tail = tail_path_;
        float c[kMaxWavelengths];
        if (clamps) std::fill(c, c + tail.n, 0.0f), tail.out = c;
        add(unused);  // one call site: the tail's emission and light sampling are inlined once
        if (!clamps) return;
        tail.out = parts_->L_in;
        Color rgb(0.0f);
        for (int i = 0; i < tail.n; ++i)
            if (clamp_w_[i] != 0.0f) rgb += tail.response[i] * (clamp_w_[i] * c[i]);
        const float scale = clamp_scale(settings, rgb, direct);
        for (int i = 0; i < tail.n; ++i) parts_->L_in[i] += c[i] * scale;
    }
    bool on_segment() const { return vertex_ == 0; }
    bool at_z1() const { return vertex_ == 1; }
    const SpectralScene& spectral_;
    SpectralThroughput segment_, tail_;
    SpectralPath& tail_path_;
    SpectralSuffixParts* parts_;
    const SpectralMaterial* z1_material_ = nullptr;
    const float* w_;
    float clamp_w_[kMaxWavelengths];  // the whole path's throughput up to z1's sample (set there)
    float* L_out_;
    float* nee_;
    int vertex_ = 0;  // the vertices shaded so far (z1 is the first)
    int own_samples_;
    float eta1_, tail_eta_ = 1.0f, rr_scale_ = 1.0f;
};

}  // namespace

// trace_suffix of psf_rgb.cpp at the iteration's wavelengths: the suffix's per-pixel
// part (RGB) into the result's `fixed`, its radiance per wavelength into L_out_k, z1's estimators into
// nee_k and next_k and the segment's transmittance into tr_k (those three when given).
template <bool kMedia>
SuffixSample PsfSpectrum::Impl::trace_suffix(const Scene& scene, const RenderSettings& settings,
                                              const ShadingPoint& sp, const PathState& prefix, const SpectralPath& p,
                                              const BsdfSample& bs, int light_samples, int own_samples,
                                              bool dirac_z1_per_pixel, Rng& rng, LocalCounters& counters,
                                              float* L_out_k, float* nee_k, float* next_k, float* tr_k) const {
    std::fill(L_out_k, L_out_k + n, 0.0f);
    if (nee_k) std::fill(nee_k, nee_k + n, 0.0f), std::fill(next_k, next_k + n, 0.0f);
    if (tr_k) std::fill(tr_k, tr_k + n, 1.0f);
    if (!bs.valid()) {
        ++counters.samples_rejected;
        return SuffixSample{};
    }
    PathState st1 = suffix_state(sp, prefix, bs, light_samples, own_samples);
    const SpectralMaterial& sm = spectral.material(sp.hit.material);
    SpectralPath p1;
    continue_from(p, p1, p.beta);
    for (int i = 0; i < n; ++i) p1.beta[i] /= float(own_samples);
    if (bs.delta) {  // see trace_suffix in psf_rgb.cpp: the pixel keeps it
        st1.diffuse_ancestor = prefix.diffuse_ancestor;
        if constexpr (kMedia) st1.medium = prefix.medium;
        SuffixSample out;
        out.fixed = continue_privately<kMedia>(spectral, scene, settings, sp, bs, st1, p1, rng, counters);
        return out;
    }
    if constexpr (kMedia) st1.medium = medium_towards(scene, sp, bs.wi, prefix.medium);
    const Ray r1 = bounce_ray(sp, bs, st1);
    // w: the whole path's throughput up to z1 (for clamping and Russian roulette).
    float f[kMaxWavelengths], w[kMaxWavelengths];
    if (!eval_spectral(sp, sm, p, bs.wi, f)) std::fill(f, f + n, 0.0f);
    for (int i = 0; i < n; ++i) {
        w[i] = p.beta[i] * f[i] / bs.pdf;
        p1.beta[i] = w[i] / float(own_samples);
    }
    SpectralSuffixParts parts;
    std::fill(parts.seg_tr, parts.seg_tr + n, 1.0f);
    std::fill(parts.L_in, parts.L_in + n, 0.0f);
    SpectralPath tail;
    continue_from(p, tail, nullptr);
    trace_path_loop<SpectralSuffix, kMedia, true>(
        scene, settings, r1, st1, rng, counters,
        SpectralSuffix(spectral, p1, tail, &parts, w, own_samples, bs.transmission ? sqr(bs.eta) : 1.0f, L_out_k, nee_k));
    SuffixSample& out = parts.out;
    if (!out.has_suffix) return out;
    if (parts.z1_sampled) {
        const BsdfSample& bs1 = parts.bs1;
        float v[kMaxWavelengths];
        out.next_dir = bs1.wi;
        for (int i = 0; i < n; ++i) {
            if (next_k) next_k[i] = bs1.delta ? 0.0f : parts.L_in[i] / bs1.pdf;
            v[i] = bs1.delta ? parts.L_in[i] : parts.f1[i] * parts.L_in[i] / bs1.pdf;
        }
        if (bs1.delta && dirac_z1_per_pixel) {
            // The Dirac lobe at z1 stays with its pixel (psf_rgb.cpp), as it arrives at x1.
            for (int i = 0; i < n; ++i) v[i] *= parts.seg_tr[i];
            out.fixed += rgb(p1.beta, v);
        } else {
            for (int i = 0; i < n; ++i) L_out_k[i] += v[i];
        }
    }
    if constexpr (kMedia) {
        for (int i = 0; i < n; ++i) L_out_k[i] *= parts.seg_tr[i];
        if (tr_k) std::copy(parts.seg_tr, parts.seg_tr + n, tr_k);
    }
    return out;
}

template <bool kMedia>
PathRecord PsfSpectrum::Impl::trace_record(size_t k, const Scene& scene, const RenderSettings& settings, Ray ray,
                                           Sampler& sampler, LocalCounters& counters, const Camera& camera,
                                           RecordAttribs* attribs, TechniqueDensity* model, const PixelStrata* strata,
                                           int extra_paths, PrivateSuffix* extra, bool dirac_z1_per_pixel,
                                           RecordMedia* record_media) const {
    PathRecord rec;
    Rng& rng = sampler.rng();
    rec.beta = Color(1.0f);
    *model = TechniqueDensity{};
    for (int m = 0; m < extra_paths; ++m) extra[m] = PrivateSuffix{};
    SpectralPath p;
    start(p);
    PathState st = camera_path_state(ray.o);
    st.first_vertex_ahead = true;
    if constexpr (kMedia) st.medium = scene.camera_medium();
    X1PrefixEnd end;
    rec.fixed = trace_path_loop<PrefixThroughput, kMedia, true>(scene, settings, ray, st, rng, counters,
                                                                PrefixThroughput(spectral, p, &end), &sampler);
    if (!end.reached) return rec;
    const ShadingPoint& sp = end.sp;
    st = end.state;
    st.first_vertex_ahead = false;

    // x1: the first non-specular vertex ends the prefix.
    record_x1(rec, end, spectral_class(p), settings, camera, attribs);
    std::copy(p.beta, p.beta + n, &beta[k * size_t(n)]);
    *model = TechniqueDensity::of(sp.bsdf, sp.hit.p, sp.wo);
    if constexpr (kMedia) *record_media = RecordMedia{st.medium, medium_across(scene, sp, st.medium)};
    // Direct light at x1, per pixel, as in RGB (psf_rgb.cpp): light samples and the pixel's BSDF
    // samples by multi-sample MIS, with the same numbers (x1's, then the stream).
    const int light_samples = std::max(1, settings.psf_light_samples);
    const int own_samples = 1 + extra_paths;
    SpectralThroughput at_x1(spectral, p);
    auto share = [&](const Color& c, bool) { return clamp_sample_share(settings, c, light_samples, st.depth == 0); };
    const VertexSampler x1(rng, end.x1_names);
    auto add_light_sample = [&](VertexSampler u) {
        at_x1.at_material(sp);
        at_x1.direct(rec.fixed, share, scene, settings, sp, u, counters, st, light_samples, own_samples);
    };
    add_light_sample(x1);
    BsdfSample bs = sample_bsdf(sp, x1);
    for (int i = 1; i < light_samples; ++i) {
        add_light_sample(extra_light_numbers(strata, sampler, i, light_samples));
    }
    const size_t at = k * size_t(n);
    SuffixSample own = trace_suffix<kMedia>(scene, settings, sp, st, p, bs, light_samples, own_samples,
                                            dirac_z1_per_pixel, rng, counters, &L_out[at], exact ? &nee[at] : nullptr,
                                            exact ? &next[at] : nullptr, exact && media ? &tr[at] : nullptr);
    rec.fixed += own.fixed;
    if (own.has_suffix) {
        rec.has_suffix = true;
        static_cast<SuffixVertex&>(rec) = own;
        if (attribs) attribs->z1 = own.z_attr;
    }
    // The private extra paths (path_space_filtering.cpp), kept as their RGB contributions.
    const SpectralMaterial& sm = spectral.material(sp.hit.material);
    for (int m = 0; m < extra_paths; ++m) {
        float L[kMaxWavelengths], f[kMaxWavelengths];
        SuffixSample e = trace_suffix<kMedia>(scene, settings, sp, st, p, sample_bsdf(sp, extra_bsdf_numbers(strata, sampler, m)), light_samples,
                                              own_samples, dirac_z1_per_pixel, rng, counters, L, nullptr, nullptr,
                                              nullptr);
        rec.fixed += e.fixed;
        if (!e.has_suffix) continue;
        Connection c = connect(sp.hit.p, e.z, e.z_ng);
        if (!c.valid() || !eval_spectral(sp, sm, p, c.dir, f)) continue;
        for (int i = 0; i < n; ++i) f[i] *= L[i];
        extra[m].z = e.z;
        extra[m].z_ng = e.z_ng;
        extra[m].contribution = rgb(p.beta, f) * c.g;
    }
    return rec;
}

PsfSpectrum::PsfSpectrum(const Scene& scene, SpectralMode mode, int wavelengths)
    : impl_(std::make_unique<Impl>(scene, mode, wavelengths)) {}
PsfSpectrum::~PsfSpectrum() = default;

int PsfSpectrum::count() const { return impl_->sampler.count(); }

void PsfSpectrum::begin_iteration(const RenderSettings& settings, uint32_t s, size_t records, bool exact, bool media) {
    Impl& I = *impl_;
    // The iteration is the pixel sample of the spectral path tracer's sequence (one "pixel", 0 0).
    Rng wavelength_rng = pixel_sample_rng(0, 0, s, settings.seed ^ kWavelengthStream);
    float u, v;
    wavelength_offsets(I.sampler, settings, 0, 0, s, wavelength_rng, &u, &v);
    I.sampler.sample(u, v, wavelength_rng, &I.set);
    I.n = I.set.n;
    for (int i = 0; i < I.n; ++i) I.response[i] = rgb_response(I.set.lambda[i]) / I.set.q[i];
    I.exact = exact;
    I.media = media;
    const size_t arrays = 2 + (exact ? 2 : 0) + (exact && media ? 1 : 0);
    const double bytes = double(records) * double(I.n) * double(arrays) * sizeof(float);
    constexpr double kLimit = 4.0 * 1024 * 1024 * 1024;
    if (bytes > kLimit)
        throw std::runtime_error("spectral path-space filtering would keep " + std::to_string(int(bytes / 1e9)) +
                                 " GB of per-wavelength records (" + std::to_string(I.n) +
                                 " wavelengths per pixel): use fewer wavelengths (BRUTE_FORCE has 512), a "
                                 "smaller image or PATH");
    const size_t size = records * size_t(I.n);
    I.beta.resize(size);
    I.L_out.resize(size);
    I.nee.resize(exact ? size : 0);
    I.next.resize(exact ? size : 0);
    I.tr.resize(exact && media ? size : 0);
}

PathRecord PsfSpectrum::trace_record(bool media, size_t k, const Scene& scene, const RenderSettings& settings, Ray ray,
                                     Sampler& sampler, LocalCounters& counters, const Camera& camera,
                                     RecordAttribs* attribs, TechniqueDensity* model, const PixelStrata* strata,
                                     int extra_paths, PrivateSuffix* extra, bool dirac_z1_per_pixel,
                                     RecordMedia* record_media) const {
    return media ? impl_->trace_record<true>(k, scene, settings, ray, sampler, counters, camera, attribs, model, strata,
                                             extra_paths, extra, dirac_z1_per_pixel, record_media)
                 : impl_->trace_record<false>(k, scene, settings, ray, sampler, counters, camera, attribs, model, strata,
                                              extra_paths, extra, dirac_z1_per_pixel, record_media);
}

bool PsfSpectrum::eval(uint32_t material, const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, float* f) const {
    const Impl& I = *impl_;
    return eval_spectral(bsdf, wo, I.spectral.material(material), I.n, I.set.lambda, wi, f);
}

Color PsfSpectrum::combine(size_t k, const float* f, const float* L, const float* tr) const {
    const Impl& I = *impl_;
    const float* b = &I.beta[k * size_t(I.n)];
    Color sum(0.0f);
    for (int i = 0; i < I.n; ++i) {
        if (b[i] == 0.0f) continue;
        sum += I.response[i] * (b[i] * f[i] * L[i] * (tr ? tr[i] : 1.0f));
    }
    return sum;
}

const float* PsfSpectrum::L_out(size_t k) const { return &impl_->L_out[k * size_t(impl_->n)]; }
const float* PsfSpectrum::suffix_tr(size_t k) const { return &impl_->tr[k * size_t(impl_->n)]; }

void PsfSpectrum::reevaluate(size_t j, const Bsdf& bz, uint32_t z_material, const Vec3& z_wo, const Vec3& nee_dir,
                             const Vec3& next_dir, float* out) const {
    const Impl& I = *impl_;
    const size_t at = j * size_t(I.n);
    float f[kMaxWavelengths];
    std::fill(out, out + I.n, 0.0f);
    // A zero direction: the estimator found nothing (its weights are 0).
    if (length_sq(nee_dir) > 0.0f && eval(z_material, bz, z_wo, nee_dir, f))
        for (int i = 0; i < I.n; ++i) out[i] += f[i] * I.nee[at + i];
    if (length_sq(next_dir) > 0.0f && eval(z_material, bz, z_wo, next_dir, f))
        for (int i = 0; i < I.n; ++i) out[i] += f[i] * I.next[at + i];
}

bool PsfSpectrum::connection_tr(const Scene& scene, const ShadowRay& s, uint32_t visibility, int32_t medium,
                                float* tr) const {
    const Impl& I = *impl_;
    SurfaceHit hit;
    RayMedia media;
    if (intersect_through(scene, Ray{s.o, s.d, 0.0f, s.tmax, s.time, visibility}, medium, &hit, &media)) return false;
    for (int i = 0; i < I.n; ++i) tr[i] = std::exp(-spectral_optical_depth(I.spectral, media, kInf, I.set.lambda[i]));
    return true;
}

double PsfSpectrum::bytes_per_record() const {
    const Impl& I = *impl_;
    return double(I.beta.size() + I.L_out.size() + I.nee.size() + I.next.size() + I.tr.size()) * sizeof(float) /
           double(std::max<size_t>(1, I.beta.size() / size_t(std::max(1, I.n))));
}

}  // namespace smis
