// The multiple scattering of anisotropic multiscatter GGX as Cycles 3.4's random walk on the stretched
// microsurface produces it (scene/ggx_walk.h), tabulated at build time (scene/tools/ggx_aniso_gen.cpp,
// which says why the table needs both roughnesses) and interpolated here: white, without the colour
// Cycles applies again at every further bounce (see ggx_aniso_half_ratio). Directions are in the
// lobe's tangent frame (x along the tangent, where the roughness is alpha_x).
#pragma once
#include "core/math.h"

namespace smis {

// The BRDF of the walks of two or more bounces, f_ms(wo, wi) (no cosine), for wo, wi above the surface.
float ggx_aniso_brdf(const Vec3& wo, const Vec3& wi, float ax, float ay);
// Its albedo from wo: the integral of f_ms cos_i.
float ggx_aniso_albedo(const Vec3& wo, float ax, float ay);
// That albedo averaged over a cosine-weighted wo.
float ggx_aniso_average(float ax, float ay);
// The average albedo with a colour of 0.5 applied at each bounce after the first, over the white one.
float ggx_aniso_half_ratio(float ax, float ay);

}  // namespace smis
