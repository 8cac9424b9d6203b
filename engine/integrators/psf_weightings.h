// Path-space filtering's weightings (PsfWeighting, path_space_filtering.h) as strategy types with one
// interface: how a pixel combines the suffixes of the technique set gathered around its x1. The gather
// (path_space_filtering.cpp) is instantiated once per type, chosen once per iteration
// (with_weighting). Internal to path_space_filtering.cpp.
//   kShares                false: PSF_PATH, the path tracer on the stage-1 paths (no grid, no gather)
//   kExact                 the unbiased variant (§4.2): every technique's density from its BSDF, and
//                          visibility and z1's scattering evaluated for every connection
//   kSumsDensities         the set's densities are summed once for all its samples (DensitySum)
//   per_sample(own, shared)  what a sample's contribution is divided by, before the pixel's own
//                          samples are counted: own() its technique's density, shared() eq. (17)'s sum
//                          over the set (only the one the type needs is called)
//   Pixel                  one pixel's estimate: takes(q, smp) (whether sample smp joins it), add(),
//                          end_of_set(), add_private() (the pixel's extra suffixes), estimate(),
//                          reused() (the diagnostic pass), own_weight() (< 0: nothing learnt about the
//                          own suffix's weight) and accepted() (Keller's acceptances, for the stats)
#pragma once
#include <algorithm>

#include "integrators/path_space_filtering.h"
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

struct PathWeighting {
    static constexpr bool kShares = false;
    static constexpr bool kExact = false;
    static constexpr bool kSumsDensities = false;
};

// Eq. (17): the balance heuristic normalised over the sampled techniques (practical variant, §4.3:
// the techniques' densities from their models, visibility assumed), the pixel's own technique
// counted once more per extra sample.
struct SmisWeighting {
    static constexpr bool kShares = true;
    static constexpr bool kExact = false;
    static constexpr bool kSumsDensities = true;
    template <class Own, class Shared>
    static float per_sample(Own&&, Shared&& shared) {
        return shared();
    }
    class Pixel {
    public:
        Pixel(const RenderSettings&, const PathRecord&, int extra, size_t set_size) : extra_(extra), n_(set_size) {}
        bool takes(const PathRecord&) const { return true; }
        // Sample ii's contribution, per_sample its shared denominator, own_density() its density under
        // the pixel's technique. (Past the visibility test of the unbiased variant, its own term needs
        // no test of its own.)
        template <class OwnDensity>
        void add(const Color& contribution, float per_sample, bool own_sample, OwnDensity&& own_density) {
            const float p_own = extra_ > 0 || own_sample ? own_density() : 0.0f;
            float denom = extra_ > 0 ? per_sample + float(extra_) * p_own : per_sample;
            if (!(denom > 0.0f)) return;
            sum_ += contribution / denom;
            if (own_sample)  // the own suffix's weight, its density counted once
                own_weight_ = excess_weight(std::min(1.0f, p_own / per_sample), n_);
        }
        void end_of_set(bool) {}
        // A private extra suffix, sampled by the own technique: its denominator is the set's sum plus
        // the own density once per extra sample.
        template <class OwnDensity, class Shared>
        void add_private(const PrivateSuffix& ps, OwnDensity&& own_density, Shared&& shared) {
            if (is_black(ps.contribution)) return;
            float denom = shared() + float(extra_) * own_density();
            if (denom > 0.0f) sum_ += ps.contribution / denom;
        }
        Color estimate() const { return sum_; }
        float reused() const { return float(n_ - 1); }  // other paths' suffixes combined here
        float own_weight() const { return own_weight_; }
        uint32_t accepted() const { return 0; }

    private:
        int extra_;
        size_t n_;
        Color sum_{0.0f};
        float own_weight_ = -1.0f;
    };
};

// The unbiased variant (§4.2): eq. (17) with every connection and density evaluated exactly.
struct SmisUnbiasedWeighting : SmisWeighting {
    static constexpr bool kExact = true;
    static constexpr bool kSumsDensities = false;  // it sums them per sample, with their visibility
};

// Keller et al. 2014: binary similarity of the prefix endpoints (same material, normals within
// psf_keller_normal_cos, near the query's tangent plane); each accepted sample divided by its own
// density, the sum normalised over the accepted samples.
struct KellerWeighting {
    static constexpr bool kShares = true;
    static constexpr bool kExact = false;
    static constexpr bool kSumsDensities = false;
    template <class Own, class Shared>
    static float per_sample(Own&& own, Shared&&) {
        return own();
    }
    class Pixel {
    public:
        Pixel(const RenderSettings& settings, const PathRecord& q, int, size_t set_size)
            : settings_(settings), q_(q), n_(set_size) {}
        bool takes(const PathRecord& smp) {
            const bool similar = smp.material == q_.material && dot(smp.ns, q_.ns) >= settings_.psf_keller_normal_cos &&
                                 std::fabs(dot(smp.p - q_.p, q_.ng)) <= settings_.psf_keller_plane * q_.radius;
            if (similar) ++accepted_;
            return similar;
        }
        template <class OwnDensity>
        void add(const Color& contribution, float per_sample, bool, OwnDensity&&) {
            sum_ += contribution / per_sample;
        }
        void end_of_set(bool has_suffix) {
            if (has_suffix && accepted_ > 0) own_weight_ = excess_weight(1.0f / float(accepted_), n_);  // weights 1 / accepted
            shared_accepted_ = accepted_;
        }
        template <class OwnDensity, class Shared>
        void add_private(const PrivateSuffix& ps, OwnDensity&& own_density, Shared&&) {
            ++accepted_;  // every own sample is similar to its pixel
            float p_own = is_black(ps.contribution) ? 0.0f : own_density();
            if (p_own > 0.0f) sum_ += ps.contribution / p_own;
        }
        Color estimate() const { return accepted_ > 0 ? sum_ / float(accepted_) : sum_; }
        float reused() const { return shared_accepted_ > 0 ? float(shared_accepted_ - 1) : 0.0f; }
        float own_weight() const { return own_weight_; }
        uint32_t accepted() const { return accepted_; }

    private:
        const RenderSettings& settings_;
        const PathRecord& q_;
        size_t n_;
        Color sum_{0.0f};
        float own_weight_ = -1.0f;
        uint32_t accepted_ = 0, shared_accepted_ = 0;
    };
};

// f(weighting type) for the weighting `w`.
template <class F>
void with_weighting(PsfWeighting w, F&& f) {
    switch (w) {
        case PsfWeighting::Path: return f(PathWeighting{});
        case PsfWeighting::Keller: return f(KellerWeighting{});
        case PsfWeighting::Smis: return f(SmisWeighting{});
        case PsfWeighting::SmisUnbiased: return f(SmisUnbiasedWeighting{});
    }
}

}  // namespace psf_detail
}  // namespace smis
