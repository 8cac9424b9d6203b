// Path-space filtering (West et al. 2020, §4; Keller et al. 2014), as a progressive two-stage
// integrator. One iteration:
//   Stage 1 traces one path per pixel. Its prefix ybar runs from the camera through Dirac bounces to
//   the first non-specular vertex x1; its suffix zbar starts with the BSDF-sampled direction out of
//   x1 and its first vertex z1, and carries back the radiance leaving z1 towards x1.
//   Stage 2 gathers, for every prefix, the prefixes of other paths whose x1 lies within a radius
//   (6 pixels projected to world space at x1 by default) from a hashed grid, and combines their
//   suffixes with the weighting under test.
// What is reused and why: only the *indirect* light at x1, i.e. the suffix radiance excluding the
// emission at z1. Everything the pixel's own path can estimate well stays per pixel: emission along
// the prefix, next-event estimation at x1, and the emission its own BSDF sample finds at z1 (MIS'd
// with NEE). Reusing the direct light would not reduce its variance much (NEE already handles it) but
// would blur shadows; the indirect light is smooth over a small radius, which is where reuse pays.
// Densities are in the area measure at z1 (solid-angle pdf x |cos theta_z1| / d^2), for every term
// of the SMIS denominator (eq. 17).
//
// Stage 1 is the path tracer's own loop (path_loop.h) with policies that end the prefix at x1 and keep
// the suffix's parts apart: psf_rgb.cpp, and psf_spectral.cpp at one wavelength set per iteration.
//
// Media (scenes with media only: the stage-1 tracers are templates instantiated for them). The prefix
// and the suffix take their segments in the path tracer's loop (transmittance, single scattering,
// medium tracking), and x1's and z1's light samples carry their shadow rays' transmittance. Vertices are surface vertices only (volume bounces = 0), so the filter gathers as
// without media. The light arriving at x1 along its BSDF sample is split in two: the single
// scattering along the segment x1 -> z1, a per-pixel part (no other pixel's sample estimates its own
// segment), and T(x1, z1) L_out(z1), the reused part. A pixel q connecting to another path's z1
// needs T(q, z1), not the sampler's: the unbiased variant traces it with the connection's visibility
// (from the medium on that side of q), and its denominators count a technique wherever its ray can
// reach z1, which a boundary without a surface shader does not stop (connection_through_media). The
// biased variants reuse the sampler's T(x1_j, z1) L_out(z1) as they reuse its unoccluded L_out:
// their bias grows with the radius and the medium's density, and vanishes as the radius shrinks.
#include "integrators/path_space_filtering.h"

#include <algorithm>
#include <chrono>

#include "integrators/aux_passes.h"
#include "integrators/hash_grid.h"
#include "integrators/media_segments.h"
#include "integrators/path_tracing.h"
#include "integrators/psf_density.h"
#include "integrators/psf_records.h"
#include "integrators/psf_rgb.h"
#include "integrators/psf_spectral.h"
#include "integrators/psf_weighting.h"
#include "integrators/tiles.h"

namespace smis {

namespace psf_detail {
// Two versions, AVX2 (8 lanes) and the baseline x86-64 (SSE2, 4 lanes), picked by the loader on the
// machine at hand. Both compute every lane with the same IEEE operations (no FMA: AVX2 alone does not
// allow contracting a * b + c), so the images do not depend on which one runs.
[[gnu::target_clones("avx2", "default")]] void model_densities(const float* const* fields, size_t n, const Vec3& z,
                                                                 const Vec3& z_ng, float* out) {
    const float* const* f = fields;
    const float zx = z.x, zy = z.y, zz = z.z, wx = z_ng.x, wy = z_ng.y, wz = z_ng.z;  // in registers
    // `out` never overlaps the fields (ivdep spares the compiler 21 run-time alias checks).
#pragma GCC ivdep
    for (size_t j = 0; j < n; ++j)
        out[j] = model_density(zx - f[0][j], zy - f[1][j], zz - f[2][j], f[3][j], f[4][j], f[5][j], f[6][j], f[7][j],
                               f[8][j], f[9][j], f[10][j], f[11][j], f[12][j], f[13][j], f[14][j], f[15][j], f[16][j],
                               f[17][j], f[18][j], f[19][j], f[20][j], wx, wy, wz);
}
}  // namespace psf_detail

namespace {

using namespace psf_detail;

// Stage 2 gathers pixels in blocks that share a technique set (psf_block_size): sides of 1, 2 or 4,
// so that the tiles' side divides them and a block never spans two tiles (two threads).
constexpr int kMaxBlock = 4;
static_assert(kTileSize % kMaxBlock == 0 && kTileSize % 2 == 0, "a block must not span two tiles");
int psf_block_side(int requested) { return requested >= 4 ? 4 : requested >= 2 ? 2 : 1; }
// A block's pixel joins the group of the block's first pixel with a vertex (the anchor) when its x1
// lies within this many of the anchor's radii (it is then in the anchor's ball, and its techniques
// within two radii of it). 1.0 and 0.5 gave the same SMAPE on psf_room and psf_glossy; 1.0 groups
// more pixels (3.8 against 2.9 per set on psf_room) for ~15% less gather time.
constexpr float kGroupReach = 1.0f;

// One Dirac depth per technique set: a set holds prefixes of one Dirac depth only (the number of Dirac
// bounces before x1). A suffix is traced with the bounce budget its own prefix leaves
// (max_bounces - depth), so the density p(zbar | ybar_j) of eq. (17) is the density of a suffix whose
// length is bounded by ybar_j's depth: a deeper prefix cannot produce the longer suffixes a shallower
// pixel integrates, and a shallower one produces suffixes too long for a deeper pixel. Counting such
// prefixes in the denominator (only z1's density is evaluated) breaks eq. (15)'s condition that the
// weights be normalised over the technique space for every suffix: in a room with a mirror wall and a
// glass ball at max_bounces = 1, mixed sets made 6% of the pixels too dark or too bright. Eq. (15) lets the technique space depend on
// the prefix, T(ybar): grouping by depth keeps the estimator unbiased, costs nothing per sample and
// loses little reuse (a mirror's or a lens's x1 are gathered with each other; their neighbours of
// other depths mostly see other parts of the scene anyway). Making the budget independent of the
// prefix instead would change what is integrated: PATH bounds the whole path's length.

// Per-thread scratch of the gather. Reached through a function that is not inlined: a thread_local
// used in the hot loops costs a TLS lookup per use in a shared library (the compiler recomputes its
// address rather than keeping it in a register).
struct GatherScratch {
    std::vector<uint32_t> in_ball, nb;
    std::vector<BsdfTechnique> techniques;  // the unbiased variant's
    DensitySum density_sum;
    std::vector<float> per_sample;
    std::vector<int8_t> visible;  // the unbiased variant's visibility tests, sample x member
};
[[gnu::noinline]] GatherScratch* gather_scratch() {
    static thread_local GatherScratch scratch;
    return &scratch;
}

}  // namespace

struct PathSpaceFilteringIntegrator::IterationBuffers {
    std::vector<PathRecord> records;
    std::vector<TechniqueDensity> models;  // records[k]'s x1 as a technique
    std::vector<uint32_t> stored;
    std::vector<Vec3> positions;
    std::vector<float> radii;
    HashGrid grid;
    // Per pixel, across iterations: the weight of the pixel's own suffix in its estimate, summed over
    // the iterations that measured it (own_weight_n), and the extra BSDF samples taken so far (the
    // index of the next one in its stratified set).
    std::vector<float> own_weight_sum;
    std::vector<uint32_t> own_weight_n, extra_bsdf_taken;
    // This iteration's private extra suffixes: pixel k's are extras[extra_offset[k] ...], extra_paths[k] of them.
    std::vector<uint8_t> extra_paths;
    std::vector<uint32_t> extra_offset;
    std::vector<PrivateSuffix> extras;
    // The auxiliary passes (when on) as each pixel's camera path recorded them (aux_passes.h).
    std::vector<FirstHitPasses> passes;
};

PathSpaceFilteringIntegrator::PathSpaceFilteringIntegrator(PsfWeighting weighting, std::unique_ptr<PsfSpectrum> spectrum)
    : weighting_(weighting), spectrum_(std::move(spectrum)) {}
PathSpaceFilteringIntegrator::~PathSpaceFilteringIntegrator() = default;

void PathSpaceFilteringIntegrator::iteration(RenderContext& ctx, uint32_t s) {
    switch (weighting_) {
        case PsfWeighting::Path: return iterate<PsfPathWeighting>(ctx, s);
        case PsfWeighting::Keller: return iterate<PsfKellerWeighting>(ctx, s);
        case PsfWeighting::Smis: return iterate<PsfSmisWeighting>(ctx, s);
        case PsfWeighting::SmisUnbiased: return iterate<PsfSmisExactWeighting>(ctx, s);
    }
}

template <class W>
void PathSpaceFilteringIntegrator::iterate(RenderContext& ctx, uint32_t s) {
    const Scene& scene = ctx.scene;
    const RenderSettings& settings = ctx.settings;
    const int w = ctx.film.width(), h = ctx.film.height();
    // The per-pixel buffers live across iterations: reallocating ~15 MB of records every iteration
    // costs page faults comparable to the grid build.
    if (!buffers_) buffers_ = std::make_unique<IterationBuffers>();
    std::vector<PathRecord>& records = buffers_->records;
    std::vector<TechniqueDensity>& models = buffers_->models;
    records.resize(size_t(w) * h);
    models.resize(records.size());
    std::vector<RecordAttribs> attribs(scene.has_varying_materials() ? records.size() : 0);
    auto x1_attr = [&](size_t k) { return attribs.empty() ? SurfaceAttribs{} : attribs[k].x1; };
    const bool media = scene.has_media();
    std::vector<RecordMedia> record_media(media ? records.size() : 0);

    // Extra paths. Where the pixel's own suffix keeps most of the weight in its estimate (a sharp lobe
    // at x1, or glossy surfaces too thin or curved for neighbours to share its lobe), the filter cannot
    // lower the indirect light's variance, and the pixel gets up to psf_extra_paths more paths from x1
    // per iteration, in proportion to that weight's excess over an even share (excess_weight) averaged
    // over the past iterations (none in the first). They are more samples of the pixel's own technique: its density counts 1 + extra times
    // in the pixel's SMIS denominators (Veach's multi-sample balance heuristic with sample counts; the
    // neighbours, which see only the one shared suffix, count it once), so the estimator keeps eq. 17's
    // form and PSF_SMIS_UNBIASED stays unbiased (the counts are fixed before the iteration's samples).
    // The count is measured without the extra samples (density counted once), so extra paths do not
    // feed their own demand.
    const size_t pixels = records.size();
    IterationBuffers& b = *buffers_;
    if (b.own_weight_sum.size() != pixels) {
        b.own_weight_sum.assign(pixels, 0.0f);
        b.own_weight_n.assign(pixels, 0);
        b.extra_bsdf_taken.assign(pixels, 0);
    }
    const int max_extra = std::clamp(settings.psf_extra_paths, 0, 255);
    b.extra_paths.assign(pixels, 0);
    b.extra_offset.resize(pixels);
    uint32_t extra_total = 0;
    for (size_t k = 0; k < pixels; ++k) {
        b.extra_offset[k] = extra_total;
        if (max_extra == 0 || b.own_weight_n[k] == 0) continue;
        float mean = b.own_weight_sum[k] / float(b.own_weight_n[k]);
        b.extra_paths[k] = uint8_t(std::clamp(int(float(max_extra) * mean + 0.5f), 0, max_extra));
        extra_total += b.extra_paths[k];
    }
    b.extras.resize(extra_total);
    b.passes.resize(ctx.film.has_aux() ? pixels : 0);

    // Stage 1: one full path per pixel, and the pixel's extra paths (spectral: at the iteration's
    // wavelengths, psf_spectral.h).
    if (spectrum_) spectrum_->begin_iteration(settings, s, pixels, W::kExact, media);
    const bool extra_strata =
        kWithStratified && settings.sampling_pattern == SamplingPattern::Stratified && (settings.psf_light_samples > 1 || max_extra > 0);
    auto t0 = StageClock::now();
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        const PixelCamera camera = pixel_camera(ctx, x, y);
        Sampler sampler;
        const Ray ray = pixel_camera_ray(camera, s, &sampler);
        const size_t k = size_t(y) * w + x;
        PixelStrata strata{};
        if (extra_strata) strata = {camera.pixel_sampler().key(), s, b.extra_bsdf_taken[k]};
        const int extra = b.extra_paths[k];
        local.sample_transparency = 0.0f;
        RecordAttribs* record_attribs = attribs.empty() ? nullptr : &attribs[k];
        const PixelStrata* record_strata = extra_strata ? &strata : nullptr;
        PrivateSuffix* record_extras = b.extras.data() + b.extra_offset[k];
        constexpr bool dirac_z1_per_pixel = W::kExact;
        if (!b.passes.empty()) b.passes[k] = FirstHitPasses(ctx, x, y, s);
        RecordPasses recording(local, b.passes.empty() ? nullptr : &b.passes[k]);
        records[k] = spectrum_ ? spectrum_->trace_record(media, k, scene, settings, ray, sampler, local, scene.camera(),
                                                         record_attribs, &models[k], record_strata, extra,
                                                         record_extras, dirac_z1_per_pixel, media ? &record_media[k] : nullptr)
                   : trace_rgb_record(media, scene, settings, ray, sampler, local, scene.camera(), record_attribs,
                                      &models[k], record_strata, extra, record_extras, dirac_z1_per_pixel,
                                      media ? &record_media[k] : nullptr);
        records[k].transparency = local.sample_transparency;
        b.extra_bsdf_taken[k] += uint32_t(extra);
        ++local.paths;
    });
    if (ctx.should_stop()) return;  // a partial iteration never reaches the film
    stage1_seconds_ += seconds_since(t0);

    // The radius shrinks over iterations like progressive photon mapping's (Knaus & Zwicker 2011):
    // r_i = r_0 (i + 1)^((alpha - 1) / 2), so the bias vanishes as iterations accumulate.
    const float shrink = std::pow(float(s) + 1.0f, 0.5f * (settings.psf_radius_alpha - 1.0f));
    std::vector<uint32_t>& stored = buffers_->stored;
    std::vector<Vec3>& positions = buffers_->positions;
    std::vector<float>& radii = buffers_->radii;
    stored.clear();
    radii.clear();
    positions.resize(records.size());
    for (size_t i = 0; i < records.size(); ++i) {
        if (!records[i].has_vertex) continue;
        records[i].radius *= shrink;
        if (private_class(records[i].technique_class)) continue;  // shares nothing (psf_spectral.cpp)
        positions[i] = records[i].p;
        stored.push_back(static_cast<uint32_t>(i));
        radii.push_back(records[i].radius);
    }

    t0 = StageClock::now();
    HashGrid& grid = buffers_->grid;
    if (W::kGathers && !stored.empty()) {
        // Cells the size of the typical radius: a query visits 2-3 cells per axis (measured faster
        // than half-radius cells, whose 4-5 per axis cost more in lookups than they save in points).
        std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
        grid.build(positions, stored, radii[radii.size() / 2]);
    }
    grid_seconds_ += seconds_since(t0);

    // Stage 2: every prefix combines the suffixes gathered around its x1.
    //
    // Pixels are gathered in groups that share one technique set: the pixels of a
    // psf_block_size x psf_block_size square whose x1 lie within kGroupReach radii of the first one's
    // (the anchor). A pixel outside that reach, or in a block of 1, is a group of its own. A group's
    // set is its pixels' own techniques and, up to psf_max_neighbors, a uniform random subset of the
    // other x1 in the anchor's ball. Each pixel's estimate is still eq. (17) over that set: the set is
    // chosen from prefix positions only, never from the suffixes, and holds the pixel's own technique,
    // so the multi-sample balance heuristic stays unbiased (given visibility; exactly, in the unbiased
    // variant). What the pixels of a group share is the part of eq. (17) that does not depend on the
    // pixel: the grid query and every sample's denominator sum_k p(z_i | ybar_k), the k^2 density
    // evaluations that dominated the gather. Only f_1(ybar_j, zbar_i), the pixel's BSDF towards each
    // z_i, is per pixel. Blocks of 2 halved the gather per stored vertex (psf_room 2.95 -> 1.40 us,
    // psf_glossy 1.92 -> 0.97 us) at the same SMAPE at equal iterations (README).
    //
    // The pixels of a group share their noise, so the block grid moves every iteration (an offset
    // drawn from the iteration and the seed; blocks are cut at tile edges): a fixed grid would add
    // the same blocks' noise up into a visible pattern.
    //
    // A pixel's extra paths (see above) are samples its group's other pixels do not see, so in its own
    // estimate its technique counts 1 + extra times: the shared denominator (every technique counted
    // once) plus extra * p(z | its own technique).
    t0 = StageClock::now();
    std::atomic<uint64_t> gathered{0}, accepted{0}, groups{0}, grouped_pixels{0}, visibility_rays_total{0};
    const int max_n = std::max(1, settings.psf_max_neighbors);
    const int block = psf_block_side(settings.psf_block_size);
    constexpr bool exact = W::kExact;
    const int window_x0 = scene.camera().window_x0(), window_y0 = scene.camera().window_y0();
    auto general_bsdf = [&](uint32_t j) {  // a technique's BSDF (for the General kind and the exact variant)
        const PathRecord& t = records[j];
        return bsdf_at(scene, t.material, t.ns, t.ng, t.backfacing, x1_attr(j), t.wo);
    };
    auto technique = [&](uint32_t j) { return BsdfTechnique(records[j].p, general_bsdf(j), records[j].wo); };
    // What a pixel adds to the film, and what it learnt about its own suffix's weight (own_weight < 0:
    // nothing to learn).
    auto finish = [&](int x, int y, size_t k, const Color& L, float reused, float own_weight, LocalCounters& local) {
        if (own_weight >= 0.0f) {
            b.own_weight_sum[k] += own_weight;
            ++b.own_weight_n[k];
        }
        if (ctx.film.has_aux()) add_aux_sample(ctx, x, y, s, b.passes[k], reused);
        ctx.film.add(x, y, guard_sample(L, local), records[k].transparency);
    };

    // PSF_PATH: the path tracer's own estimate, f cos / p_omega times the suffix radiance, averaged over
    // the pixel's own samples. Contributions are in the area measure at z1: divided by the density in
    // the same measure.
    auto path_estimate = [&](auto spectral_tag, size_t k) {
        constexpr bool kSpectral = decltype(spectral_tag)::value;
        const PathRecord& q = records[k];
        const int extra = b.extra_paths[k];
        const PrivateSuffix* private_suffixes = b.extras.data() + b.extra_offset[k];
        Bsdf bx = bsdf_at(scene, q.material, q.ns, q.ng, q.backfacing, x1_attr(k), q.wo);
        Color sum(0.0f);
        auto add = [&](const Connection& c, const Color& contribution) {
            float p_area = bx.pdf(q.wo, c.dir) * c.g;
            if (p_area > 0.0f) sum += contribution / p_area;
        };
        if (q.has_suffix) {
            Connection c = connect(q.p, q.z, q.z_ng);
            if constexpr (kSpectral) {
                float f[spectral::kMaxWavelengths];
                if (c.valid() && spectrum_->eval(q.material, bx, q.wo, c.dir, f))
                    add(c, spectrum_->combine(k, f, spectrum_->L_out(k)) * c.g);
            } else {
                if (c.valid()) add(c, bx.eval(q.wo, c.dir) * q.L_out * c.g);
            }
        }
        for (int m = 0; m < extra; ++m) {
            const PrivateSuffix& ps = private_suffixes[m];
            if (is_black(ps.contribution)) continue;
            Connection c = connect(q.p, ps.z, ps.z_ng);
            if (c.valid()) add(c, ps.contribution);
        }
        return q.beta * sum / float(1 + extra);
    };

    // The filtered estimates of a group: `members` (pixel indices, all with a vertex; pixel (mx[i],
    // my[i]) each) share the technique set drawn around the anchor members[0], whose pixel seeds the
    // random subset.
    // kSpectral (spectral_tag): the records carry their throughput and radiance per wavelength
    // (psf_spectral.h); the weights are the same.
    auto gather_group = [&](auto spectral_tag, const uint32_t* members, const int* mx, const int* my, int n_members,
                            LocalCounters& local) {
        constexpr bool kSpectral = decltype(spectral_tag)::value;
        GatherScratch& scratch = *gather_scratch();
        const PathRecord& anchor = records[members[0]];
        uint64_t visibility_rays = 0;  // the unbiased variant's shadow rays
        std::vector<uint32_t>& nb = scratch.nb;
        std::vector<uint32_t>& in_ball = scratch.in_ball;
        nb.assign(members, members + n_members);
        in_ball.clear();
        grid.query_ball(anchor.p, anchor.radius, in_ball);
        // Only prefixes of the anchor's Dirac depth (the members have it too): see "One Dirac depth per technique set".
        in_ball.erase(std::remove_if(in_ball.begin(), in_ball.end(),
                                     [&](uint32_t j) {
                                         return records[j].technique_class != anchor.technique_class ||
                                                std::find(members, members + n_members, j) != members + n_members;
                                     }),
                      in_ball.end());
        const size_t others = std::min(in_ball.size(), size_t(std::max(0, max_n - n_members)));
        if (others < in_ball.size()) {  // a partial Fisher-Yates shuffle
            Rng pick = pixel_sample_rng(mx[0] + window_x0, my[0] + window_y0, s, settings.seed ^ 0x5a5a5a5au);
            for (size_t i = 0; i < others; ++i) {
                size_t j = i + size_t((uint64_t(pick.next_u32()) * (in_ball.size() - i)) >> 32);
                std::swap(in_ball[i], in_ball[j]);
            }
        }
        nb.insert(nb.end(), in_ball.begin(), in_ball.begin() + others);

        // The set's densities, every technique counted once.
        std::vector<BsdfTechnique>& techniques = scratch.techniques;
        DensitySum& density_sum = scratch.density_sum;
        if constexpr (exact) {
            techniques.clear();
            for (uint32_t j : nb) techniques.push_back(technique(j));
        } else if constexpr (!W::kOwnDensityPerSample) {
            density_sum.reset();
            for (uint32_t j : nb) {
                if (models[j].kind == TechniqueDensity::General)
                    density_sum.add_general(records[j].p, general_bsdf(j), records[j].wo);
                else
                    density_sum.add(models[j]);
            }
        }
        // p(z | technique nb[jj]).
        auto density = [&](size_t jj, const Vec3& z, const Vec3& z_ng) {
            if constexpr (exact) return techniques[jj].area_density(z, z_ng);
            const uint32_t j = nb[jj];
            return models[j].kind == TechniqueDensity::General ? technique(j).area_density(z, z_ng)
                                                               : models[j].area_density(z, z_ng);
        };
        // sum_k p(z | ybar_k) over the set, for a sample of technique nb[sampled_by].
        //
        // The unbiased variant counts a technique only where it can produce the sample for the same
        // integrand, which eq. (15) needs of the weights (normalised over the techniques for every
        // suffix):
        //  * z visible from it: the visibility of z is tested from every technique but the one that
        //    sampled it (which reached z by a ray). `visible`, when given, receives the tests of the
        //    first n_members techniques (the group's pixels, which connect to z next; 1 visible,
        //    0 occluded, -1 not tested), so the connection does not trace them again.
        //  * x1 on the sampler's side of z's surface. The suffix's radiance towards another x1 is
        //    re-evaluated from the directions sampled at z. Its light sample serves either side (light
        //    sampling does not depend on wo, and its MIS weight is 1 where the sampler's BSDF has no
        //    density), but its BSDF sample covers only the sampler's side of a thin two-sided surface:
        //    seen from the other side, z's BSDF is 0 there, and the light reaching that side through
        //    z's BSDF is lost. The techniques of the other side are left out of the denominator and
        //    their pixels do not take the sample, so the weights stay normalised for both sides (each
        //    side's samples serve that side). Keeping the light-sample part for both sides (with a
        //    second denominator over both) would share more; not done.
        auto same_side = [](const Vec3& a, const Vec3& b, const Vec3& z, const Vec3& z_ng) {
            return (dot(a - z, z_ng) > 0.0f) == (dot(b - z, z_ng) > 0.0f);
        };
        // Whether an opaque surface blocks the connection from x1 (p, ng) to z. With media a boundary
        // without a surface shader does not: a technique's own ray passes it, so the technique can
        // produce z.
        auto connection_blocked = [&](const Vec3& p, const Vec3& ng, const Vec3& z) {
            const ShadowRay s = shadow_ray_between(p, ng, z);
            return media ? !connection_through_media(scene, s, kConnectionVisibility, kNoMedium, nullptr)
                         : scene.occluded(s.o, s.d, s.tmax, kShutterCentre, kConnectionVisibility);
        };
        // With media: the transmittance along member k's connection to z in direction dir (0 where blocked).
        auto connection_tr = [&](size_t k, const Vec3& z, const Vec3& dir) {
            const PathRecord& q = records[k];
            Color tr(0.0f);
            connection_through_media(scene, shadow_ray_between(q.p, q.ng, z), kConnectionVisibility,
                                     record_media[k].towards(q.ng, dir), &tr);
            return tr;
        };
        auto shared_denominator = [&](const Vec3& z, const Vec3& z_ng, size_t sampled_by, int8_t* visible) {
            if constexpr (!exact) return density_sum(z, z_ng);
            const Vec3& sampler = records[nb[sampled_by]].p;
            float denom = 0.0f;
            for (size_t jj = 0; jj < nb.size(); ++jj) {
                const PathRecord& t = records[nb[jj]];
                if (jj != sampled_by && !same_side(t.p, sampler, z, z_ng)) continue;
                float pj = techniques[jj].area_density(z, z_ng);
                if (pj > 0.0f && jj != sampled_by) {
                    const bool occluded = connection_blocked(t.p, t.ng, z);
                    ++visibility_rays;
                    if (occluded) pj = 0.0f;
                    if (visible && jj < size_t(n_members)) visible[jj] = occluded ? 0 : 1;
                }
                denom += pj;
            }
            return denom;
        };
        // Per sample, what does not depend on the pixel: eq. (17)'s shared denominator, or (Keller)
        // the sample's own density.
        std::vector<float>& per_sample = scratch.per_sample;
        per_sample.assign(nb.size(), 0.0f);
        // The unbiased variant's visibility of sample ii from member jj: visible[ii * n_members + jj].
        std::vector<int8_t>& visible = scratch.visible;
        if (exact) visible.assign(nb.size() * size_t(n_members), int8_t(-1));
        for (size_t ii = 0; ii < nb.size(); ++ii) {
            const PathRecord& smp = records[nb[ii]];
            if (!smp.has_suffix) continue;
            if constexpr (W::kOwnDensityPerSample)
                per_sample[ii] = density(ii, smp.z, smp.z_ng);
            else
                per_sample[ii] = shared_denominator(smp.z, smp.z_ng, ii,
                                                    exact ? visible.data() + ii * size_t(n_members) : nullptr);
        }
        groups += 1;
        grouped_pixels += uint64_t(n_members);

        for (int jj = 0; jj < n_members; ++jj) {  // member jj is nb[jj]
            const size_t k = members[jj];
            const PathRecord& q = records[k];
            const int extra = b.extra_paths[k];
            const PrivateSuffix* private_suffixes = b.extras.data() + b.extra_offset[k];
            const Bsdf own = bsdf_at(scene, q.material, q.ns, q.ng, q.backfacing, x1_attr(k), q.wo);
            gathered += nb.size();
            typename W::Pixel estimate(extra);
            for (size_t ii = 0; ii < nb.size(); ++ii) {
                const PathRecord& smp = records[nb[ii]];
                if (!estimate.take(q, smp, settings)) continue;
                if (!(per_sample[ii] > 0.0f)) continue;  // no suffix, or no density to divide by
                // Connection f_1(ybar_j, zbar_i) in the area measure at z1.
                const Connection c = connect(q.p, smp.z, smp.z_ng);
                if (!c.valid()) continue;
                Color f, L_z;
                // Spectral: f, L_z and the connection's transmittance per wavelength.
                float f_s[kSpectral ? spectral::kMaxWavelengths : 1], L_s[kSpectral ? spectral::kMaxWavelengths : 1];
                float tr_s[kSpectral ? spectral::kMaxWavelengths : 1];
                const float* L_own = nullptr;
                const float* tr = nullptr;
                if constexpr (kSpectral) {
                    if (!spectrum_->eval(q.material, own, q.wo, c.dir, f_s)) continue;
                    L_own = spectrum_->L_out(nb[ii]);
                } else {
                    f = own.eval(q.wo, c.dir);
                    if (is_black(f)) continue;
                    L_z = smp.L_out;
                }
                if constexpr (exact) {
                    // Visibility and z1's scattering for the new direction (§4.2). The own sample was
                    // reached by a ray; the others' visibility was traced for the denominator, unless
                    // this technique had no density there (then it is traced here).
                    if (ii != size_t(jj)) {
                        if (!same_side(q.p, smp.p, smp.z, smp.z_ng)) continue;  // see shared_denominator
                        int8_t& v = visible[ii * size_t(n_members) + size_t(jj)];
                        if (v < 0) {
                            v = connection_blocked(q.p, q.ng, smp.z) ? 0 : 1;
                            ++visibility_rays;
                        }
                        if (v == 0) continue;
                    }
                    Vec3 z_wo = -c.dir;
                    bool back = dot(z_wo, smp.z_ng) < 0.0f;
                    Vec3 zng = back ? -smp.z_ng : smp.z_ng;
                    Vec3 zns = back ? -smp.z_ns : smp.z_ns;
                    Bsdf bz = bsdf_at(scene, smp.z_material, zns, zng, back,
                                      attribs.empty() ? SurfaceAttribs{} : attribs[nb[ii]].z1, z_wo);
                    if (scene.has_subsurface()) bz.subsurface_as_diffuse();  // as its own path shaded z1
                    // With media, what arrives at x1: the own segment's transmittance, or the connection's.
                    if constexpr (kSpectral) {
                        spectrum_->reevaluate(nb[ii], bz, smp.z_material, z_wo, smp.nee_dir, smp.next_dir, L_s);
                        L_own = L_s;
                        if (media && ii == size_t(jj)) {
                            tr = spectrum_->suffix_tr(k);
                        } else if (media) {
                            if (!spectrum_->connection_tr(scene, shadow_ray_between(q.p, q.ng, smp.z), kConnectionVisibility,
                                                          record_media[k].towards(q.ng, c.dir), tr_s))
                                std::fill(tr_s, tr_s + spectrum_->count(), 0.0f);
                            tr = tr_s;
                        }
                    } else {
                        L_z = bz.eval(z_wo, smp.nee_dir) * smp.nee_weighted + bz.eval(z_wo, smp.next_dir) * smp.next_weighted;
                        if (media) L_z *= ii == size_t(jj) ? record_media[k].suffix_tr : connection_tr(k, smp.z, c.dir);
                    }
                }
                Color contribution;
                if constexpr (kSpectral) contribution = spectrum_->combine(k, f_s, L_own, tr) * c.g;
                else contribution = f * L_z * c.g;
                // (Past the visibility test above, the unbiased variant's own term needs no test of its own.)
                estimate.add_shared(contribution, per_sample[ii], ii == size_t(jj), nb.size(),
                                    [&] { return density(size_t(jj), smp.z, smp.z_ng); });
            }
            estimate.end_shared(q.has_suffix, nb.size());
            // The private extra suffixes, sampled by the own technique.
            for (int m = 0; m < extra; ++m) {
                const PrivateSuffix& ps = private_suffixes[m];
                estimate.add_private(ps.contribution, [&] { return density(size_t(jj), ps.z, ps.z_ng); },
                                     [&] { return shared_denominator(ps.z, ps.z_ng, size_t(jj), nullptr); });
            }
            if constexpr (W::kOwnDensityPerSample) accepted += estimate.accepted();
            // reused: other paths' suffixes combined here (the diagnostic pass)
            finish(mx[jj], my[jj], k, q.fixed + q.beta * estimate.estimate(), estimate.reused(nb.size()),
                   estimate.own_weight(), local);
        }
        visibility_rays_total += visibility_rays;
    };

    auto gather = [&](const uint32_t* members, const int* mx, const int* my, int n_members, LocalCounters& local) {
        if constexpr (W::kGathers) {
            if (spectrum_) gather_group(std::true_type{}, members, mx, my, n_members, local);
            else gather_group(std::false_type{}, members, mx, my, n_members, local);
        }
    };
    const uint64_t grid_hash = mix64((uint64_t(s) << 32) ^ uint64_t(settings.seed) ^ 0x6a09e667f3bcc909ull);
    const int offset_x = int(grid_hash % uint64_t(block)), offset_y = int((grid_hash >> 32) % uint64_t(block));
    auto starts_block = [&](int v, int offset) { return v % kTileSize == 0 || (v + block - offset) % block == 0; };
    auto block_end = [&](int v, int offset, int limit) {
        int e = v + 1;
        while (e < limit && !starts_block(e, offset)) ++e;
        return e;
    };
    for_each_pixel_in_tiles(ctx, [&](int x, int y, LocalCounters& local) {
        if (!starts_block(x, offset_x) || !starts_block(y, offset_y)) return;  // (x, y) starts a block
        // The block's pixels with a vertex within reach of the anchor form its group; the others are
        // gathered on their own.
        uint32_t members[kMaxBlock * kMaxBlock];
        int mx[kMaxBlock * kMaxBlock], my[kMaxBlock * kMaxBlock];
        int n_members = 0;
        const PathRecord* anchor = nullptr;
        const int x_end = block_end(x, offset_x, w), y_end = block_end(y, offset_y, h);
        for (int py = y; py < y_end; ++py)
            for (int px = x; px < x_end; ++px) {
                const size_t k = size_t(py) * w + px;
                const PathRecord& q = records[k];
                if (!q.has_vertex) {
                    finish(px, py, k, q.fixed, 0.0f, -1.0f, local);
                } else if (!W::kGathers || private_class(q.technique_class)) {
                    const Color own = spectrum_ ? path_estimate(std::true_type{}, k) : path_estimate(std::false_type{}, k);
                    finish(px, py, k, q.fixed + own, 0.0f, 1.0f, local);  // nothing is shared
                } else if (!anchor || (n_members < max_n && q.technique_class == anchor->technique_class &&
                                       length_sq(q.p - anchor->p) <= sqr(kGroupReach * anchor->radius))) {
                    if (!anchor) anchor = &q;
                    members[n_members] = uint32_t(k), mx[n_members] = px, my[n_members] = py;
                    ++n_members;
                } else {
                    const uint32_t single = uint32_t(k);
                    gather(&single, &px, &py, 1, local);
                }
            }
        if (n_members > 0) gather(members, mx, my, n_members, local);
    });
    gather_seconds_ += seconds_since(t0);
    iterations_++;
    stored_vertices_ += stored.size();
    gathered_ += gathered.load();
    groups_ += groups.load();
    grouped_pixels_ += grouped_pixels.load();
    visibility_rays_ += visibility_rays_total.load();
    accepted_ += accepted.load();
    extra_paths_ += extra_total;
    pixels_ += pixels;
    // The extra paths' per-pixel state and private suffixes are counted in, shared over the vertices.
    // (own_weight_sum, own_weight_n, extra_bsdf_taken, extra_offset, extra_paths per pixel)
    const double extra_bytes = double(pixels) * (sizeof(float) + 3 * sizeof(uint32_t) + sizeof(uint8_t)) +
                               double(extra_total) * sizeof(PrivateSuffix);
    bytes_per_vertex_ = sizeof(PathRecord) + sizeof(TechniqueDensity) + (spectrum_ ? spectrum_->bytes_per_record() : 0.0) +
                        (stored.empty() ? 0.0 : (double(grid.memory_bytes()) + extra_bytes) / stored.size());
}

std::map<std::string, double> PathSpaceFilteringIntegrator::stats() const {
    double it = iterations_ ? double(iterations_) : 1.0;
    return {
        {"iterations", double(iterations_)},
        {"stage1_seconds_per_iteration", stage1_seconds_ / it},
        {"grid_build_seconds_per_iteration", grid_seconds_ / it},
        {"gather_seconds_per_iteration", gather_seconds_ / it},
        {"stored_vertices_per_iteration", stored_vertices_ / it},
        // Every stored vertex queries the grid once.
        {"techniques_per_query", stored_vertices_ ? double(gathered_) / stored_vertices_ : 0.0},
        {"pixels_per_technique_set", groups_ ? double(grouped_pixels_) / double(groups_) : 0.0},
        {"visibility_rays_per_query", stored_vertices_ ? double(visibility_rays_) / stored_vertices_ : 0.0},
        {"keller_accepted_per_query", stored_vertices_ ? double(accepted_) / stored_vertices_ : 0.0},
        {"bytes_per_stored_vertex", bytes_per_vertex_},
        {"extra_paths_per_pixel", pixels_ ? double(extra_paths_) / double(pixels_) : 0.0},
        {"wavelengths_per_path", spectrum_ ? double(spectrum_->count()) : 0.0},
    };
}

}  // namespace smis
