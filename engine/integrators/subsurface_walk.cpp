#include "integrators/subsurface_walk.h"

#include "scene/lobes/principled_part.h"

namespace smis {

namespace subsurface_detail {

void walk_coefficients(float albedo, float radius, float g, float* sigma_t, float* alpha) {
    // Polynomial fits in g of the albedo inversion (Cycles' subsurface_random_walk_remap).
    const float g2 = g * g, g3 = g2 * g, g4 = g3 * g, g5 = g4 * g, g6 = g5 * g, g7 = g6 * g;
    const float a = 1.8260523782f - 1.28451056436f * g - 1.79904629312f * g2 + 9.19393289202f * g3 -
                    22.8215585862f * g4 + 32.0234874259f * g5 - 23.6264803333f * g6 + 7.21067002658f * g7;
    const float b = 4.98511194385f +
                    0.127355959438f * std::exp(31.1491581433f * g - 201.847017512f * g2 + 841.576016723f * g3 -
                                               2018.09288505f * g4 + 2731.71560286f * g5 - 1935.41424244f * g6 +
                                               559.009054474f * g7);
    const float c = 1.09686102424f - 0.394704063468f * g + 1.05258115941f * g2 - 8.83963712726f * g3 +
                    28.8643230661f * g4 - 46.8802913581f * g5 + 38.5402837518f * g6 - 12.7181042538f * g7;
    const float d = 0.496310210422f + 0.360146581622f * g - 2.15139309747f * g2 + 17.8896899217f * g3 -
                    55.2984010333f * g4 + 82.065982243f * g5 - 58.5106008578f * g6 + 15.8478295021f * g7;
    const float e = 4.23190299701f +
                    0.00310603949088f * std::exp(76.7316253952f * g - 594.356773233f * g2 + 2448.8834203f * g3 -
                                                 5576.68528998f * g4 + 7116.60171912f * g5 - 4763.54467887f * g6 +
                                                 1303.5318055f * g7);
    const float f = 2.40602999408f - 2.51814844609f * g + 9.18494908356f * g2 - 79.2191708682f * g3 +
                    259.082868209f * g4 - 403.613804597f * g5 + 302.85712436f * g6 - 87.4370473567f * g7;
    const float blend = std::pow(albedo, 0.25f);
    float x = (1.0f - blend) * a * std::pow(std::atan(b * albedo), c) +
              blend * d * std::pow(std::atan(e * albedo), f);
    *alpha = clampf(x, 0.0f, 0.999999f);
    *sigma_t = (1.0f / std::fmax(radius, 1e-16f)) / (1.0f - g);
}

}  // namespace subsurface_detail

namespace {

constexpr int kMaxScatterings = 256;     // Cycles' BSSRDF_MAX_BOUNCES
constexpr int kSimilarityLevel = 9;      // beyond, isotropic scattering with the similar medium
constexpr float kMinAlpha = 0.2f;        // lower single-scattering albedos are raised, their loss kept in beta
constexpr float kThroughputEpsilon = 1e-6f;  // Cycles' VOLUME_THROUGHPUT_EPSILON

// Henyey-Greenstein phase function of cos between the old and new directions.
float hg_phase(float cos_theta, float g) {
    const float denom = 1.0f + g * g - 2.0f * g * cos_theta;
    return (1.0f - g * g) / (denom * std::sqrt(denom)) * (0.25f * kInvPi);
}

// A direction at cos_theta from axis, azimuth 2 pi u.
Vec3 around(const Vec3& axis, float cos_theta, float u) {
    const float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    const float phi = 2.0f * kPi * u;
    return Frame(axis).to_world(Vec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta));
}

// Henyey-Greenstein sampling about d (uniform below |g| 1e-3), with its density.
Vec3 sample_hg(const Vec3& d, float g, Point2 u, float* pdf) {
    float cos_theta;
    if (std::fabs(g) < 1e-3f) {
        cos_theta = 1.0f - 2.0f * u.x;
        *pdf = 0.25f * kInvPi;
    } else {
        const float k = (1.0f - g * g) / (1.0f - g + 2.0f * g * u.x);
        cos_theta = (1.0f + g * g - k * k) / (2.0f * g);
        *pdf = hg_phase(cos_theta, g);
    }
    return around(d, cos_theta, u.y);
}

// Dwivedi's guiding phase function (Meng et al. 2016, eqs. 9 and 10) about the entry normal, with
// v the diffusion length and log_v = log((v + 1) / (v - 1)).
float dwivedi_phase(float v, float log_v, float cos_theta) { return 1.0f / ((v - cos_theta) * log_v); }
float sample_dwivedi(float v, float log_v, float u) { return v - (v + 1.0f) * std::exp(-u * log_v); }
// Diffusion length of single-scattering albedo alpha (d'Eon and Krivanek 2020, eq. 67).
float diffusion_length(float alpha) {
    return 1.0f / std::sqrt(1.0f - std::pow(alpha, 2.44294f - 0.0215813f * alpha + 0.578637f / alpha));
}

// The density of a flight of length t in a medium of extinction sigma: the transmittance when it
// ended on the surface (every longer flight is cut there), sigma times it when it scattered.
float flight_pdf(float sigma, float t, bool hit) {
    const float tr = std::exp(-sigma * t);
    return hit ? tr : sigma * tr;
}

// The walk over the n channels of `ch` (N: their capacity, 3 for RGB so that its loops unroll).
// Chiang et al.'s walk samples each flight from one channel, picked in proportion to
// |throughput x alpha|, and weighs it by the one-sample MIS density over all channels (the balance
// heuristic); a spectral path's wavelengths are its channels, so every wavelength's estimate is
// unbiased given the path's wavelength set and the relative densities r_j do not change.
template <int N>
bool walk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, SubsurfaceChannels<N>& ch,
          ShadingPoint* exit) {
    const int n = N == 3 ? 3 : ch.n;
    const Vec3 p0 = entry.hit.p;
    const Vec3 n_entry = entry.bsdf.frame().n;  // the closure normal, on the viewer's side
    const Point2 u_dir{rng.next_float(), rng.next_float()};
    Vec3 d = Frame(-n_entry).to_world(sample_cosine_hemisphere(u_dir));
    if (!(dot(-entry.ng, d) > 0.0f)) return false;

    // The medium (per channel), and the throughput without the surface albedo, which the walk's
    // scattering brings back (Cycles divides it out).
    const float g = lobe.alpha;
    float sigma_t[N], alpha[N], throughput[N], sigma_s[N], sigma_s_similar[N], sigma_t_similar[N];
    float max_alpha = 0.0f, min_sigma_t = kInf;
    for (int k = 0; k < n; ++k) {
        subsurface_detail::walk_coefficients(ch.albedo[k], ch.radius[k], g, &sigma_t[k], &alpha[k]);
        throughput[k] = ch.albedo[k] != 0.0f ? ch.beta[k] / ch.albedo[k] : 0.0f;
        // Very low albedos would make the guiding phase function infinite: raise alpha, keep the loss.
        if (alpha[k] < kMinAlpha) {
            throughput[k] *= alpha[k] / kMinAlpha;
            alpha[k] = kMinAlpha;
        }
        sigma_s[k] = sigma_t[k] * alpha[k];
        // After kSimilarityLevel events: the isotropic medium similar to the anisotropic one.
        sigma_s_similar[k] = sigma_s[k] * (1.0f - g);
        sigma_t_similar[k] = sigma_t[k] - sigma_s[k] + sigma_s_similar[k];
        max_alpha = std::max(max_alpha, alpha[k]);
        min_sigma_t = std::min(min_sigma_t, sigma_t[k]);
    }
    // The guiding uses the highest albedo of the channels (lower ones guide too hard: fireflies).
    const float v = diffusion_length(max_alpha);
    if (!(v != 1.0f) || !std::isfinite(v)) return false;
    const float log_v = std::log((v + 1.0f) / (v - 1.0f));
    const float guided_fraction_0 = 1.0f - std::fmax(0.5f, std::pow(std::fabs(g), 0.125f));

    Ray ray{offset_ray_origin(p0, -entry.ng), d, 0.0f, kInf, entry.hit.time, kRayAllVisibility};
    Vec3 at = p0;  // the current scattering point (the ray's origin but for the first flight's offset)
    SurfaceHit hit;
    bool found_exit = false, have_opposite = false;
    float opposite_distance = 0.0f;
    for (int bounce = 0; bounce < kMaxScatterings; ++bounce) {
        const bool similar = bounce > kSimilarityLevel;
        const float g_b = similar ? 0.0f : g;
        const float guided_fraction = similar ? 0.75f : guided_fraction_0;
        const float* st = similar ? sigma_t_similar : sigma_t;
        const float* ss = similar ? sigma_s_similar : sigma_s;

        // Chiang et al.'s channel choice: proportional to |throughput alpha| (uniform when zero).
        float channel_pmf[N], sum = 0.0f;
        for (int k = 0; k < n; ++k) {
            channel_pmf[k] = std::fabs(throughput[k] * alpha[k]);
            sum += channel_pmf[k];
        }
        const float inv_sum = sum > 0.0f ? 1.0f / sum : 0.0f;
        for (int k = 0; k < n; ++k) channel_pmf[k] = sum > 0.0f ? channel_pmf[k] * inv_sum : 1.0f / float(n);
        const float u_channel = rng.next_float();
        int channel = n - 1;
        float acc = 0.0f;
        for (int k = 0; k < n - 1; ++k) {
            acc += channel_pmf[k];
            if (u_channel < acc) {
                channel = k;
                break;
            }
        }
        float sample_sigma = st[channel];
        const float u_t = rng.next_float();

        float backward_fraction = 0.0f, forward_factor = 0.0f, backward_factor = 0.0f;
        float forward_stretch = 1.0f, backward_stretch = 1.0f;
        if (bounce > 0) {  // the first flight's direction is already chosen: classic distance sampling
            const bool guided = rng.next_float() < guided_fraction;
            bool backward = false;
            if (have_opposite) {
                // Towards the opposite side, more likely the deeper the walk (d'Eon and Krivanek 2020).
                const float depth = clampf(dot(at - p0, -n_entry), 0.0f, opposite_distance);
                backward_fraction = 1.0f / (1.0f + std::exp((opposite_distance - 2.0f * depth) / v));
                backward = rng.next_float() < backward_fraction;
            }
            const Point2 u_s{rng.next_float(), rng.next_float()};
            float cos_theta, phase_pdf;
            if (guided) {
                cos_theta = sample_dwivedi(v, log_v, u_s.x);
                if (backward) cos_theta = -cos_theta;  // the mirrored lobe
                const Vec3 nd = around(n_entry, cos_theta, u_s.y);
                phase_pdf = hg_phase(dot(ray.d, nd), g_b);
                ray.d = nd;
            } else {
                ray.d = sample_hg(ray.d, g_b, u_s, &phase_pdf);
                cos_theta = dot(ray.d, n_entry);
            }
            // The guided direction densities as ratios to the phase function, which cancels in the
            // estimator (it does not depend on the channel).
            forward_factor = 0.5f * kInvPi * dwivedi_phase(v, log_v, cos_theta) / phase_pdf;
            backward_factor = 0.5f * kInvPi * dwivedi_phase(v, log_v, -cos_theta) / phase_pdf;
            forward_stretch = 1.0f - cos_theta / v;
            backward_stretch = 1.0f + cos_theta / v;
            if (guided) sample_sigma *= backward ? backward_stretch : forward_stretch;
        }
        float t = -std::log(1.0f - u_t) / sample_sigma;

        // The first flight also looks for the opposite side within 10 mean free paths.
        ray.tmax = bounce == 0 ? std::fmax(t, 10.0f / min_sigma_t) : t;
        bool hit_surface = scene.intersect_instance(entry.hit.attr.instance, ray, &hit);
        if (bounce == 0) {
            if (hit_surface) {
                have_opposite = true;
                opposite_distance = dot(ray.o + ray.d * hit.t - p0, -n_entry);
            }
            hit_surface = hit_surface && hit.t < t;
        }
        if (hit_surface) t = hit.t;
        at = ray.o + ray.d * t;

        // One-sample MIS (balance heuristic) over classic and guided sampling, forward and backward,
        // and over the channels.
        float tr[N], mis_pdf = 0.0f;
        for (int k = 0; k < n; ++k) {
            tr[k] = std::exp(-st[k] * t);
            float pdf = hit_surface ? tr[k] : st[k] * tr[k];
            if (bounce > 0) {
                float guided_pdf = flight_pdf(st[k] * forward_stretch, t, hit_surface) * forward_factor;
                if (have_opposite)
                    guided_pdf = guided_pdf * (1.0f - backward_fraction) +
                                 flight_pdf(st[k] * backward_stretch, t, hit_surface) * backward_factor *
                                     backward_fraction;
                pdf = pdf * (1.0f - guided_fraction) + guided_pdf * guided_fraction;
            }
            mis_pdf += channel_pmf[k] * pdf;
        }
        const float inv_mis_pdf = 1.0f / mis_pdf;
        float max_throughput = 0.0f;
        for (int k = 0; k < n; ++k) {
            throughput[k] = throughput[k] * (hit_surface ? tr[k] : ss[k] * tr[k]) * inv_mis_pdf;
            if (!std::isfinite(throughput[k])) return false;
            max_throughput = std::max(max_throughput, throughput[k]);
        }
        if (hit_surface) {
            found_exit = true;
            break;
        }
        if (max_throughput < kThroughputEpsilon) return false;
        ray.o = at;
    }
    if (!found_exit) return false;

    // The exit, seen from outside (Cycles turns the ray around).
    subsurface_exit(hit, dot(ray.d, hit.ng) < 0.0f, lobe, exit);
    for (int k = 0; k < n; ++k) ch.beta[k] = throughput[k];
    return true;
}

}  // namespace

void subsurface_exit(const SurfaceHit& hit, bool backfacing, const Lobe& lobe, ShadingPoint* exit) {
    exit->hit = hit;
    exit->backfacing = backfacing;
    exit->ng = backfacing ? -hit.ng : hit.ng;
    exit->ns = backfacing ? -hit.ns : hit.ns;
    // Neither lobe reads wo but for its side: the normal keeps it on the lit side however the
    // step that found the exit met the surface.
    exit->wo = exit->ns;
    exit->holdout = Color(0.0f);
    Lobe out;
    out.weight = Color(1.0f);
    if (lobe.variant & SubsurfaceLobe::kPrincipledExit) {
        out.kind = LobeKind::PrincipledPart;
        out.variant = PrincipledPartLobe::kExit;
    }
    exit->bsdf = Bsdf(Frame(exit->ns), exit->ng);
    exit->bsdf.add(out);
}

bool subsurface_walk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, Color* beta,
                     ShadingPoint* exit) {
    SubsurfaceChannels<3> ch = rgb_channels(lobe, *beta);
    if (!walk<3>(scene, entry, lobe, rng, ch, exit)) return false;
    *beta = Color(ch.beta[0], ch.beta[1], ch.beta[2]);
    return true;
}

bool subsurface_walk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng,
                     SpectralSubsurface& ch, ShadingPoint* exit) {
    return walk<SpectralSubsurface::kCapacity>(scene, entry, lobe, rng, ch, exit);
}

}  // namespace smis
