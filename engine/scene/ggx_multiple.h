// The multiple scattering of multiscatter GGX as Cycles 3.4's random walk produces it (scene/ggx_walk.h),
// tabulated at build time (scene/tools/ggx_multiple_gen.cpp) and interpolated here: white, without
// the colour Cycles applies again at every further bounce (see ggx_multiple_half_ratio).
#pragma once
#include "core/math.h"

namespace smis {

// The BRDF of the walks of two or more bounces, f_ms(wo, wi) (no cosine), for wo, wi above the surface.
float ggx_multiple_brdf(const Vec3& wo, const Vec3& wi, float alpha);
// Its albedo from wo: the integral of f_ms cos_i.
float ggx_multiple_albedo(float cos_o, float alpha);
// That albedo averaged over a cosine-weighted wo: 2 integral m(mu) mu dmu.
float ggx_multiple_average(float alpha);
// The average albedo with a colour of 0.5 applied at each bounce after the first, over the white one.
float ggx_multiple_half_ratio(float alpha);

}  // namespace smis
