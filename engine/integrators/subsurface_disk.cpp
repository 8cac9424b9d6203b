#include "integrators/subsurface_disk.h"

#include <algorithm>

#include "integrators/subsurface_walk.h"

namespace smis {

namespace burley {

namespace {

// The profile's cumulative distribution in x = r / d, uncut: 1 - e^(-x)/4 - 3/4 e^(-x/3)
// (Christensen and Burley 2015, eq. 3 times 2 pi r, integrated).
float unit_cdf(float x) { return 1.0f - 0.25f * std::exp(-x) - 0.75f * std::exp(-x / 3.0f); }

const float kCdfAtCut = unit_cdf(kTruncate);

}  // namespace

float radial_pdf(float d, float r) {
    if (!(d > 0.0f) || !(r > 0.0f) || r >= kTruncate * d) return 0.0f;
    const float e3 = std::exp(-r / (3.0f * d));
    return (e3 * e3 * e3 + e3) / (4.0f * d * kCdfAtCut);
}

float radial_cdf(float d, float r) {
    if (!(d > 0.0f) || !(r > 0.0f)) return 0.0f;
    return unit_cdf(std::fmin(r / d, kTruncate)) / kCdfAtCut;
}

float sample_radius(float d, float u) {
    const float target = u * kCdfAtCut;
    // The cdf is concave: Newton's iterates from a point below the root stay below it and rise to
    // it. 1 - cdf lies between 3/4 e^(-x/3) and e^(-x/3), so the tail's inverse is such a point,
    // and a close one where the profile is flat (u near 1).
    float x = std::fmax(0.0f, -3.0f * std::log((1.0f - target) / 0.75f));
    for (int i = 0; i < 12; ++i) {
        const float e3 = std::exp(-x / 3.0f);
        const float f = 1.0f - 0.25f * e3 * e3 * e3 - 0.75f * e3 - target;
        const float df = 0.25f * (e3 * e3 * e3 + e3);
        if (std::fabs(f) < 1e-7f || !(df > 0.0f)) break;
        x -= f / df;
    }
    return clampf(x, 0.0f, kTruncate) * d;
}

}  // namespace burley

namespace {

constexpr int kMaxHits = 4;        // Cycles' BSSRDF_MAX_HITS
constexpr int kMaxCounted = 64;    // crossings counted beyond, for the subset's weight (a safety cap)
constexpr float kReachSlack = 1.0001f;  // a hit on the chosen channel's cut is within it despite rounding

// The object's surface along the probe segment, as Cycles' scene_intersect_local: every crossing
// in order, keeping kMaxHits of them (a uniform subset by reservoir sampling when there are more),
// sorted along the ray. Returns how many crossings there were. Each hit's t is its distance from
// the segment's start.
int probe_hits(const Scene& scene, uint32_t instance, Ray ray, Rng& rng, SurfaceHit* hits) {
    const Vec3 start = ray.o;
    const float length = ray.tmax;
    int count = 0;
    SurfaceHit h;
    while (count < kMaxCounted && scene.intersect_instance(instance, ray, &h)) {
        h.t = dot(h.p - start, ray.d);
        int slot = count;
        if (count >= kMaxHits) slot = std::min(int(rng.next_float() * float(count + 1)), count);
        if (slot < kMaxHits) hits[slot] = h;
        ++count;
        // On past this crossing (a few ULPs beyond the surface, on the ray's side of it).
        ray.o = offset_ray_origin(h.p, dot(ray.d, h.ng) > 0.0f ? h.ng : -h.ng);
        ray.tmax = length - dot(ray.o - start, ray.d);
        if (!(ray.tmax > 0.0f)) break;
    }
    for (int i = 1; i < std::min(count, kMaxHits); ++i)  // insertion sort of the few kept
        for (int j = i; j > 0 && hits[j].t < hits[j - 1].t; --j) std::swap(hits[j], hits[j - 1]);
    return count;
}

// The disk step over the n channels of `ch` (N: their capacity, 3 for RGB): the radius is drawn
// from one channel's profile, uniform among those with a radius, and weighed by the mixture of
// their densities (one-sample MIS); a spectral path's wavelengths are its channels, as in the walk.
// A channel's probe only reaches hits within its cut R_max = 16 d of the entry (the probe's
// half-length is sqrt(R_max^2 - r^2)). Cycles' bssrdf_pdf counts every channel's density at r
// anyway, which under-weights exits beyond the smaller radii' cuts when the channels' radii
// differ; RGB keeps it (kCyclesDensity, the closure spheres match Cycles). A spectral path's
// wavelengths count only the channels whose probe reaches the hit, so each wavelength's estimate is
// unbiased for its profile whatever the path's other wavelengths (measured on a back-lit slab
// with radii 0.4/0.15/0.05: Cycles' density put SMIS' red 7% below single-wavelength paths, 6 SE).
template <int N, bool kCyclesDensity>
bool disk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, SubsurfaceChannels<N>& ch,
          ShadingPoint* exit) {
    const int n = N == 3 ? 3 : ch.n;
    const float* d = ch.radius;  // per channel; 0 for the channels left to the diffuse lobe
    int channels = 0;
    for (int k = 0; k < n; ++k) channels += d[k] > 0.0f ? 1 : 0;
    if (channels == 0) return false;

    // The channel whose profile samples the radius, uniform among those with a radius; the rest of
    // the random number draws the radius.
    float u_r = rng.next_float() * float(channels);
    const int nth = std::min(int(u_r), channels - 1);
    u_r -= float(nth);
    int channel = 0;
    for (int k = 0, seen = 0; k < n; ++k)
        if (d[k] > 0.0f && seen++ == nth) channel = k;
    u_r = std::fmin(u_r, 0.99999994f);
    const float disk_r = burley::sample_radius(d[channel], u_r);
    const float r_max = burley::kTruncate * d[channel];
    const float height = safe_sqrt(r_max * r_max - disk_r * disk_r);

    // The projection axis: the geometric normal half the time, each tangent a quarter.
    const Frame f(entry.ng);
    Vec3 axes[3] = {f.n, f.s, f.t};  // axes[0] is the probe's, axes[1] and [2] span its disk
    float pick[3] = {0.5f, 0.25f, 0.25f};
    float u_axis = rng.next_float();
    if (u_axis < 0.5f) {
        u_axis *= 2.0f;
    } else {
        const int swap = u_axis < 0.75f ? 1 : 2;
        u_axis = (u_axis - (swap == 1 ? 0.5f : 0.75f)) * 4.0f;
        std::swap(axes[0], axes[swap]);
        std::swap(pick[0], pick[swap]);
    }
    const float phi = 2.0f * kPi * u_axis;
    const Vec3 on_disk = axes[1] * (disk_r * std::cos(phi)) + axes[2] * (disk_r * std::sin(phi));
    const Vec3 p0 = entry.hit.p;
    Ray probe{p0 + axes[0] * height + on_disk, -axes[0], 0.0f, 2.0f * height, entry.hit.time, kRayAllVisibility};

    SurfaceHit hits[kMaxHits];
    const int found = probe_hits(scene, entry.hit.attr.instance, probe, rng, hits);
    const int kept = std::min(found, kMaxHits);
    if (kept == 0) return false;

    // The disk's density at r over the channels with a radius (Cycles' bssrdf_pdf).
    float density = 0.0f;
    for (int k = 0; k < n; ++k) density += burley::radial_pdf(d[k], disk_r);
    density /= float(channels);
    if (!(density > 0.0f)) return false;
    // The density over the channels whose probe reaches distance r from the entry (see above).
    auto reaching_density = [&](float r) {
        float sum = 0.0f;
        for (int k = 0; k < n; ++k)
            if (r <= burley::kTruncate * d[k] * kReachSlack) sum += burley::radial_pdf(d[k], disk_r);
        return sum / float(channels);
    };
    // A kept hit stands for found / kept crossings.
    const float subset = found > kMaxHits ? float(found) / float(kMaxHits) : 1.0f;
    float weights[kMaxHits][N], mean_weight[kMaxHits];
    float total = 0.0f;
    for (int i = 0; i < kept; ++i) {
        // MIS over the three axes (power heuristic), each axis' density to reach this hit being its
        // pick probability times the cosine between the axis and the hit's normal; the disk's
        // density in r, common to the three, cancels.
        float pdf_axis[3];
        for (int a = 0; a < 3; ++a) pdf_axis[a] = pick[a] * std::fabs(dot(axes[a], hits[i].ng));
        const float mis = pdf_axis[0] / (sqr(pdf_axis[0]) + sqr(pdf_axis[1]) + sqr(pdf_axis[2]));
        // The profile per channel at the hit's true distance (Cycles' bssrdf_eval).
        const float r = length(hits[i].p - p0);
        const float scale = mis * subset / (kCyclesDensity ? density : reaching_density(r));
        bool finite = true;
        for (int k = 0; k < n; ++k) {
            weights[i][k] = burley::radial_pdf(d[k], r) * scale;
            finite = finite && std::isfinite(weights[i][k]);
        }
        float sum = 0.0f;
        for (int k = 0; k < n; ++k) {
            if (!finite) weights[i][k] = 0.0f;
            sum += weights[i][k];
        }
        mean_weight[i] = sum * (1.0f / float(n));
        total += mean_weight[i];
    }
    if (!(total > 0.0f)) return false;

    // One hit, picked in proportion to its weight (Cycles' resampling); the others' share stays
    // in the throughput.
    const float u_pick = rng.next_float() * total;
    int chosen = kept - 1;
    float acc = 0.0f;
    for (int i = 0; i < kept; ++i) {
        acc += mean_weight[i];
        if (u_pick < acc && mean_weight[i] > 0.0f) {
            chosen = i;
            break;
        }
    }
    const float share = mean_weight[chosen];
    if (!(share > 0.0f)) return false;
    const float resampling = total / share;
    for (int k = 0; k < n; ++k) ch.beta[k] = ch.beta[k] * weights[chosen][k] * resampling;
    subsurface_exit(hits[chosen], entry.backfacing, lobe, exit);
    return true;
}

}  // namespace

bool subsurface_disk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, Color* beta,
                     ShadingPoint* exit) {
    SubsurfaceChannels<3> ch = rgb_channels(lobe, *beta);
    if (!disk<3, true>(scene, entry, lobe, rng, ch, exit)) return false;
    *beta = Color(ch.beta[0], ch.beta[1], ch.beta[2]);
    return true;
}

bool subsurface_disk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng,
                     SpectralSubsurface& ch, ShadingPoint* exit) {
    return disk<SpectralSubsurface::kCapacity, false>(scene, entry, lobe, rng, ch, exit);
}

}  // namespace smis
