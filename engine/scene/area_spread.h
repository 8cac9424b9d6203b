// Area light spread (Blender's Light > Spread), as Cycles 3.4 models it (light/common.h and
// scene/light.cpp): the light is a soft box behind a grid of slats that pass light within half the
// spread, h, of its normal, attenuated as (1 - tan(angle) / tan(h)) and normalised so the light
// keeps its power: integral over the cone of cos x (1 - tan x / tan h) sin x dx = (1 - (pi/2 - h) /
// tan(h)) / 2, against 1/2 for the Lambertian light. Spread 180 degrees is the plain light.
#pragma once
#include <algorithm>
#include <cmath>

#include "core/math.h"

namespace smis {

struct AreaSpread {
    float tan_spread = 0.0f;  // tan(pi/2 - h) = 1 / tan(h); 0: no cone (spread 180 degrees)
    float normalize = 1.0f;

    // spread: the full cone angle in radians; Cycles keeps at least 1 degree. The normalisation's
    // denominator cancels at small spreads, so it is computed in double: Cycles 3.4 does it in float
    // and gives small spreads more power than they have (+24% at 1 degree, +2.5% at 2, 0.16% at 5).
    static AreaSpread from_angle(float spread) {
        constexpr double pi = 3.14159265358979323846;
        AreaSpread s;
        if (!(spread < kPi)) return s;  // no cone
        const double h = 0.5 * std::max(std::min(double(spread), pi), pi / 180.0);
        s.tan_spread = static_cast<float>(1.0 / std::tan(h));
        // Cycles' 2 / (2 + (2a - pi) tan a) with a = pi/2 - h, that is tan h / (tan h - h).
        s.normalize = static_cast<float>(std::tan(h) / (std::tan(h) - h));
        return s;
    }
    bool active() const { return tan_spread > 0.0f; }
    // The radiance factor towards a direction at cos_angle (> 0) from the light's normal.
    float attenuation(float cos_angle) const {
        const float sin_angle = std::sqrt(std::max(0.0f, 1.0f - cos_angle * cos_angle));
        return std::max((1.0f - tan_spread * sin_angle / cos_angle) * normalize, 0.0f);
    }
    // Light points further than this from the foot of a point at `height` above the light's plane
    // send it nothing (they see it beyond h).
    float reach(float height) const { return height / tan_spread; }
};

}  // namespace smis
