// RGB path-space filtering's stage 1 on the path tracer's loop (path_loop.h). Two policies derived
// from the path tracer's RGB one (rgb_throughput.h) change only what differs:
//   RgbPrefix: the RGB camera prefix (camera_prefix.h, rgb_throughput.h) up to x1, its first
//     non-specular vertex, where the loop ends; a Subsurface lobe alone keeps the path tracer's walk
//     in the pixel.
//   RgbSuffix: the path from x1's BSDF sample on, in three parts the record keeps apart: the segment
//     x1 -> z1 (its emission and, in media, its single scattering: the pixel's own), z1's light sample
//     and BSDF sample (kept as estimators, for the unbiased variant's re-evaluation), and the rest
//     of the path from z1 at unit throughput (L_in), clamped and stopped by Russian roulette under
//     the whole path's throughput, as the path tracer would.
#include "integrators/psf_rgb.h"

#include <algorithm>

#include "integrators/rgb_throughput.h"
#include "integrators/tiles.h"

namespace smis {
namespace psf_detail {
namespace {

struct RgbPrefixEnd : X1PrefixEnd {
    Color beta{1.0f};  // the prefix throughput f_e / p up to x1
};

class RgbPrefix : public RgbCameraPrefix {
public:
    explicit RgbPrefix(RgbPrefixEnd* end) : RgbCameraPrefix(end), end_(end) {}
    // A Subsurface lobe alone: its exit would be x1, but the gather re-evaluates x1's BSDF from its
    // material, which is not the exit's; the pixel keeps PATH's estimate from here (unbiased, not
    // filtered), and the prefix ends.
    template <class Clamp>
    bool subsurface(Color& L, Clamp&&, const Scene& scene, const RenderSettings& settings, ShadingPoint& sp,
                    BsdfSample& bs, Rng& rng, LocalCounters& counters, const PathState& state) {
        PathState at_entry = state;
        at_entry.first_vertex_ahead = false;  // the path tracer's walk takes plain light samples
        L += trace_subsurface(scene, settings, sp, bs, at_entry, beta, rng, counters);
        return false;
    }
    void first_vertex(const ShadingPoint& sp, const PathState& state, const VertexSampler& numbers) {
        RgbCameraPrefix::first_vertex(sp, state, numbers);
        end_->sp = sp;
        end_->beta = beta;
    }

private:
    RgbPrefixEnd* end_;
};

// What the suffix's loop leaves beside its SuffixSample: z1's BSDF sample and the radiance the rest
// of the path brought back along it, at unit throughput.
struct SuffixParts {
    SuffixSample out;
    bool z1_sampled = false;
    BsdfSample bs1;
    Color L_in{0.0f};
};

// The suffix's policy (see the top of the file). The loop starts with the ray of x1's sample; its
// first shaded vertex is z1. Contributions go to `parts`, none to the loop's sum.
class RgbSuffix : public RgbThroughput {
public:
    static constexpr bool kResampledLights = false;
    static constexpr bool kSubsurfaceWalks = false;  // the suffix starts with the diffuse ancestor set
    static constexpr bool kGlowDirections = false;   // its direct() weighs by the BSDF's density alone
    // bsdf_weight: x1's share of this sample (prefix throughput times f / p over own_samples);
    // path_weight: the whole path's throughput up to z1; eta_scale: the refraction scaling up to x1's
    // bounce included.
    RgbSuffix(SuffixParts* parts, const Color& bsdf_weight, const Color& path_weight, float eta_scale,
              int own_samples)
        : parts_(parts), own_samples_(own_samples), eta_scale_(eta_scale),
          bsdf_weight_(bsdf_weight), path_weight_(path_weight) {}

    template <class Clamp>
    void emission(Color&, Clamp&&, const Scene& scene, const RenderSettings& settings, const Ray& ray, bool found,
                  const SurfaceHit& hit, const PathState& state, const RayMedia* media, const ShaderRay* sray) {
        const Color e = emission_along(scene, settings, ray, found, hit, state, media, sray);
        if (on_segment()) parts_->out.fixed += clamp_sample_share(settings, bsdf_weight_ * e, own_samples_, state.depth <= 1);
        else parts_->L_in += clamp_contribution(settings, beta * e, state.depth <= 1, clamp_beta_);
    }
    void scattering(Color&, const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                    LocalCounters& counters, bool skip_plane_lights) {
        // The single scattering along x1 -> z1 is this pixel's alone (path_space_filtering.cpp).
        const Color s = single_scattering(scene, ray, media, rng, counters, skip_plane_lights);
        if (on_segment()) parts_->out.fixed += bsdf_weight_ * s;
        else parts_->L_in += beta * s;
    }
    // The segment's transmittance is folded into L_out (it is what arrives at x1); z1 is shaded even
    // where it underflows to 0: other pixels' connections to z1 may see it (the unbiased variant's
    // denominators count this technique wherever its ray reaches z1).
    void attenuate(const RayMedia& media) {
        if (on_segment()) parts_->out.segment_tr = media.transmittance_to_end();
        else beta *= media.transmittance_to_end();
    }
    bool is_black() const { return !on_segment() && smis::is_black(beta); }
    void prepare(ShadingPoint& sp) {
        if (++vertex_ == 1) parts_->out.found_z1(sp.hit);
    }
    // z1's light sample, kept as an estimator and clamped as this pixel's path would be (neighbours
    // reuse it under their own throughput); after z1, the path tracer's.
    template <class Clamp>
    void direct(Color&, Clamp&&, const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                VertexSampler u, LocalCounters& counters, const PathState& state) {
        const DirectSample ds = sample_direct(scene, settings, sp, u, counters, state.medium);
        if (!ds.valid) return;
        if (at_z1()) {
            SuffixSample& out = parts_->out;
            out.nee_dir = ds.wi;
            out.nee_weighted = ds.weighted;
            out.L_out += clamp_contribution(settings, direct_eval(sp, ds) * ds.weighted, false, path_weight_);
        } else {
            parts_->L_in += clamp_contribution(settings, beta * direct_eval(sp, ds) * ds.weighted, state.depth == 0,
                                               clamp_beta_);
        }
    }
    // At z1 the rest of the path starts at unit throughput; Russian roulette and clamping there see
    // the whole path's throughput, as in PATH (a suffix traced as if it started with throughput 1
    // would survive longer, costing more per path).
    bool scatter(const ShadingPoint&, const BsdfSample& bs) {
        if (!at_z1()) {
            beta *= bs.value / bs.pdf;
            if (bs.transmission) tail_eta_ *= sqr(bs.eta);
            return true;
        }
        parts_->z1_sampled = true;
        parts_->bs1 = bs;
        clamp_beta_ = path_weight_ * bs.value / bs.pdf;
        rr_scale_ = max_component(clamp_beta_) * (eta_scale_ * (bs.transmission ? sqr(bs.eta) : 1.0f));
        return true;
    }
    bool roulette(int depth, float, Rng& rng) {
        return at_z1() || (russian_roulette(depth, beta, tail_eta_ * rr_scale_, rng) && !smis::is_black(beta));
    }

private:
    bool on_segment() const { return vertex_ == 0; }
    bool at_z1() const { return vertex_ == 1; }
    SuffixParts* parts_;
    int vertex_ = 0;  // the vertices shaded so far (z1 is the first)
    int own_samples_;
    float eta_scale_, tail_eta_ = 1.0f, rr_scale_ = 1.0f;
    Color bsdf_weight_, path_weight_, clamp_beta_{1.0f};
};

template <bool kMedia, bool kRules>
void trace_suffix_loop(const Scene& scene, const RenderSettings& settings, const Ray& r1, const PathState& st1,
                       Rng& rng, LocalCounters& counters, RgbSuffix&& suffix) {
    trace_path_loop<RgbSuffix, kMedia, kRules>(scene, settings, r1, st1, rng, counters, suffix);
}

// The suffix started by BSDF sample `bs` at x1 (shading point sp, prefix throughput beta, refraction
// scaling eta_scale). x1 takes `light_samples` light samples and `own_samples` BSDF samples per
// iteration, combined by multi-sample MIS, so this sample carries 1/own_samples of the BSDF
// technique's per-pixel part. kMedia: the scene has media; prefix.medium is the one the prefix
// arrived in at x1.
template <bool kMedia>
SuffixSample trace_suffix(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                          const PathState& prefix, const BsdfSample& bs, const Color& beta, float eta_scale,
                          int light_samples, int own_samples, bool dirac_z1_per_pixel, Rng& rng,
                          LocalCounters& counters) {
    if (!bs.valid()) {
        ++counters.samples_rejected;
        return SuffixSample{};
    }
    PathState st1 = suffix_state(sp, prefix, bs, light_samples, own_samples);
    if constexpr (kMedia) st1.medium = medium_towards(scene, sp, bs.wi, prefix.medium);
    const Ray r1 = bounce_ray(sp, bs, st1);
    const Color path_weight = beta * bs.value / bs.pdf;
    const Color bsdf_weight = path_weight / float(own_samples);
    if (bs.delta) {
        // A Dirac lobe of a mixed BSDF: its suffix has no density to share, so the pixel keeps it,
        // traced as PATH would (a Subsurface lobe walks on from x1; after a Dirac bounce the next
        // hit's subsurface walks too).
        SuffixSample out;
        if (picks_subsurface(sp, bs)) {
            out.fixed = trace_subsurface(scene, settings, sp, bs, prefix, beta / float(own_samples), rng, counters);
        } else {
            st1.clamp_beta = path_weight;
            st1.diffuse_ancestor = prefix.diffuse_ancestor;
            out.fixed = bsdf_weight * trace_path(scene, settings, r1, st1, rng, counters);
        }
        return out;
    }
    SuffixParts parts;
    const float eta1 = eta_scale * (bs.transmission ? sqr(bs.eta) : 1.0f);
    RgbSuffix suffix(&parts, bsdf_weight, path_weight, eta1, own_samples);
    if (uses_light_path_rules(scene, settings))
        trace_suffix_loop<kMedia, true>(scene, settings, r1, st1, rng, counters, std::move(suffix));
    else
        trace_suffix_loop<kMedia, false>(scene, settings, r1, st1, rng, counters, std::move(suffix));
    SuffixSample& out = parts.out;
    if (!parts.z1_sampled) {
        if (kMedia && out.has_suffix) out.L_out *= out.segment_tr;
        return out;
    }
    const BsdfSample& bs1 = parts.bs1;
    out.next_dir = bs1.wi;
    out.next_weighted = bs1.delta ? Color(0.0f) : parts.L_in / bs1.pdf;
    const Color scattered = bs1.value / bs1.pdf * parts.L_in;
    if (bs1.delta && dirac_z1_per_pixel) {
        // A Dirac lobe at z1 sends another x1's connection to another direction than the one traced,
        // so in path space no other technique can produce this path (x1, z1, z2): its
        // balance-heuristic denominator (eq. 17) holds the pixel's own technique only, counted
        // own_samples times, and the path is the pixel's at full weight. (Re-evaluating z1's BSDF for
        // a neighbour's direction, as the unbiased gather does, gives 0 for Dirac lobes, so the shared
        // L_out must not carry it: it would be lost, not shared.)
        if constexpr (kMedia) out.fixed += bsdf_weight * scattered * out.segment_tr;  // as it arrives at x1
        else out.fixed += bsdf_weight * scattered;
    } else {
        out.L_out += scattered;
    }
    if constexpr (kMedia) out.L_out *= out.segment_tr;
    return out;
}

template <bool kMedia>
PathRecord trace_record(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                        LocalCounters& counters, const Camera& camera, RecordAttribs* attribs,
                        TechniqueDensity* model, const PixelStrata* strata, int extra_paths, PrivateSuffix* extra,
                        bool dirac_z1_per_pixel, RecordMedia* media) {
    PathRecord rec;
    Rng& rng = sampler.rng();
    *model = TechniqueDensity{};
    for (int m = 0; m < extra_paths; ++m) extra[m] = PrivateSuffix{};
    PathState st = camera_path_state(ray.o);
    st.first_vertex_ahead = true;
    if constexpr (kMedia) st.medium = scene.camera_medium();
    RgbPrefixEnd end;
    rec.fixed =
        trace_path_loop<RgbPrefix, kMedia, true>(scene, settings, ray, st, rng, counters, RgbPrefix(&end), &sampler);
    if (!end.reached) return rec;
    const ShadingPoint& sp = end.sp;
    st = end.state;
    st.first_vertex_ahead = false;
    const Color& beta = end.beta;

    // x1: the first non-specular vertex ends the prefix.
    record_x1(rec, end, kSharedClass, settings, camera, attribs);
    rec.beta = beta;
    *model = TechniqueDensity::of(sp.bsdf, sp.hit.p, sp.wo);
    if constexpr (kMedia) *media = RecordMedia{st.medium, medium_across(scene, sp, st.medium)};
    // Direct light at x1, per pixel: psf_light_samples light samples and the pixel's BSDF samples
    // (its path's own and its extra paths'), combined by multi-sample MIS (each density counted
    // that many times in both weights). The first light sample and the path's BSDF sample take x1's
    // numbers (by name when x1 is the camera path's first vertex, camera_prefix.h); the extra light
    // and BSDF samples are drawn from the stream after them, stratified on their own. The BSDF
    // samples' weights read the counts from PathState::light_pdf_scale (suffix_state).
    const int light_samples = std::max(1, settings.psf_light_samples);
    const int own_samples = 1 + extra_paths;
    const VertexSampler x1(rng, end.x1_names);
    auto add_light_sample = [&](VertexSampler u) {
        DirectSample ds = sample_direct(scene, settings, sp, u, counters, st.medium, light_samples, own_samples);
        if (ds.valid)
            rec.fixed += clamp_sample_share(settings, beta * direct_eval(sp, ds) * ds.weighted, light_samples,
                                            st.depth == 0);
    };
    add_light_sample(x1);
    BsdfSample bs = sample_bsdf(sp, x1);
    for (int i = 1; i < light_samples; ++i) {
        add_light_sample(extra_light_numbers(strata, sampler, i, light_samples));
    }
    SuffixSample own = trace_suffix<kMedia>(scene, settings, sp, st, bs, beta, end.eta_scale, light_samples,
                                            own_samples, dirac_z1_per_pixel, rng, counters);
    rec.fixed += own.fixed;
    if (own.has_suffix) {
        rec.has_suffix = true;
        static_cast<SuffixVertex&>(rec) = own;
        if (attribs) attribs->z1 = own.z_attr;
        if constexpr (kMedia) media->suffix_tr = own.segment_tr;
    }
    // The private extra paths: more samples of this pixel's own technique, where the filter has
    // little to share (path_space_filtering.cpp, iteration()).
    for (int m = 0; m < extra_paths; ++m) {
        SuffixSample e = trace_suffix<kMedia>(scene, settings, sp, st, sample_bsdf(sp, extra_bsdf_numbers(strata, sampler, m)), beta, end.eta_scale,
                                              light_samples, own_samples, dirac_z1_per_pixel, rng, counters);
        rec.fixed += e.fixed;
        if (!e.has_suffix) continue;
        Connection c = connect(sp.hit.p, e.z, e.z_ng);
        if (!c.valid()) continue;
        extra[m].z = e.z;
        extra[m].z_ng = e.z_ng;
        extra[m].contribution = sp.bsdf.eval(sp.wo, c.dir) * e.L_out * c.g;
    }
    return rec;
}

}  // namespace

PathRecord trace_rgb_record(bool media, const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                            LocalCounters& counters, const Camera& camera, RecordAttribs* attribs,
                            TechniqueDensity* model, const PixelStrata* strata, int extra_paths, PrivateSuffix* extra,
                            bool dirac_z1_per_pixel, RecordMedia* record_media) {
    return media ? trace_record<true>(scene, settings, ray, sampler, counters, camera, attribs, model, strata, extra_paths,
                                      extra, dirac_z1_per_pixel, record_media)
                 : trace_record<false>(scene, settings, ray, sampler, counters, camera, attribs, model, strata,
                                       extra_paths, extra, dirac_z1_per_pixel, nullptr);
}

}  // namespace psf_detail
}  // namespace smis
