// Homogeneous participating media and their phase functions. Coefficients are per metre in linear
// Rec.709 RGB, built from Blender's volume shaders with Cycles' conventions (see sync/volumes.py):
// Volume Scatter adds sigma_s = sigma_t = density * colour; Volume Absorption adds
// sigma_a = density * (1 - colour); Principled Volume adds sigma_s = density * colour and
// sigma_a = density * max(1 - colour, 0) * max(1 - sqrt(absorption colour), 0).
#pragma once
#include "core/math.h"
#include "core/sampling.h"

namespace smis {

// Henyey-Greenstein phase function; g = 0 is isotropic. Directions follow the BSDF convention: wo
// points back along the ray (towards the viewer), wi towards the light; forward scattering (g > 0)
// favours wi = -wo, i.e. Cycles' cos_theta = dot(-wo, wi).
struct PhaseSample {
    Vec3 wi;
    float pdf = 0.0f;  // equals the phase function value (the sampling is exact)
};
class HenyeyGreenstein {
public:
    explicit HenyeyGreenstein(float g = 0.0f) : g_(clampf(g, -0.99f, 0.99f)) {}
    float g() const { return g_; }
    float eval(const Vec3& wo, const Vec3& wi) const { return density(-dot(wo, wi)); }
    float pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    PhaseSample sample(const Vec3& wo, Point2 u) const;

private:
    float density(float cos_theta) const {
        if (g_ == 0.0f) return kInv4Pi;
        float denom = 1.0f + g_ * g_ - 2.0f * g_ * cos_theta;
        return kInv4Pi * (1.0f - g_ * g_) / (denom * std::sqrt(std::max(denom, 1e-12f)));
    }
    float g_;
};

struct Medium {
    Color sigma_a{0.0f}, sigma_s{0.0f};
    HenyeyGreenstein phase;
    Color sigma_t() const { return sigma_a + sigma_s; }
    bool scatters() const { return max_component(sigma_s) > 0.0f; }
};

inline Color transmittance(const Color& sigma_t, float dist) {
    return {std::exp(-sigma_t.x * dist), std::exp(-sigma_t.y * dist), std::exp(-sigma_t.z * dist)};
}

// A distance in [0, len) along a segment of a homogeneous medium, for single scattering: one colour
// channel is picked uniformly and the distance drawn from that channel's exponential truncated to
// the segment, so the three channels' transmittances are all importance sampled; pdf() is the
// one-sample MIS (average) density over the channels (spectral MIS, Miller et al. 2019's "hero"
// idea with equal channel probabilities). A channel with sigma_t = 0 samples uniformly.
struct DistanceSample {
    float t = 0.0f;
    float pdf = 0.0f;
};
DistanceSample sample_segment_distance(const Color& sigma_t, float len, float u_channel, float u);
// One channel's part: the exponential of rate sigma truncated to [0, len), its density at t, and a
// sample *t (false: nothing to sample, a clear infinite segment). Spectral rendering mixes these over
// its wavelengths as the RGB functions above mix them over the three channels.
float truncated_exponential_pdf(float sigma, float len, float t);
bool sample_truncated_exponential(float sigma, float len, float u, float* t);
float segment_distance_pdf(const Color& sigma_t, float len, float t);

// Equiangular sampling (Kulla & Fajardo 2012) of t in [0, len) on the line o + t d (d unit) towards a
// point p: pdf proportional to 1 / |o + t d - p|^2, which cancels the light's inverse-square falloff
// near the light where distance sampling is poor. Invalid (pdf 0) when p lies on the line.
struct EquiangularFrame {
    float delta = 0.0f, h = 0.0f;     // p's projection on the line and its distance to it
    float theta_a = 0.0f, theta_b = 0.0f;
    bool valid = false;
};
EquiangularFrame equiangular_frame(const Vec3& o, const Vec3& d, float len, const Vec3& p);
DistanceSample sample_equiangular(const EquiangularFrame& f, float u);
float equiangular_pdf(const EquiangularFrame& f, float t);

// Free-flight distance with a scalar rate (exponential, not truncated): the survival probability to
// distance d is exp(-rate d). Rate 0 returns infinity.
inline float sample_free_flight(float rate, float u) {
    return rate > 0.0f ? -std::log1p(-u) / rate : kInf;
}

}  // namespace smis
