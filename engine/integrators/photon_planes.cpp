// One iteration: a fresh set of photon planes (footnote 2 of the paper: one plane set serves every
// pixel), then one camera sample per pixel that runs the path tracer with the camera ray's single
// scattering from rectangular lights left out, and adds what the camera ray gathers from the planes
// it crosses inside scattering media, up to its first opaque surface.
//
// Estimator for one crossing (path y on the light, x on the camera ray), per plane of N drawn:
//   f / p = T_cam(x) sigma_s rho(x) Le pi A / (pmf_light N) * T(x, y) e^{rate |x - y|} * W,
// where Le pi / (cos / pi) is the emission over the cosine sampling of w_l, A / |s| the inverse density
// of the chord offset (p(v | alpha) = |s| / A, eq. 25), the free flight of the sweep survives to |x - y|
// with probability e^{-rate |x - y|} (rate: the smallest channel of sigma_t, so the true coloured
// transmittance T(x, y) of the shadow ray divided by it is at most 1 inside the light's medium) and
//   W = 1 / (|s| J)                         unweighted (eq. 22),       J = |(s_hat x w_l) . w_e|
//   W = 1 / (|s| (2/pi) sqrt(a^2 + b^2))    CMIS (eq. 26, p(alpha) = 1/pi already inside), a, b the
//                                           J of the light's u and v edges
//   W = n / (|s| sum_j J_j)                 SMIS, cosine-only densities (eq. 27)
//   W = n / (sum_j |s_j| J_j)               SMIS, exact densities (eq. 25, 27)
// with the SMIS orientations alpha_j = alpha + j pi / n: a random rotation of the stratified set that
// contains the realised alpha, each chord s_j through the path's actual light point y. Only the
// realised plane was sampled (one of the n techniques), hence the factor n.
//
// Point and spot lights without radius (README, "Planes from point and spot lights"): a plane
// through the light point y with a normal n uniform on the sphere, covering the disk of a free
// flight's radius around y. A camera ray x(t) = o + t d crosses it at one t; the density of that
// crossing over all normals is
//   p(t) = 1/(4 pi) \int_{S^2} |n.d| delta(n.(x(t) - y)) dn = |d x u| / (pi r),  r u = x(t) - y,
// (the normals of the planes through x(t) form the great circle orthogonal to u, on which |n.d|
// integrates to 4 |d x u|). It is every orientation's density at once, the continuous MIS that
// CMIS and SMIS approximate for rectangles (no chord length varies with the orientation), so every
// weighting uses it: per crossing, of N planes,
//   f / p = T_cam(x) sigma_s rho(x) I(u) falloff(u) / r^2 T(x, y) e^{rate r} pi r / (pmf_light N |d x u|).
#include "integrators/photon_planes.h"

#include "integrators/aux_passes.h"

#include <chrono>

#include <tbb/parallel_for.h>

#include "integrators/photon_plane_set.h"
#include "integrators/tiles.h"
#include "integrators/volume.h"

namespace smis {
namespace {

using Clock = StageClock;

struct PlaneLights {
    std::vector<PlaneLight> lights;
    DiscreteDistribution selection;  // proportional to power
};

// How far a plane must sweep from its light: to every point where light can scatter. The farthest
// point of the scattering volumes' box from the light's rectangle (or point) is a pair of corners
// (both are convex). A World volume that scatters reaches everywhere: the sweep is bounded only by its free
// flight (the integrator divides by its survival), unless that has no rate; then the sweep covers the
// geometry and the camera, the most a finite plane can. (It was the geometry's bounding sphere around
// the light's centre: single scattering near a camera outside it, or in a World volume beyond it, was
// missed, and light points off the centre fell short of the sphere's far side.)
float sweep_reach(const Scene& scene, const Vec3* light_points, int count, float flight_rate) {
    const Scene::ScatteringRegion& region = scene.scattering_region();
    if (region.everywhere && flight_rate > 0.0f) return kInf;
    Vec3 lo = region.lo, hi = region.hi;
    if (region.everywhere) {
        const Vec3 reach(scene.radius());
        lo = vmin(scene.center() - reach, scene.camera().origin());
        hi = vmax(scene.center() + reach, scene.camera().origin());
    }
    if (!(lo.x <= hi.x)) return 0.0f;  // nothing scatters
    float farthest = 0.0f;
    for (int l = 0; l < count; ++l)
        for (int c = 0; c < 8; ++c) {
            const Vec3 x(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
            farthest = std::max(farthest, length(x - light_points[l]));
        }
    return farthest;
}

PlaneLights collect_plane_lights(const Scene& scene) {
    PlaneLights out;
    std::vector<float> power;
    auto flight_rate = [&](const Vec3& p) {
        int32_t m = scene.has_media() ? scene.medium_at(p) : kNoMedium;
        return m >= 0 ? min_component(scene.medium(m).sigma_t()) : 0.0f;
    };
    for (uint32_t i = 0; i < scene.lights().size(); ++i) {
        // A light hidden from Volume Scatter rays lights no medium (single_scattering skips it too).
        if (!(scene.light(i).visibility & kRayVolumeScatter)) continue;
        LightRectangle r;
        PlaneLight pl;
        pl.light = i;
        if (scene.light(i).point(&pl.emitter)) {
            pl.point = true;
            // A spot's planes only where they cut its cone (sample_point_photon_plane).
            if (pl.emitter.spot && pl.emitter.cos_half > 0.0f)
                pl.normal_band = std::sqrt(1.0f - pl.emitter.cos_half * pl.emitter.cos_half);
            pl.flight_rate = flight_rate(pl.emitter.position);
            pl.max_length = sweep_reach(scene, &pl.emitter.position, 1, pl.flight_rate);
        } else if (scene.light(i).rectangle(&r)) {
            pl.corner = r.corner;
            pl.width = length(r.u);
            pl.height = length(r.v);
            pl.u_hat = r.u / pl.width;
            pl.v_hat = r.v / pl.height;
            pl.normal = r.normal;
            pl.radiance = r.radiance;
            pl.area = pl.width * pl.height;
            pl.flight_rate = flight_rate(r.corner + (r.u + r.v) * 0.5f);
            const Vec3 corners[4] = {r.corner, r.corner + r.u, r.corner + r.v, r.corner + r.u + r.v};
            pl.max_length = sweep_reach(scene, corners, 4, pl.flight_rate);
        } else {
            continue;
        }
        out.lights.push_back(pl);
        power.push_back(scene.light(i).power(scene.radius()));
    }
    // Planes per light: half by power, half shared equally among the lights that emit. By power
    // alone a dim light that lights a large part of the fog (volume_spot's fill light beside a
    // 40x brighter spot, 12 planes of 512) drew too few planes to cover it: streaks and empty
    // regions wherever it is the only light. The pmf is in the estimator's scale: unbiased.
    double total = 0.0;
    int emitting = 0;
    for (float p : power)
        if (p > 0.0f && std::isfinite(p)) total += p, ++emitting;
    for (float& p : power)
        p = p > 0.0f && std::isfinite(p) ? float(0.5 * p / total + 0.5 / emitting) : 0.0f;
    out.selection = DiscreteDistribution(power);
    return out;
}

// W of a point light's plane crossed at distance r from the light in direction u (the header's
// point-light estimator without T_cam sigma_s rho, the shadow ray's T and the flight survival):
// I falloff(u) pi band / (r |d x u|); the plane scale holds I / (pmf N). A spot's normals cover the
// fraction `band` of the sphere, and for u inside its cone the whole great circle of normals
// orthogonal to u lies in that band, so the crossing density is the header's p(t) / band.
float point_plane_weight(const PlaneLight& l, const Vec3& u, float r, const Vec3& d) {
    return l.emitter.falloff(u) * kPi * l.normal_band / (r * length(cross(d, u)));
}

// The estimator's weighting with what it needs precomputed: the rotation by pi / n between the SMIS
// orientations, so a crossing costs no trigonometry (the second plane "only computes a weight").
struct PlaneWeights {
    PlaneWeighting weighting;
    int n;
    float rot_c, rot_s;  // cos, sin of pi / n
    PlaneWeights(PlaneWeighting w, int n_) : weighting(w), n(n_), rot_c(std::cos(kPi / n_)), rot_s(std::sin(kPi / n_)) {}

    // W of the header comment for one crossing of plane p by direction d.
    float operator()(const PlaneLight& l, const PhotonPlane& p, const PlaneHit& h, const Vec3& d) const {
        // J(alpha') = |cos(alpha') a + sin(alpha') b| for every orientation of a chord swept along w_l.
        float a = dot(cross(l.u_hat, p.w_l), d), b = dot(cross(l.v_hat, p.w_l), d);
        switch (weighting) {
            case PlaneWeighting::Unweighted:
                return 1.0f / (p.chord_length * std::fabs(p.cos_alpha * a + p.sin_alpha * b));
            case PlaneWeighting::Cmis:
                return 1.0f / (p.chord_length * (2.0f / kPi) * std::sqrt(a * a + b * b));
            case PlaneWeighting::SmisCos:
            case PlaneWeighting::SmisExact: {
                const bool exact = weighting == PlaneWeighting::SmisExact;
                // The path's light point y in 2D light coordinates (on the realised chord).
                float yx = p.x1 + h.a * p.chord_length * p.cos_alpha, yy = p.y1 + h.a * p.chord_length * p.sin_alpha;
                float cj = p.cos_alpha, sj = p.sin_alpha;
                float sum = std::fabs(cj * a + sj * b) * (exact ? p.chord_length : 1.0f);
                if (n == 2) {  // the perpendicular partner (-sin, cos): its inverses are known already
                    float J1 = std::fabs(-sj * a + cj * b);
                    sum += exact ? J1 * chord_through(yx, yy, l.width, l.height, -sj, cj, -p.inv_sin_alpha,
                                                      p.inv_cos_alpha).length()
                                 : J1;
                }
                for (int j = 1; n > 2 && j < n; ++j) {
                    float c_next = cj * rot_c - sj * rot_s;
                    sj = sj * rot_c + cj * rot_s;
                    cj = c_next;
                    float Jj = std::fabs(cj * a + sj * b);
                    sum += exact ? Jj * chord_through(yx, yy, l.width, l.height, cj, sj).length() : Jj;
                }
                return float(n) / (exact ? sum : p.chord_length * sum);
            }
        }
        return 0.0f;
    }
};

// What gathering along camera rays counted (the integrator's statistics).
struct GatherCounts {
    uint64_t parallel = 0, nonfinite = 0, gathered = 0, shadow_rays = 0;
};

// One iteration's plane set with what its estimator needs.
struct PlaneGather {
    const Scene& scene;
    const PhotonPlaneSet& set;
    const PlaneLights& lights;
    const PlaneWeights& weight;
    const std::vector<Color>& scale;  // Le pi A / (pmf N) per rectangle, I / (pmf N) per point light
    uint32_t shadow_ray_budget;       // RenderSettings::plane_shadow_rays

    // The single scattering from the planes' lights along a camera ray that starts in `medium`, up
    // to its first opaque surface: the header's estimator summed over the ray's crossings.
    // Segments whose bit in `segments` is clear are the path tracer's (RayMedia::plane_segments).
    // On those, the crossings of plane lights whose bit (scene light index) is set in keep[i] are
    // skipped too (the per-light partition left them to the path tracer; keep may be null).
    // `traced`: the ray's media as intersect_through(scene, ray, medium) gives them, when the path
    // sample has just traced this camera ray (LocalCounters::camera_media); null: traced here.
    Color operator()(const Ray& ray, int32_t medium, const RayMedia* traced, uint8_t segments, const uint32_t* keep,
                     Rng& rng, GatherCounts* n) const {
        thread_local std::vector<PlaneHit> hits;
        Color L(0.0f);
        RayMedia own;
        if (!traced) {
            SurfaceHit first;
            intersect_through(scene, ray, medium, &first, &own);
        }
        const RayMedia& media = traced ? *traced : own;
        for (int i = 0; i < media.count; ++i) {
            const RayMedia::Segment& seg = media.seg[i];
            const Medium& med = scene.medium(seg.medium);
            if (!med.scatters() || !(segments >> i & 1u)) continue;
            set.gather(Ray{ray.o, ray.d, seg.t0, seg.t1, ray.time}, &hits, &n->parallel);
            if (keep && keep[i])
                hits.erase(std::remove_if(hits.begin(), hits.end(),
                                          [&](const PlaneHit& h) {
                                              return keep[i] >> lights.lights[set.plane(h.plane).light].light & 1u;
                                          }),
                           hits.end());
            n->gathered += hits.size();
            // Each crossing's contribution before its shadow ray's transmittance: T_cam sigma_s
            // and the plane's weight, kept apart so that the traced crossing's product is formed
            // in the order it had before the roulette existed.
            struct Unshadowed {
                Color cam;
                float weight;
                float size;       // the contribution's largest channel
                Vec3 from_light;  // the photon's direction at x
                float dist;       // |x - y|
            };
            thread_local std::vector<Unshadowed> unshadowed;
            unshadowed.resize(hits.size());
            float total = 0.0f;
            for (size_t k = 0; k < hits.size(); ++k) {
                const PlaneHit& hit = hits[k];
                const PhotonPlane& p = set.plane(hit.plane);
                const PlaneLight& l = lights.lights[p.light];
                Unshadowed& u = unshadowed[k];
                u.cam = media.transmittance(scene, hit.t) * med.sigma_s;
                if (l.point) {
                    const Vec3 w = ray.o + ray.d * hit.t - l.emitter.position;
                    u.dist = length(w);
                    u.from_light = w / u.dist;
                    // Outside the disk the free flight reached (the quad's corners): no photon there.
                    u.weight = u.dist <= p.reach ? point_plane_weight(l, u.from_light, u.dist, ray.d) : 0.0f;
                } else {
                    u.dist = hit.b * p.sweep_length;
                    u.from_light = p.w_l;
                    u.weight = weight(l, p, hit, ray.d);
                }
                u.weight *= med.phase.eval(-ray.d, -u.from_light) * std::exp(l.flight_rate * u.dist);
                u.size = max_component(u.cam * scale[p.light] * u.weight);
                if (!std::isfinite(u.size)) {
                    ++n->nonfinite;
                    u.size = 0.0f;
                }
                total += u.size;
            }
            const float budget = float(shadow_ray_budget);
            for (size_t k = 0; k < hits.size(); ++k) {
                const Unshadowed& u = unshadowed[k];
                if (!(u.size > 0.0f)) continue;
                float q = 1.0f;
                if (budget > 0.0f) {  // Russian roulette on visibility, by the unshadowed contribution
                    q = std::min(1.0f, budget * u.size / total);
                    if (!(rng.next_float() < q)) continue;
                }
                const PlaneHit& hit = hits[k];
                const PhotonPlane& p = set.plane(hit.plane);
                Vec3 xs = ray.o + ray.d * hit.t;
                Color tr = shadow_transmittance(scene, xs, -u.from_light, u.dist * (1.0f - 1e-4f), seg.medium);
                ++n->shadow_rays;
                if (is_black(tr)) continue;
                Color c = u.cam * tr * scale[p.light] * u.weight;
                if (!is_finite(c)) {
                    ++n->nonfinite;
                    continue;
                }
                L += q < 1.0f ? c / q : c;
            }
        }
        return L;
    }
};

// fn(segment index, crossings) for each scattering media segment of window pixel (x, y)'s sample-0
// camera ray: the crossings of `set` there (a fixed ray per pixel, the same whatever the thread count).
template <class Fn>
void crossings_per_segment(const RenderContext& ctx, const PhotonPlaneSet& set, int x, int y, Fn&& fn) {
    thread_local std::vector<PlaneHit> hits;
    uint64_t parallel = 0;
    const Ray ray = camera_ray(ctx, x, y, 0);
    SurfaceHit first;
    RayMedia media;
    intersect_through(ctx.scene, ray, ctx.scene.camera_medium(), &first, &media);
    for (int k = 0; k < media.count; ++k) {
        if (!ctx.scene.medium(media.seg[k].medium).scatters()) continue;
        set.gather(Ray{ray.o, ray.d, media.seg[k].t0, media.seg[k].t1, ray.time}, &hits, &parallel);
        fn(k, hits);
    }
}

// The camera ray crossings a plane set gives per pixel, estimated on a grid of pixel centres (a
// fixed sample of the image, so that the choice it feeds is the same whatever the thread count).
// Segments the path tracer takes (the partition) are left out, and so are the crossings of lights
// the per-light partition left to it (`keep`, RayMedia::plane_keep per pixel, or empty): the gather
// skips them.
double crossings_per_camera_ray(const RenderContext& ctx, const PhotonPlaneSet& set, const std::vector<PlaneLight>& lights,
                                const std::vector<uint8_t>& plane_segments, const std::vector<uint32_t>& keep) {
    constexpr int kGrid = 16;
    const int w = ctx.film.width(), h = ctx.film.height();
    uint64_t crossings = 0;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            const int x = (2 * i + 1) * w / (2 * kGrid), y = (2 * j + 1) * h / (2 * kGrid);
            const uint8_t mask = plane_segments.empty() ? 0xff : plane_segments[size_t(y) * w + x];
            const uint32_t* kept = keep.empty() ? nullptr : &keep[(size_t(y) * w + x) * RayMedia::kMaxSegments];
            crossings_per_segment(ctx, set, x, y, [&](int k, const std::vector<PlaneHit>& hits) {
                if (!(mask >> k & 1u)) return;
                for (const PlaneHit& hit : hits)
                    crossings += !(kept && kept[k] >> lights[set.plane(hit.plane).light].light & 1u);
            });
        }
    return double(crossings) / (kGrid * kGrid);
}

// n planes from `lights` with the numbers of `sequence` (rectangles: Fig. 10b; point lights: a
// uniform normal), each light chosen by its pmf.
std::vector<PhotonPlane> draw_planes(const PlaneLights& lights, uint32_t n, PlaneSequence& sequence) {
    std::vector<uint32_t> per_light(lights.lights.size(), 0);
    std::vector<PhotonPlane> planes;
    planes.reserve(n);
    for (uint32_t i = 0; i < n; ++i) {
        uint32_t li = static_cast<uint32_t>(lights.selection.sample(sequence.light_u(i)));
        const PlaneLight& l = lights.lights[li];
        const PlaneUniforms u = sequence.plane(li, per_light[li]++, l.point);
        PhotonPlane p = l.point ? sample_point_photon_plane(l, li, u) : sample_photon_plane(l, li, u);
        if (p.chord_length > 0.0f && p.sweep_length > 0.0f) planes.push_back(p);
    }
    return planes;
}

}  // namespace

// The segment partition. Crossing counts scale with a segment's length and the planes' density
// there: short fog segments (the floor's edge, thin fog in front of a surface) and regions few
// planes reach get 0-2 crossings per plane set, so their pixels are mostly exactly 0 with rare
// bright crossings (SMAPE), where the path tracer's single scattering (equiangular sampling towards
// the light, one shadow ray) is never 0. Here each pixel's camera-ray segments are split once per
// render: a pilot plane set (the iterations' distribution, its own stream, so independent of every
// iteration's set and path samples) is gathered along the pixel's sample-0 camera ray, the counts
// per segment index are averaged over the pilot pixels near it (5x5 pixels at plane_pilot_stride 1,
// below; an estimate of the expected count), and segment indices below plane_min_crossings go to
// the path tracer. Every camera ray of the pixel then uses
// that split: its segment i is estimated by the planes or by the path tracer's single scattering
// for the plane lights, never both and never neither (a fixed partition of the integral over
// camera rays and segments), so the sum stays unbiased whatever the pilot drew.
//
// The per-light partition (plane_min_light_crossings) refines it: on a segment the planes keep, a
// plane light that the pilot crosses there on average fewer times than that, but at all, is left
// to the path tracer (RayMedia::plane_keep; the media light choice then includes it there). A
// dim light whose few planes streak across the fog another light's planes fill (volume_spot's fill
// light beside the spot's cone) thus stops streaking there. Still a fixed partition, now of the
// (segment, light) pairs: unbiased.
//
// The pilot is part of the first iteration's fixed cost (at 5 s on volume_spot the first iteration is
// all a budget completes, and the path part's samples, all that dark fog and surfaces get, are what
// is left after it). With plane_pilot_stride s > 1 it gathers along every s-th pixel in x and y only
// (1/s^2 of the cost) and each pixel averages the pilot pixels within 2s - 1 of it. A segment index
// that no pilot pixel of the window has goes to the path tracer (so that a pixel none of whose
// segments are the planes' can skip its gather: gathers()). The partition stays a fixed one of the
// (segment, light) pairs of every camera ray, chosen before and independently of the iterations.
void PhotonPlanesIntegrator::partition_segments(const RenderContext& ctx, const PhotonPlaneSet& pilot,
                                                const std::vector<PlaneLight>& lights) {
    constexpr int kSeg = RayMedia::kMaxSegments;
    const int w = ctx.film.width(), h = ctx.film.height();
    const int stride = std::max(1, int(ctx.settings.plane_pilot_stride));
    const int radius = stride == 1 ? 2 : 2 * stride - 1;
    // Per light only where a light mask fits the media light choice (MediaLightChoice::Segment).
    const size_t nl = lights.size();
    const bool per_light = ctx.settings.plane_min_light_crossings > 0.0f && nl > 1 &&
                           ctx.scene.lights().size() <= size_t(MediaLightChoice::kMaxSegmentLights);
    std::vector<float> counts(size_t(w) * h * kSeg, -1.0f);  // -1: no scattering segment there (or no pilot)
    std::vector<uint8_t> light_counts(per_light ? size_t(w) * h * kSeg * nl : 0, 0);  // clamped at 255
    tbb::parallel_for(0, (h + stride - 1) / stride, [&](int row) {
        const int y = row * stride;
        for (int x = 0; x < w; x += stride)
            crossings_per_segment(ctx, pilot, x, y, [&](int k, const std::vector<PlaneHit>& hits) {
                const size_t at = (size_t(y) * w + x) * kSeg + k;
                counts[at] = float(hits.size());
                if (!per_light) return;
                uint8_t* c = &light_counts[at * nl];
                for (const PlaneHit& hit : hits) {
                    uint8_t& n = c[pilot.plane(hit.plane).light];
                    if (n < 255) ++n;
                }
            });
    });
    plane_segments_.assign(size_t(w) * h, 0xff);
    if (per_light) plane_keep_.assign(size_t(w) * h * kSeg, 0u);
    const float k_min = ctx.settings.plane_min_crossings, k_light = ctx.settings.plane_min_light_crossings;
    std::atomic<uint64_t> pilot_segments{0}, path_segments{0}, path_segment_lights{0};
    // Window sums per segment index, separable (running sums of integers: exact in doubles, so the
    // same whatever the order): channel 0 the crossings, 1 the pilot rays, 2 + l light l's crossings.
    const size_t nc = 2 + (per_light ? nl : 0);
    std::vector<double> rows(size_t(w) * h * nc), box(size_t(w) * h * nc);
    for (int k = 0; k < kSeg; ++k) {
        const auto value = [&](int x, int y, size_t c) -> double {
            const size_t at = (size_t(y) * w + x) * kSeg + k;
            const float n = counts[at];
            if (!(n >= 0.0f)) return 0.0;
            return c == 0 ? double(n) : c == 1 ? 1.0 : double(light_counts[at * nl + (c - 2)]);
        };
        tbb::parallel_for(0, h, [&](int y) {
            for (size_t c = 0; c < nc; ++c) {
                double run = 0.0;
                for (int i = 0; i < std::min(w, radius); ++i) run += value(i, y, c);
                for (int x = 0; x < w; ++x) {
                    if (x + radius < w) run += value(x + radius, y, c);
                    if (x - radius - 1 >= 0) run -= value(x - radius - 1, y, c);
                    rows[(size_t(y) * w + x) * nc + c] = run;
                }
            }
        });
        tbb::parallel_for(0, w, [&](int x) {
            for (size_t c = 0; c < nc; ++c) {
                double run = 0.0;
                for (int j = 0; j < std::min(h, radius); ++j) run += rows[(size_t(j) * w + x) * nc + c];
                for (int y = 0; y < h; ++y) {
                    if (y + radius < h) run += rows[(size_t(y + radius) * w + x) * nc + c];
                    if (y - radius - 1 >= 0) run -= rows[(size_t(y - radius - 1) * w + x) * nc + c];
                    box[(size_t(y) * w + x) * nc + c] = run;
                }
            }
        });
        tbb::parallel_for(0, h, [&](int y) {
            uint64_t n_pilot = 0, n_path = 0, n_lights = 0;
            for (int x = 0; x < w; ++x) {
                // Every pixel has its own pilot ray at stride 1: a segment index it lacks keeps its bit.
                if (stride == 1 && counts[(size_t(y) * w + x) * kSeg + k] < 0.0f) continue;
                const double* b = &box[(size_t(y) * w + x) * nc];
                const double sum = b[0], n = b[1];
                if (n == 0.0 || sum < double(k_min) * n) {  // n = 0 (stride > 1): no pilot ray of the window has it
                    plane_segments_[size_t(y) * w + x] &= uint8_t(~(1u << k));
                    if (n > 0.0) ++n_pilot, ++n_path;
                    continue;
                }
                ++n_pilot;
                for (size_t l = 0; per_light && l < nl; ++l)
                    if (b[2 + l] > 0.0 && b[2 + l] < double(k_light) * n) {
                        plane_keep_[(size_t(y) * w + x) * kSeg + k] |= 1u << lights[l].light;
                        ++n_lights;
                    }
            }
            pilot_segments += n_pilot, path_segments += n_path, path_segment_lights += n_lights;
        });
    }
    pilot_segments_ += pilot_segments.load();
    path_segments_ += path_segments.load();
    path_segment_lights_ += path_segment_lights.load();
}

// Whether window pixel i's gather can give anything but 0: some segment index is the planes' and
// not every plane light there is left to the path tracer (`lights`: the plane lights' bits, scene
// light indices). Skipping the gather where it cannot saves tracing its camera ray once more.
bool PhotonPlanesIntegrator::gathers(size_t i, uint32_t lights) const {
    if (plane_segments_.empty()) return true;
    const uint8_t bits = plane_segments_[i];
    for (int k = 0; k < RayMedia::kMaxSegments; ++k)
        if ((bits >> k & 1u) && (plane_keep_.empty() || (plane_keep_[i * RayMedia::kMaxSegments + k] & lights) != lights))
            return true;
    return false;
}

double PhotonPlanesIntegrator::gather_cost(const RenderContext& ctx, const PhotonPlaneSet& set,
                                          const std::vector<PlaneLight>& lights) {
    if (gather_cost_ < 0.0) {
        // A crossing counted on the grid (its weight, transmittance and shadow ray, and its share
        // of the camera ray's traversal) costs about plane_crossing_cost path samples. Measured per
        // iteration at 512x384 with the thread-time statistics below (path_thread_seconds,
        // gather_thread_seconds): 0.2 on volume_spot (gathering 23 us per camera ray for about 30
        // grid crossings, a path sample 3.9 us), 0.28 on volume_planes (12.7 us for about 6, a path
        // sample 7.4 us). It was 0.5 (from volume_planes at 96x96 and 40,960 planes): on volume_spot
        // that gave M = 15, the path samples took 72% of an iteration, and an iteration so long
        // (8.7 s) that a 15 s budget completed one and discarded the second (SMAPE 0.244; M = 6:
        // two iterations, 0.203, the same relMSE; volume_planes M = 3: 0.210, M = 1: 0.178, relMSE
        // 0.182 and 0.180). M gives the two parts about equal time.
        // An iteration also costs what does not scale with the crossings (the camera ray's walk
        // through the planes' BVH, the plane set's build; the ray's trace through the scene is shared
        // with its first path sample since planes6): about kIterationCost
        // path samples. Without it, once the per-light partition left volume_planes 1.7 gathered
        // crossings per camera ray, M fell to 1 and every path sample paid a whole iteration: at 15 s,
        // 3 seeds, load 8-12, M = 4 gave planes / PATH 1.05 / 0.81 (SMAPE / relMSE) where M = 1 gave
        // 1.23 / 1.12 (docs/bench/planes3_m4.md); on volume_spot (about 26 crossings) it gives M = 8,
        // near the optimum 9 of the error model A + B / M measured there (docs/bench/planes3.md).
        // The crossing cost is RenderSettings::plane_crossing_cost (0.2 by default).
        constexpr double kIterationCost = 3.0;
        gather_cost_ = crossings_per_camera_ray(ctx, set, lights, plane_segments_, plane_keep_) *
                           double(ctx.settings.plane_crossing_cost) +
                       kIterationCost;
    }
    return gather_cost_;
}

uint32_t PhotonPlanesIntegrator::surface_samples(const RenderContext& ctx, const PhotonPlaneSet& set,
                                                  const std::vector<PlaneLight>& lights) {
    if (ctx.settings.plane_surface_samples > 0)
        surface_samples_ = ctx.settings.plane_surface_samples;
    else if (surface_samples_ == 0)
        surface_samples_ = uint32_t(std::clamp(std::lround(gather_cost(ctx, set, lights)), 1l, 64l));
    return surface_samples_;
}

// A pixel that gathers no planes (gathers()) pays per pass its path sample only, a gathering pixel
// its path sample and, once per iteration, the gather: about M + G path samples an iteration against
// M. With K = round(1 + G / M) path samples per pass the former get about as many path samples per
// unit time as the path tracer alone would give them (K = 2 where M is chosen, M being about G).
// On volume_spot and volume_planes (512x384) 53% and 58% of the pixels gather nothing (the dim fog
// outside the spot's cone among them): with one sample per pass they lost SMAPE to PATH at equal
// time by the samples the gathering pixels' cost took from them (docs/bench/planes4_where.md).
// K depends only on the pilot's partition and the first plane set's crossings on a fixed grid,
// both fixed before any path sample: each pixel's value stays the mean of its film samples.
// Not the default (plane_path_pixel_samples 1): at equal instructions (one plane set, 512x384,
// random pattern, 3 seeds) K = 2, M = 8 against K = 1, M = 12 lowered volume_spot's SMAPE 4%
// (relMSE +2%; M = 10 against 16: -2%, +7%), but K = 2, M = 3 against K = 1, M = 5 raised
// volume_planes' SMAPE 3% and relMSE 15%: the gathering pixels' path samples are worth more than
// the others' extra ones (docs/bench/planes5_where.md).
uint32_t PhotonPlanesIntegrator::path_pixel_samples(const RenderContext& ctx, const PhotonPlaneSet& set,
                                                     const std::vector<PlaneLight>& lights, uint32_t M) {
    if (path_pixel_samples_ == 0) {
        if (ctx.settings.plane_path_pixel_samples > 0)
            path_pixel_samples_ = ctx.settings.plane_path_pixel_samples;
        else
            path_pixel_samples_ = uint32_t(std::clamp(std::lround(1.0 + gather_cost(ctx, set, lights) / M), 1l, 16l));
    }
    return path_pixel_samples_;
}

void PhotonPlanesIntegrator::iteration(RenderContext& ctx, uint32_t s) {
    const Scene& scene = ctx.scene;
    const RenderSettings& settings = ctx.settings;
    const int w = ctx.film.width(), h = ctx.film.height();
    const PlaneWeights plane_weight(weighting_, std::max(1, settings.smis_planes));

    // The plane set of this iteration, from its own stream (independent of the pixels' streams).
    auto t0 = Clock::now();
    if (s == 0) first_iteration_start_ = t0;
    const PlaneLights lights = collect_plane_lights(scene);
    const bool use_planes = scene.has_media() && !lights.lights.empty() && settings.photon_planes > 0;
    std::vector<PhotonPlane> planes;
    std::vector<Color> plane_scale;  // Le pi A / (pmf N) per rectangle, I / (pmf N) per point light
    if (use_planes) {
        if ((settings.plane_min_crossings > 0.0f || settings.plane_min_light_crossings > 0.0f) &&
            plane_segments_.empty()) {
            PlaneSequence pilot(mix64(0x70696c6f74ull ^ settings.seed), 0, settings.plane_stratified);
            partition_segments(ctx, PhotonPlaneSet(scene.device(), draw_planes(lights, settings.photon_planes, pilot)),
                               lights.lights);
        }
        PlaneSequence sequence(mix64(0x706c616e6573ull ^ settings.seed), s, settings.plane_stratified);
        planes = draw_planes(lights, settings.photon_planes, sequence);
        for (uint32_t li = 0; li < lights.lights.size(); ++li) {
            const PlaneLight& l = lights.lights[li];
            const float pmf_n = lights.selection.pmf(li) * float(settings.photon_planes);
            const Color emitted = l.point ? l.emitter.intensity : l.radiance * (kPi * l.area);
            plane_scale.push_back(pmf_n > 0.0f ? emitted / pmf_n : Color(0.0f));
        }
    }
    PhotonPlaneSet set(scene.device(), std::move(planes));
    build_seconds_ += seconds_since(t0);
    const PlaneGather gather{scene, set, lights, plane_weight, plane_scale, settings.plane_shadow_rays};
    const uint32_t M = use_planes && !settings.camera_volume_only ? surface_samples(ctx, set, lights.lights) : 1;
    uint32_t plane_light_bits = 0;  // the plane lights as plane_keep_ marks them (scene light indices)
    if (!plane_keep_.empty())
        for (const PlaneLight& l : lights.lights) plane_light_bits |= 1u << l.light;
    // Path samples per pass of a pixel that gathers nothing (path_pixel_samples); only the partition skips gathers.
    const uint32_t K = use_planes && !settings.camera_volume_only && !plane_segments_.empty()
                           ? path_pixel_samples(ctx, set, lights.lights, M)
                           : 1;

    // M passes over the image, one path sample per pixel each (pixel samples s M ... s M + M - 1),
    // for all but the planes' part; the first pass's camera ray also gathers the planes. Every path
    // sample reaches the film at once with its plane set's estimate added (not divided by M):
    //   film sample j of the pixel = path_j + planes(iteration of j),
    // so the pixel's value, the mean of its film samples, is the mean of all its path samples plus
    // the planes' estimates weighted by the path samples each got: unbiased however many passes of
    // an iteration the time limit let finish (the weights depend on the time only). A time limit
    // thus stops between passes, or between tiles of one, and keeps every finished path sample (it
    // discarded the whole unfinished iteration: 40% of a 15 s budget on volume_spot). With M whole
    // passes the pixel's value is the old one, the iteration's M path samples averaged plus planes.
    t0 = Clock::now();
    std::vector<Color> planes_at(size_t(w) * h, Color(0.0f));  // this iteration's planes per pixel
    std::atomic<uint64_t> path_ns{0}, gather_ns{0};  // thread time of the path samples and the gathering
    uint32_t finished = 0;
    // The session's first pass (iteration 0) ignores the time limit so that a short limit still
    // gives an image (session.cpp); that needs only this iteration's first pass: the later ones obey
    // the limit, counted from the first iteration's start (the session's start but for the set-up
    // of its render loop), so that the first iteration of M passes does not overrun the budget.
    RenderContext later = ctx;
    if (ctx.settings.time_limit > 0.0 && ctx.deadline == std::chrono::steady_clock::time_point::max())
        later.deadline = first_iteration_start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                      std::chrono::duration<double>(ctx.settings.time_limit));
    // should_stop() never turns false again: once a pass was cut short no later pass runs, so
    // passes 1.. only visit pixels whose gather pass finished.
    for (uint32_t m = 0; m < M && !(m == 0 ? ctx : later).should_stop(); ++m) {
        RenderContext& pass = m == 0 ? ctx : later;
        for_each_pixel_in_tiles(pass, [&](int x, int y, LocalCounters& local) {
            const size_t i = size_t(y) * w + x;
            // The camera path's first vertex asks the sample's Sampler for its numbers by name (path_loop.h).
            const PixelCamera pixel(ctx, x, y);
            const bool gathering = use_planes && gathers(i, plane_light_bits);
            if (m == 0 && use_planes && !gathering) ++gathers_skipped_;
            // A pixel that gathers nothing takes K path samples per pass: its pixel samples are
            // (s M + m) K ... (s M + m) K + K - 1, so that its samples are still 0, 1, 2, ... in order.
            const uint32_t k_samples = use_planes && !gathering ? K : 1;
            const uint32_t* keep = plane_keep_.empty() ? nullptr : &plane_keep_[i * RayMedia::kMaxSegments];
            for (uint32_t k = 0; k < k_samples; ++k) {
                const uint32_t index = (s * M + m) * k_samples + k;
                Sampler sampler;
                Ray ray = pixel.ray(index, &sampler);
                Rng& rng = sampler.rng();
                local.sample_transparency = 0.0f;
                PathState camera = camera_path_state(ray.o);
                camera.medium = scene.camera_medium();
                camera.planes_on_camera_ray = use_planes;
                if (!plane_segments_.empty()) camera.plane_segments = plane_segments_[i];
                camera.plane_keep = keep;
                // The auxiliary passes (when on) as the camera path of the passes' sample s recorded
                // them (aux_passes.h): the first path sample's when it is sample s (M = K = 1, or the
                // first iteration); else add_aux_sample traces the sample's camera ray.
                const bool first = m == 0 && k == 0;
                FirstHitPasses pixel_passes;
                const bool record_passes = ctx.film.has_aux() && index == s && first;
                if (record_passes) pixel_passes = FirstHitPasses(ctx, x, y, s);
                auto t_path = Clock::now();
                Color surfaces(0.0f);
                // The gathering sample's path traces the camera ray's media once for both (a copy, no
                // random numbers: the same media, so the same image as tracing them twice).
                RayMedia camera_media;
                bool media_traced = false;
                if (!settings.camera_volume_only) {
                    RecordPasses recording(local, record_passes ? &pixel_passes : nullptr);
                    local.camera_media = first && gathering ? &camera_media : nullptr;
                    surfaces = guard_sample(trace_path(scene, settings, ray, camera, rng, local, &sampler), local);
                    media_traced = first && gathering && !local.camera_media;
                    local.camera_media = nullptr;
                }
                auto t_gather = Clock::now();
                path_ns += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(t_gather - t_path).count());
                ++local.paths;
                float gathered = 0.0f;
                if (first && gathering) {
                    GatherCounts n;
                    planes_at[i] = gather(ray, camera.medium, media_traced ? &camera_media : nullptr, camera.plane_segments, keep,
                                          rng, &n);
                    gather_ns += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t_gather).count());
                    plane_hits_ += n.gathered;
                    shadow_rays_ += n.shadow_rays;
                    parallel_rejected_ += n.parallel;
                    nonfinite_rejected_ += n.nonfinite;
                    local.samples_rejected += n.parallel + n.nonfinite;
                    gathered = float(n.gathered);
                }
                // Diagnostic pass: photon planes the camera ray gathered.
                if (first && ctx.film.has_aux()) add_aux_sample(ctx, x, y, s, pixel_passes, gathered);
                ctx.film.add(x, y, guard_sample(surfaces + planes_at[i], local), local.sample_transparency);
            }
        });
        if (!pass.should_stop()) ++finished;  // (a pass the limit met after its last tile counts as cut)
    }
    render_seconds_ += seconds_since(t0);
    path_seconds_ += 1e-9 * double(path_ns.load());
    gather_seconds_ += 1e-9 * double(gather_ns.load());
    passes_ += finished;
    if (finished == M) ++iterations_;
    planes_ += set.size();
}

std::map<std::string, double> PhotonPlanesIntegrator::stats() const {
    return {{"iterations", double(iterations_)},
            {"planes", double(planes_)},
            {"plane_hits", double(plane_hits_.load())},
            {"shadow_rays", double(shadow_rays_.load())},
            {"parallel_rejected", double(parallel_rejected_.load())},
            {"nonfinite_rejected", double(nonfinite_rejected_.load())},
            {"surface_samples", double(surface_samples_)},
            {"path_pixel_samples", double(path_pixel_samples_)},
            {"passes", double(passes_)},
            {"path_segments", double(path_segments_)},
            {"path_segment_lights", double(path_segment_lights_)},
            {"pilot_segments", double(pilot_segments_)},
            {"gathers_skipped", double(gathers_skipped_.load())},
            {"build_seconds", build_seconds_},
            {"render_seconds", render_seconds_},
            {"path_thread_seconds", path_seconds_},
            {"gather_thread_seconds", gather_seconds_}};
}

}  // namespace smis
