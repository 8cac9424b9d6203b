// ReSTIR (Bitterli et al. 2020, Alg. 5) for the direct light at the camera path's first non-specular
// vertex x1, with the offline analogue of temporal reuse. One iteration (one sample per pixel):
//   1. trace: per pixel the camera prefix through Dirac bounces to x1 (the path tracer's loop,
//      path_loop.h, with the RestirPrefix policy below), x1's initial RIS reservoir (M candidates,
//      visibility reuse: an occluded selection is dropped), and the rest of the path (BSDF sample at
//      x1 and the path tracer from there), which is kept per pixel as `fixed`;
//   2. temporal (only with a history cap > 0; off by default, see RenderSettings::restir_history_cap):
//      the reservoir is combined with the same pixel's final reservoir of the previous iteration (a
//      different x1: another sub-pixel position), its M capped at cap x M;
//   3. spatial: combined with the reservoirs of k random pixels within a screen radius whose x1 is
//      similar (normals within ~25 degrees, path length within 10%: decisions from geometry only,
//      so they select techniques without biasing them);
//   4. shade: the final reservoir's sample, plus `fixed`, to the film; the final reservoirs become
//      the next iteration's history. With visibility in the MIS the combination has traced the
//      sample's visibility from x1 already (and dropped an occluded one): no shadow ray here.
// Only the direct light at x1 is resampled (MIS-combined with x1's BSDF sample, see
// reservoir_contribution); emission along the prefix and everything after x1 is the path
// tracer's, so the image converges to the path tracer's.
// A subsurface exit is a surface vertex like any other: x1 when the Subsurface lobe is the entry's
// only one (the entry is then a Dirac vertex of the prefix), else the path tracer's part after x1.
// With media the prefix's segments carry transmittance and single scattering as the path tracer's
// do (the loop's), and the resampled light at x1 its shadow ray's transmittance (unshadowed
// targets, visibility [T > 0] in the reservoirs and the MIS: direct_lighting.h).
#include "integrators/restir.h"

#include "integrators/aux_passes.h"

#include "integrators/reservoir_reuse.h"
#include "integrators/rgb_throughput.h"
#include "integrators/tiles.h"

namespace smis {
namespace {

// Stream offsets of the reuse stages, distinct from the camera sample's stream.
constexpr uint32_t kTemporalStream = 0x7e3a91c5u, kSpatialStream = 0x2b8d4f17u;

// Where the camera prefix ended (camera_prefix.h); x1 itself is written into the pixel record.
struct RestirPrefixEnd : PrefixEnd {
    bool subsurface_exit = false;  // x1 is the exit of a Subsurface lobe alone (a Dirac entry); the
                                   // state is the entry's then (the walk is no bounce)
};

// The camera path up to x1 on the path tracer's loop (the RGB camera prefix), changing only what
// differs: x1's shading point, throughput and medium go into the pixel record, and a Subsurface
// lobe alone walks to its exit, which is x1.
class RestirPrefix : public RgbCameraPrefix {
public:
    RestirPrefix(RestirPixel* px, RestirPrefixEnd* end) : RgbCameraPrefix(end), px_(px), end_(end) {}
    // In media a segment's emission and single scattering join L as one sum (emission first), the
    // order ReSTIR's stage 1 has always added them in, so its images stay bit-identical.
    template <class Clamp>
    void emission(Color& L, Clamp&& clamped, const Scene& scene, const RenderSettings& settings, const Ray& ray,
                  bool found, const SurfaceHit& hit, const PathState& state, const RayMedia* media,
                  const ShaderRay* sray) {
        const Color e = clamped(beta * emission_along(scene, settings, ray, found, hit, state, media, sray),
                                state.depth <= 1);
        if (media && state.depth <= settings.max_bounces) segment_emission_ = e;  // scattering() adds it
        else L += e;
    }
    void scattering(Color& L, const Scene& scene, const Ray& ray, const RayMedia& media, Rng& rng,
                    LocalCounters& counters, bool skip_plane_lights) const {
        L += segment_emission_ + beta * single_scattering(scene, ray, media, rng, counters, skip_plane_lights);
    }
    template <class Clamp>
    bool subsurface(Color&, Clamp&&, const Scene& scene, const RenderSettings&, ShadingPoint& sp, BsdfSample& bs,
                    Rng& rng, LocalCounters&, const PathState& state) {
        if (!subsurface_step(scene, sp, bs, beta, rng)) return false;
        end_->subsurface_exit = true;
        first_vertex(sp, state, VertexSampler(rng));  // the entry took the names: the exit draws the stream
        return false;
    }
    void first_vertex(const ShadingPoint& sp, const PathState& state, const VertexSampler& numbers) {
        RgbCameraPrefix::first_vertex(sp, state, numbers);
        px_->has_vertex = true;
        px_->camera_hit = state.depth == 0;
        px_->sp = sp;
        px_->beta = beta;
        px_->medium = state.medium;
    }

private:
    RestirPixel* px_;
    RestirPrefixEnd* end_;
    Color segment_emission_{0.0f};
};

// Stage 1 for one pixel sample, written in place (a pixel record is large: no copies). kMedia: the
// scene has media (instantiated only then). The path draws from the sampler's stream; x1's
// candidates too, and its BSDF sample asks for the first vertex's lobe and direction by name when x1
// is the camera path's first vertex (as RIS in the path tracer: path_loop.h).
template <bool kMedia>
void trace_pixel(const Scene& scene, const RenderSettings& settings, const Ray& camera, Sampler& sampler,
                 LocalCounters& counters, RestirPixel& px) {
    Rng& rng = sampler.rng();
    px.has_vertex = false;
    px.beta = Color(0.0f);
    px.r = Reservoir{};
    px.eval = CandidateEval{};
    PathState st = camera_path_state(camera.o);
    st.first_vertex_ahead = true;
    if constexpr (kMedia) st.medium = scene.camera_medium();
    RestirPrefixEnd end;
    px.fixed = trace_path_loop<RestirPrefix, kMedia, true>(scene, settings, camera, st, rng, counters,
                                                           RestirPrefix(&px, &end), &sampler);
    px.distance = end.distance;
    if (!end.reached) return;
    // x1's reservoir; resampled: the vertex the next ray leaves from took it (x1 itself, also when it
    // is the exit of a Subsurface lobe alone; not the exit of a Subsurface lobe x1 samples below).
    st = end.state;
    st.first_vertex_ahead = false;
    px.r = ris_reservoir(scene, px.sp, settings.ris_candidates, settings.restir_visibility_reuse, rng, &px.eval,
                         st.medium);
    Color beta = px.beta;
    float eta_scale = end.eta_scale;
    bool resampled = true;
    const ShadingPoint* from = &px.sp;
    ShadingPoint exit;
    BsdfSample bs = sample_bsdf(px.sp, VertexSampler(rng, end.x1_names));
    if (!end.subsurface_exit && picks_subsurface(px.sp, bs)) {
        // The subsurface exit after x1 is a surface vertex at x1's depth with plain NEE (part of the
        // path tracer's estimate after x1, as in PATH).
        exit = px.sp;
        Color direct;
        if (!subsurface_bounce(scene, settings, exit, bs, beta, rng, counters, st.medium, &direct)) return;
        px.fixed += clamp_contribution(settings, direct, st.depth == 0);
        resampled = false;
        from = &exit;
    }
    if (!bs.valid()) {
        ++counters.samples_rejected;
        return;
    }
    beta *= bs.value / bs.pdf;
    if (bs.transmission) eta_scale *= sqr(bs.eta);
    update_transparent_background(settings, st, from->bsdf, bs);
    advance_ray_type(st, from->bsdf, bs);
    if constexpr (kMedia) st.medium = medium_towards(scene, *from, bs.wi, st.medium);
    st.prev_delta = bs.delta;
    st.light_pdf_scale = resampled ? resampled_light_pdf_scale(settings) : 1.0f;
    st.prev_pdf = bs.pdf;
    st.prev_p = from->hit.p;
    const Ray ray = bounce_ray(*from, bs, st);
    if (!russian_roulette(st.depth, beta, eta_scale, rng) || is_black(beta)) return;
    // The rest of the path, with NEE from here on.
    ++st.depth;
    st.clamp_beta = beta;
    px.fixed += beta * trace_path(scene, settings, ray, st, rng, counters);
}

}  // namespace

void trace_restir_pixel(const Scene& scene, const RenderSettings& settings, const Ray& camera, Sampler& sampler,
                        LocalCounters& counters, RestirPixel& px) {
    if (scene.has_media()) trace_pixel<true>(scene, settings, camera, sampler, counters, px);
    else trace_pixel<false>(scene, settings, camera, sampler, counters, px);
}

namespace {

// Bitterli et al. 2020's neighbour heuristic, on geometry only.
bool similar(const RestirPixel& a, const RestirPixel& b) {
    return dot(a.sp.ns, b.sp.ns) >= 0.9f && std::fabs(a.distance - b.distance) <= 0.1f * a.distance;
}

Rng stage_rng(const RenderContext& ctx, int x, int y, uint32_t s, uint32_t stream) {
    const Camera& cam = ctx.scene.camera();
    return pixel_sample_rng(x + cam.window_x0(), y + cam.window_y0(), s, ctx.settings.seed ^ stream);
}

}  // namespace

RestirIntegrator::RestirIntegrator(const Scene& scene, spectral::SpectralMode mode, int wavelengths,
                                   float fixed_wavelength)
    : spectral_(std::make_unique<SpectralPathIntegrator>(scene, mode, wavelengths, fixed_wavelength)) {}

void RestirIntegrator::iteration(RenderContext& ctx, uint32_t s) {
    const Scene& scene = ctx.scene;
    const RenderSettings& settings = ctx.settings;
    const int w = ctx.film.width(), h = ctx.film.height();
    const size_t n_pixels = size_t(w) * h;
    // Without visibility reuse the reservoirs keep occluded samples, so unshadowed pdfs are the
    // right MIS pdfs and no shadow ray is needed; with it, leaving visibility out is the biased mode.
    const bool visibility_in_mis = settings.restir_visibility_reuse && settings.restir_unbiased;
    const int k = std::max(0, settings.restir_neighbors);
    const float history_cap = float(std::max(0, settings.restir_history_cap)) * float(std::max(1, settings.ris_candidates));
    // The buffers are kept between iterations (a pixel record holds a shading point: allocating and
    // faulting in a fresh image-sized array per iteration was measurable).
    std::vector<RestirPixel>& cur = cur_;
    cur.resize(n_pixels);
    const size_t n_lambda = spectral_ ? size_t(spectral_->wavelength_count()) : 0;
    lambda_.resize(n_pixels * n_lambda);
    weight_.resize(n_pixels * n_lambda);
    std::atomic<uint64_t> pdf_evaluations{0}, shadow_rays{0}, neighbours{0}, vertices{0};
    auto flush_cost = [&](const ReuseCost& c) {
        pdf_evaluations += c.pdf_evaluations;
        shadow_rays += c.shadow_rays;
    };

    // Two passes, each with one barrier: stages 1-2 and stages 3-4 read only their own pixel's (and,
    // for 3, neighbours' stage-2) data. Every stage keeps its own random stream.
    const bool temporal = prev_.size() == n_pixels && history_cap > 0.0f;
    auto t0 = StageClock::now();
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        const size_t i = size_t(y) * w + x;
        RestirPixel& me = cur[i];
        const PixelCamera camera = pixel_camera(ctx, x, y);
        Sampler sampler;
        const Ray ray = pixel_camera_ray(camera, s, &sampler);
        local.sample_transparency = 0.0f;
        me.passes = ctx.film.has_aux() ? FirstHitPasses(ctx, x, y, s) : FirstHitPasses();
        {
            RecordPasses recording(local, ctx.film.has_aux() ? &me.passes : nullptr);
            if (spectral_) {
                const Camera& cam = scene.camera();
                me.fixed = spectral_->trace_restir_pixel(ctx, x + cam.window_x0(), y + cam.window_y0(), s, ray, sampler,
                                                         local, me, &lambda_[i * n_lambda], &weight_[i * n_lambda]);
            } else {
                trace_restir_pixel(scene, settings, ray, sampler, local, me);
            }
        }
        me.transparency = local.sample_transparency;
        ++local.paths;
        const RestirPixel& old = temporal ? prev_[i] : me;
        if (!temporal || !me.has_vertex || !old.has_vertex) return;
        Reservoir history = prev_final_[i];
        history.M = std::min(history.M, history_cap);
        const Reservoir initial = me.r;
        const CandidateEval initial_eval = me.eval;
        const ReuseInput inputs[2] = {{&initial, &me.sp, &initial_eval, me.medium},
                                      {&history, &old.sp, nullptr, old.medium}};
        Rng temporal_rng = stage_rng(ctx, x, y, s, kTemporalStream);
        ReuseCost cost;
        CombinedReservoir c =
            combine_reservoirs(scene, me.sp, inputs, 2, settings.restir_mis, visibility_in_mis, temporal_rng, cost);
        me.r = c.r;
        me.eval = c.at_q;
        flush_cost(cost);
    });
    if (ctx.should_stop()) return;  // a partial iteration never reaches the film
    trace_seconds_ += seconds_since(t0);

    t0 = StageClock::now();
    final_.resize(n_pixels);
    const float radius = std::max(1.0f, settings.restir_radius_px);
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        const size_t i = size_t(y) * w + x;
        const RestirPixel& me = cur[i];
        Color L = me.fixed;
        final_[i] = Reservoir{};
        if (me.has_vertex) {
            ++vertices;
            thread_local std::vector<ReuseInput> inputs;
            inputs.assign(1, ReuseInput{&me.r, &me.sp, &me.eval, me.medium});
            Rng rng = stage_rng(ctx, x, y, s, kSpatialStream);
            // Up to 2k tries for k neighbours, as Bitterli et al. do, so dissimilar surroundings do not loop.
            for (int attempt = 0; attempt < 2 * k && int(inputs.size()) <= k; ++attempt) {
                Point2 d = sample_uniform_disk_concentric({rng.next_float(), rng.next_float()});
                int nx = x + int(std::lround(d.x * radius)), ny = y + int(std::lround(d.y * radius));
                if ((nx == x && ny == y) || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
                const RestirPixel& other = cur[size_t(ny) * w + nx];
                if (other.has_vertex && similar(me, other))
                    inputs.push_back(ReuseInput{&other.r, &other.sp, nullptr, other.medium});
            }
            neighbours += inputs.size() - 1;
            ReuseCost cost;
            CombinedReservoir c = combine_reservoirs(scene, me.sp, inputs.data(), int(inputs.size()),
                                                     settings.restir_mis, visibility_in_mis, rng, cost);
            flush_cost(cost);
            final_[i] = c.r;
            // The MIS weights traced the sample's visibility from here already when they include it
            // (with media, only whether its transmittance is black: the shading traces it again).
            // Clamping (Cycles' Clamp Direct / Indirect) takes the resampled estimate as the vertex's
            // one light sample.
            Color direct;
            if (spectral_) {  // the sample at each wavelength, through its own shadow ray unless known
                const float weight = resampled_weight(scene, settings, me.sp, c.r, c.at_q);
                if (weight > 0.0f)
                    direct = spectral_->shade_restir_vertex(scene, me, &lambda_[i * n_lambda], &weight_[i * n_lambda],
                                                            c.at_q, weight, c.visibility_known);
            } else {
                direct = me.beta * (c.visibility_known && !scene.has_media()
                                        ? visible_reservoir_contribution(scene, settings, me.sp, c.r, c.at_q)
                                        : reservoir_contribution(scene, settings, me.sp, c.r, me.medium));
            }
            L += clamp_contribution(settings, direct, me.camera_hit);
        }
        if (ctx.film.has_aux()) {  // diagnostic pass: the candidates the shaded reservoir stands for (M)
            add_aux_sample(ctx, x, y, s, me.passes, me.has_vertex ? final_[i].M : 0.0f);
        }
        ctx.film.add(x, y, guard_sample(L, local), me.transparency);
    });
    reuse_seconds_ += seconds_since(t0);
    std::swap(prev_, cur_);
    std::swap(prev_final_, final_);
    iterations_++;
    vertices_ += vertices.load();
    neighbours_ += neighbours.load();
    pdf_evaluations_ += pdf_evaluations.load();
    mis_shadow_rays_ += shadow_rays.load();
}

std::map<std::string, double> RestirIntegrator::stats() const {
    double it = iterations_ ? double(iterations_) : 1.0;
    double per_vertex = vertices_ ? 1.0 / double(vertices_) : 0.0;
    return {
        {"iterations", double(iterations_)},
        {"trace_seconds_per_iteration", trace_seconds_ / it},
        {"reuse_seconds_per_iteration", reuse_seconds_ / it},
        {"neighbours_per_pixel", double(neighbours_) * per_vertex},
        {"mis_pdf_evaluations_per_pixel", double(pdf_evaluations_) * per_vertex},
        {"mis_shadow_rays_per_pixel", double(mis_shadow_rays_) * per_vertex},
    };
}

}  // namespace smis
