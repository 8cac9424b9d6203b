// Path-space filtering's weightings (stage 2 of path_space_filtering.cpp), one type each. The
// integrator is compiled once per weighting, so a weighting's choices are constants there, and what
// a weighting does with the samples a pixel gathers is its Pixel accumulator:
//   take()        whether the pixel uses a shared sample at all (Keller's similarity test),
//   add_shared()  a shared sample's contribution f_1 L g, with the sample's per-sample value (the
//                 set's density sum for SMIS, eq. 17's denominator; the sample's own density for
//                 Keller) and the pixel's own technique's density on demand,
//   add_private() one of the pixel's private extra suffixes, sampled by its own technique,
//   estimate(), reused(), own_weight()  what reaches the film and the extra-path feedback.
// Internal to path-space filtering.
#pragma once
#include <algorithm>
#include <cstdint>

#include "integrators/psf_records.h"

namespace smis {
namespace psf_detail {

// How far the own suffix's weight w in its pixel's estimate, among n gathered techniques, is from
// an even share: 0 at w = 1/n (the filter shares the pixel's suffix as well as it can), 1 at w = 1
// (it shares nothing). The extra paths are proportional to it.
inline float excess_weight(float w, size_t n) {
    if (n <= 1) return 1.0f;
    const float even = 1.0f / float(n);
    return std::clamp((w - even) / (1.0f - even), 0.0f, 1.0f);
}

// Eq. (17): the balance heuristic normalised over the set's sampled techniques, the pixel's own
// technique counted once more per private extra sample (Veach's multi-sample heuristic with sample
// counts; the other pixels see only the one shared suffix).
class SmisPixel {
public:
    explicit SmisPixel(int extra) : extra_(extra) {}
    bool take(const PathRecord&, const PathRecord&, const RenderSettings&) { return true; }
    // shared: sum_k p(z | ybar_k) over the set; own_density(): p(z | the pixel's technique).
    template <class OwnDensity>
    void add_shared(const Color& contribution, float shared, bool own_sample, size_t set_size, OwnDensity&& own_density) {
        const float p_own = extra_ > 0 || own_sample ? own_density() : 0.0f;
        const float denom = extra_ > 0 ? shared + float(extra_) * p_own : shared;
        if (!(denom > 0.0f)) return;
        sum_ += contribution / denom;
        if (own_sample)  // the own suffix's weight, its density counted once
            own_weight_ = excess_weight(std::min(1.0f, p_own / shared), set_size);
    }
    void end_shared(bool, size_t) {}
    // own_density(), shared(): as above, at the private sample's z1.
    template <class OwnDensity, class Shared>
    void add_private(const Color& contribution, OwnDensity&& own_density, Shared&& shared) {
        if (is_black(contribution)) return;
        const float denom = shared() + float(extra_) * own_density();
        if (denom > 0.0f) sum_ += contribution / denom;
    }
    Color estimate() const { return sum_; }
    float reused(size_t set_size) const { return float(set_size - 1); }
    float own_weight() const { return own_weight_; }

private:
    int extra_;
    Color sum_{0.0f};
    float own_weight_ = -1.0f;  // < 0: nothing learnt (the pixel has no suffix of its own)
};

// Keller et al. 2014: binary similarity of the prefix endpoints (same material, normals within
// psf_keller_normal_cos, near the query's tangent plane); every accepted sample is divided by its
// own density only and the sum by the number accepted (weights 1 / accepted).
class KellerPixel {
public:
    explicit KellerPixel(int) {}
    bool take(const PathRecord& q, const PathRecord& smp, const RenderSettings& settings) {
        const bool similar = smp.material == q.material && dot(smp.ns, q.ns) >= settings.psf_keller_normal_cos &&
                             std::fabs(dot(smp.p - q.p, q.ng)) <= settings.psf_keller_plane * q.radius;
        if (similar) ++accepted_;
        return similar;
    }
    // own_sample_density: the sample's own density (the per-sample value for this weighting).
    template <class OwnDensity>
    void add_shared(const Color& contribution, float own_sample_density, bool, size_t, OwnDensity&&) {
        sum_ += contribution / own_sample_density;
    }
    void end_shared(bool has_suffix, size_t set_size) {
        if (has_suffix && accepted_ > 0) own_weight_ = excess_weight(1.0f / float(accepted_), set_size);
        shared_accepted_ = accepted_;
    }
    template <class OwnDensity, class Shared>
    void add_private(const Color& contribution, OwnDensity&& own_density, Shared&&) {
        ++accepted_;  // every own sample is similar to its pixel
        const float p_own = is_black(contribution) ? 0.0f : own_density();
        if (p_own > 0.0f) sum_ += contribution / p_own;
    }
    Color estimate() const { return accepted_ > 0 ? sum_ / float(accepted_) : sum_; }
    float reused(size_t) const { return shared_accepted_ > 0 ? float(shared_accepted_ - 1) : 0.0f; }
    float own_weight() const { return own_weight_; }
    uint32_t accepted() const { return accepted_; }

private:
    Color sum_{0.0f};
    uint32_t accepted_ = 0, shared_accepted_ = 0;
    float own_weight_ = -1.0f;
};

// No reuse: the path tracer on the stage-1 paths (no grid, no gather).
struct PsfPathWeighting {
    static constexpr bool kGathers = false;
    static constexpr bool kExact = false;
    static constexpr bool kOwnDensityPerSample = false;
    using Pixel = SmisPixel;  // never gathers; named so the gather compiles for every weighting
};

struct PsfKellerWeighting {
    static constexpr bool kGathers = true;
    static constexpr bool kExact = false;
    // The per-sample value is the sample's own density, not the set's sum (no DensitySum is built).
    static constexpr bool kOwnDensityPerSample = true;
    using Pixel = KellerPixel;
};

// Eq. (17) with the practical densities (§4.3): technique models, and no visibility in the weights.
struct PsfSmisWeighting {
    static constexpr bool kGathers = true;
    static constexpr bool kExact = false;
    static constexpr bool kOwnDensityPerSample = false;
    using Pixel = SmisPixel;
};

// Eq. (17) with every connection and density evaluated exactly (§4.2): each technique's own BSDF,
// the visibility of every sample from every technique, and z1's radiance re-evaluated for the
// connecting pixel. Unbiased.
struct PsfSmisExactWeighting {
    static constexpr bool kGathers = true;
    static constexpr bool kExact = true;
    static constexpr bool kOwnDensityPerSample = false;
    using Pixel = SmisPixel;
};

}  // namespace psf_detail
}  // namespace smis
