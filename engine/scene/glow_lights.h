// The lights whose glow in a medium the path tracer samples directions towards (issue 22,
// integrators/glow_directions.h): point and spot lights without radius that sit inside a scattering
// medium and light media (Ray Visibility > Volume Scatter on). Found once at commit.
//
// Why these: light scattered once from such a light towards a point x arrives from a direction at
// angle theta from the light's direction with radiance ~ sigma_s I pi / (d theta) (d = |x - light|),
// so BSDF sampling at x has an estimator f L / p ~ 1 / theta whose second moment diverges
// (logarithmically): the rare bright samples of volume_spot. Lights with a radius or an area
// saturate at theta ~ size / d and are left to BSDF sampling.
#pragma once
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace smis {

struct GlowLight {
    uint32_t light;    // index into Scene's lights
    Vec3 position;
    float power;       // the light's selection power (Light::power)
    int32_t medium;    // the scattering medium it sits in
};

// At most this many, the most powerful: the per-vertex choice and density loop over all of them.
constexpr int kMaxGlowLights = 8;

}  // namespace smis
