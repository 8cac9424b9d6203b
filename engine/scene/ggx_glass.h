// The multiple scattering of multiscatter GGX glass as Cycles 3.4's dielectric random walk produces it
// (scene/ggx_walk.h, glass_walk), tabulated at build time (scene/tools/ggx_glass_gen.cpp) and
// interpolated here. wo is above the surface (z > 0) and eta the relative IOR of the far side over
// wo's; wi on either side. White, and an energy density (no radiance scaling): lobes/glass_multiple.h
// applies the colours and the transmission's (1 / eta)^2.
#pragma once
#include "core/math.h"

namespace smis {

// The BSDF of the walks of two or more bounces, f_ms(wo, wi) (no cosine).
float ggx_glass_multiple_bsdf(const Vec3& wo, const Vec3& wi, float alpha, float eta);
// Its albedo from wo on side `side` (0: reflection, 1: transmission): the integral of f_ms |cos_i| there.
float ggx_glass_multiple_albedo(float cos_o, float alpha, float eta, int side);
// The albedo of both sides averaged over a cosine-weighted wo and over eta and 1 / eta, so that it
// does not change when the back face inverts the IOR: the lobe's weight for the lobe selection.
float ggx_glass_multiple_average(float alpha, float eta);
// The colour of the multiple scattering from wo on `side` for a colour c applied at each bounce after
// the first (mode 0: the Glass BSDF; sum_k share_k c^k over the walks' counts), or at each refraction
// with Cycles' interpolated Fresnel colour of Specular Tint spec_tint at each reflection (mode 1: the
// Principled BSDF; the mean of c^n prod_j (FH_j + (1 - FH_j) cspec0) over the walks, cspec0 = 1 -
// spec_tint (1 - c)).
float ggx_glass_multiple_colour(float c, float cos_o, float alpha, float eta, int side, int mode, float spec_tint);

}  // namespace smis
