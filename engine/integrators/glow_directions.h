// A second technique for the path's continuation direction at surface vertices inside a scattering
// medium: directions around radius-0 point and spot lights in that medium (scene/glow_lights.h),
// combined with BSDF sampling by one-sample MIS (issue 22).
//
// Why: from a surface point x in fog, the light that a radius-0 light at distance d scatters once
// towards x arrives from a direction at angle theta from the light's with radiance
// ~ sigma_s I pi / (d theta) (the in-scattered integral int I / r^2 dt along a ray passing the light
// at distance d sin theta). BSDF sampling there has an estimator ~ 1 / theta and a logarithmically
// divergent second moment: rays that pass a few centimetres from the light are the fireflies of
// volume_spot (Cycles has them too). Equiangular sampling fixes the distance along such a ray, not
// the choice of the ray. This technique samples theta uniformly in [0, theta_max] around the light's
// direction (core/sampling.h, sample_glow_cone): p(omega) = 1 / (2 pi theta_max sin theta), whose
// 1 / theta matches the glow, so f L / p stays bounded near the light.
//
// One-sample MIS (Veach 1997, sec. 9.2.4, balance heuristic): the continuation is BSDF-sampled with
// probability c (glow_directions.cpp says how c and the cone's size are chosen), else light-aimed, and weighted by the mixture density
//   p(omega) = c p_bsdf(omega) + (1 - c) p_glow(omega),
// which is also the BSDF-side density wherever MIS against next-event estimation needs it (the
// emission the ray then finds uses PathState::prev_pdf = p; the vertex's own light sample uses
// mixture_pdf). p_glow counts only directions on wo's side of the surface: a light-aimed direction
// on the other side is dropped (the path ends), and there p = c p_bsdf, the density of the BSDF
// samples that remain, so every direction is still counted exactly once.
#pragma once
#include "integrators/path_tracing.h"

namespace smis {

class GlowDirections {
public:
    // The technique at sp, whose continuation starts in `medium`; on() false (and no cost beyond
    // these tests) without glow lights in that medium on wo's side, or for BSDFs with a Dirac lobe.
    GlowDirections(const Scene& scene, const ShadingPoint& sp, int32_t medium);
    GlowDirections() = default;  // off
    bool on() const { return n_ > 0; }
    // The light-aimed technique's solid-angle density at wi (a mixture over the lights).
    float pdf(const Vec3& wi) const;
    // The continuation's density: BSDF density bsdf_pdf at wi mixed with pdf(wi).
    float mixture_pdf(float bsdf_pdf, const Vec3& wi) const;
    // The same for a light hidden from some lobes' rays: only continuations labelled with the lit
    // lobes find it, which for BSDF sampling have density lit_pdf and for a light-aimed direction
    // (labelled as BSDF sampling would, Bsdf::lobe_at) the share lit_pdf / bsdf_pdf of pdf(wi).
    float lit_mixture_pdf(float lit_pdf, float bsdf_pdf, const Vec3& wi) const;
    // The continuation at sp from the vertex's lobe and direction numbers and one more, u_technique,
    // which picks the technique and then the light: *bs as from Bsdf::sample but with the mixture's
    // pdf (and, for a light-aimed direction, the BSDF's value there and the lobe BSDF sampling would
    // label it with). False: a light-aimed direction on the far side of the surface (the path ends;
    // not a failed sample).
    bool sample(const ShadingPoint& sp, float u_lobe, Point2 u_dir, float u_technique, BsdfSample* bs) const;

private:
    int n_ = 0;
    float cdf_[kMaxGlowLights];   // the light choice's running sum, normalised
    float pmf_[kMaxGlowLights];
    Vec3 axis_[kMaxGlowLights];  // unit direction from the vertex to each light
    Vec3 side_;                  // the geometric normal on wo's side
};

// The BSDF-side density of a light sample's MIS weight at a vertex that continues by GlowDirections'
// mixture: lit_pdf is the BSDF's density of the lobes that see the light (all of them unless
// `hidden`). Out of line, so sample_direct_through's common path stays as it was.
[[gnu::noinline]] float glow_light_mis_pdf(const Scene& scene, const ShadingPoint& sp, int32_t medium,
                                           uint32_t hidden, float lit_pdf, const Vec3& wi);

}  // namespace smis
