// The light a single-scattering sample in a medium connects to, chosen per ray segment.
//
// Choosing by power alone (the surfaces' light selection) gives a bright light far from the ray,
// or behind a wall, nearly all the samples while the dim light next to the ray, which lights most
// of it, gets few: volume_slit's fireflies (issue 22). Here the probability of light i for a
// segment is a mixture
//   pmf_i = a * power_i / P  +  b / n  +  c * w_i / W,   w_i = power_i * G_i * exp(-tau_i),
// over the n lights that can light the medium (Volume Scatter on, and not left to photon planes):
//   - power (a) and uniform (b) parts: the defensive mixture, so every light that can contribute
//     has at least (a power_i / P + b / n) and no weight exceeds 1/a times the power-based one;
//   - the segment part (c): the unoccluded equiangular integral of 1/r^2 over the segment,
//       G_i = int_0^len dt / (h^2 + r^2 + (t - delta)^2) = (atan((len - delta) / h') + atan(delta / h')) / h',
//     h the distance of the light's bounding-sphere centre from the ray's line, delta its foot on
//     the ray, r the sphere's radius (h'^2 = h^2 + r^2 keeps lights on the ray finite), times the
//     transmittance over the distance from the segment's start to its closest point and on to the
//     light (mean sigma_t of the segment's medium), and zero when the whole segment lies behind a
//     one-sided light. Lights at infinity have no segment part.
// Every term is a heuristic: the estimator divides by the pmf of the light it chose, which is what
// pmf() returns, so the mixture only changes the variance. Above kMaxSegmentLights lights (mesh
// emitters) the segment part would cost more than the shadow ray it guides, and the choice is the
// defensive mixture alone, (power + uniform) / 2.
#pragma once
#include <cstdint>
#include <vector>

#include "core/distribution.h"
#include "scene/lights.h"

namespace smis {

class MediaLightChoice {
public:
    static constexpr int kMaxSegmentLights = 32;
    static constexpr float kPowerWeight = 0.25f, kUniformWeight = 0.25f, kSegmentWeight = 0.5f;

    MediaLightChoice() = default;
    // `power` is the surfaces' selection (proportional to each light's power).
    MediaLightChoice(const std::vector<std::unique_ptr<Light>>& lights, const DiscreteDistribution& power);

    // The segment o + d t, t in [0, len] (len may be infinite), in a medium of mean extinction
    // sigma_t. With skip_plane_lights, rectangles and points without radius are left out (photon
    // planes estimate their single scattering).
    // With skip_plane_lights, the plane lights whose bit (by scene light index) is set in
    // keep_plane_lights stay eligible: the per-light segment partition (photon_planes.cpp) left
    // their scattering on this segment to the path tracer. Only for at most kMaxSegmentLights lights.
    struct Segment {
        Vec3 o, d;
        float len;
        float sigma_t;
        bool skip_plane_lights;
        uint32_t keep_plane_lights = 0;
    };
    // Chooses a light with u in [0, 1); false when no light can light media. *remapped (if given): u
    // rescaled within the chosen light's share of [0, 1), uniform and independent of the choice,
    // for the caller's next decisions.
    bool sample(const Segment& s, float u, uint32_t* light, float* pmf, float* remapped = nullptr) const;
    // The probability that sample() chooses `light` for s.
    float pmf(const Segment& s, uint32_t light) const;
    bool empty(bool skip_plane_lights) const { return mode_[skip_plane_lights].eligible.empty(); }
    bool empty(bool skip_plane_lights, uint32_t keep_plane_lights) const {
        return empty(skip_plane_lights) && !(skip_plane_lights && keep_plane_lights);
    }

private:
    struct Entry {
        LightBounds bounds;
        bool bounded = false;
        bool plane = false;  // a rectangle or a point without radius: photon planes can take it
        float power = 0.0f;  // the surfaces' pmf: proportional to power
    };
    struct Mode {
        std::vector<uint32_t> eligible;
        std::vector<float> power_pmf;  // per light, renormalised over eligible ones (0 otherwise)
        DiscreteDistribution power;    // the same, for sampling among many lights
    };
    // The eligible lights of one segment and their power pmf: a mode's, or (keep_plane_lights) the
    // skipping mode's with the kept plane lights added, in the stack arrays of the caller.
    struct Eligible {
        const uint32_t* index;
        size_t count;
        const float* power_pmf;
    };
    struct EligibleStorage {
        uint32_t index[kMaxSegmentLights];
        float power_pmf[kMaxSegmentLights];
    };
    Eligible eligible(const Segment& s, EligibleStorage* storage) const;
    // The mixture's pmf of every light into pmf[] (size lights); only for at most kMaxSegmentLights.
    void segment_pmfs(const Segment& s, const Eligible& e, float* pmf) const;
    float segment_weight(const Segment& s, const Entry& e, float* tau) const;

    std::vector<Entry> entries_;
    Mode mode_[2];
};

}  // namespace smis
