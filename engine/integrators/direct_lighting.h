// Resampled direct lighting (Talbot et al. 2005 RIS; Bitterli et al. 2020 ReSTIR), shared by the path
// tracer's RIS strategy and the ReSTIR integrator.
//
// The domain. A light sample is kept in primary sample space: x = (light index i, u in [0,1)^2), the
// input of Light::sample. Its integrand at a shading point q is
//     g_q(x) = f_q(wo, wi) Le(y) / pdf_i(y | q),      y = light i's sample for (q, u),
// (f includes the cosine, pdf_i is the light's solid-angle density), and sum_i int g_q(i, u) du is the
// unshadowed direct light at q. The domain and its measure are the same for every shading point, so a
// sample moves to another pixel unchanged (the identity shift): no Jacobian, for every light type.
// For area and triangle lights (area sampling) the same u is the same point y at every pixel.
//
// Candidates come from the power-based light selection: p(x) = pmf(i). The resampling target is
// p^_q(x) = luminance(g_q(x)), the unshadowed contribution.
//
// Media. In a scene with participating media the target stays unshadowed (no transmittance): the
// shading multiplies g by the shadow ray's transmittance T_q(x) from the medium q's path arrived in,
// and the visibility V_q(x) that the reservoirs' support and the reuse's MIS pdfs depend on is
// [T_q(x) > 0], a deterministic function of q and x like the surface-only visibility. An unbiased
// contribution weight W for the support {p^ > 0, V = 1} then estimates sum_i int g T du, since
// g T vanishes wherever the target or V does.
#pragma once
#include "integrators/volume.h"

namespace smis {

struct LightCandidate {
    uint32_t light = 0;
    Point2 u;
};

// A candidate evaluated at a shading point.
struct CandidateEval {
    LightSample ls;     // the light's sample for (q, u)
    Color g{0.0f};      // f(wo, wi) Le / pdf_light: the integrand in primary sample space (unshadowed)
    float target = 0;   // p^_q(x) = luminance(g)
    uint32_t light = 0;  // which light (x.light)
};
CandidateEval evaluate_candidate(const Scene& scene, const ShadingPoint& sp, const LightCandidate& x);
// Whether the candidate's light point is visible from the shading point (one shadow ray). With media,
// `medium` is the one sp's path arrived in, and visible means a transmittance that is not black.
bool candidate_visible(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e,
                       int32_t medium = kNoMedium);
// With media: the shadow ray's transmittance towards the candidate's light point (0 where blocked),
// as sample_direct's.
Color candidate_transmittance(const Scene& scene, const ShadingPoint& sp, const CandidateEval& e, int32_t medium);

// A weighted reservoir (Chao 1982) holding one sample y with an unbiased contribution weight W: for
// any h supported where the reservoir can produce samples, E[h(y) W] = int h (Lin et al. 2022).
// M is the confidence weight (candidates seen), used to weight reservoirs against each other.
struct Reservoir {
    LightCandidate y;
    float w_sum = 0.0f;
    float M = 0.0f;
    float W = 0.0f;
    // p^ of y at the shading point the reservoir belongs to, kept so that reuse does not evaluate it
    // again (it is one of the MIS pdfs of every combination the reservoir takes part in).
    float target = 0.0f;
    bool has_sample() const { return W > 0.0f; }
    // Streams one candidate with resampling weight w; u decides whether it replaces y.
    bool update(const LightCandidate& x, float w, float u) {
        if (!(w > 0.0f)) return false;
        w_sum += w;
        if (u * w_sum >= w) return false;
        y = x;
        return true;
    }
};

// RIS at one shading point: M candidates from the light selection, resampled by p^/p (Talbot et al.
// 2005 eq. 4), W = w_sum / (M p^(y)). With `visibility_reuse`, an occluded y gets W = 0 (one shadow
// ray; Bitterli et al. 2020 Alg. 5 lines 7-9), which makes the reservoir's support the visible set.
// `chosen`, when given, receives the selected candidate evaluated at sp (so it is not evaluated again).
// `medium`: the one sp's path arrived in (scenes with media).
Reservoir ris_reservoir(const Scene& scene, const ShadingPoint& sp, int candidates, bool visibility_reuse, Rng& rng,
                        CandidateEval* chosen = nullptr, int32_t medium = kNoMedium);

// The direct-light contribution of a reservoir at its shading point: g(y) V(y) W (one shadow ray)
// times w_light(y), its MIS weight against the vertex's BSDF sample, whose emission gets
// w_bsdf = 1 - w_light in emission_along. The weights may come from any densities as long as both
// places use the same ones (shared/papers/001, sec. 3): the resampled strategy's density is
// unknown and is approximated by M times the NEE density pmf(i) pdf_i(y), M the candidates (a
// light is about M times likelier to be among the candidates than to be NEE's one sample). The NEE
// density itself (scale 1) gave small emitters' BSDF hits almost full weight, the fireflies of
// glossy surfaces; no BSDF sampling at all (weight 0) left the near field of emitters to light
// sampling's 1/d^2 tail (measured 1.5% low at 256 spp on scenes/many_lights.blend).
// With media, g V becomes g T (the shadow ray's transmittance from `medium`, see above).
Color reservoir_contribution(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                             const Reservoir& r, int32_t medium = kNoMedium);
// The same for a sample already evaluated and known to be visible at sp (e = evaluate_candidate(sp, r.y)):
// no evaluation, no shadow ray.
Color visible_reservoir_contribution(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                                     const Reservoir& r, const CandidateEval& e);
// The weight w_light(y) W that reservoir_contribution multiplies g(y) V(y) by: r's unbiased
// contribution weight times its sample's MIS weight against the BSDF sample (0 without a sample).
// For any integrand h of the same light sample, h(y) V(y) times this weight is the resampled
// estimate of h's MIS-weighted share, provided h vanishes where the target p^ does: so a spectral
// path evaluates the chosen sample at each of its wavelengths (h = f(l) Le(l) T(l) / pdf_i) with
// the RGB target, which is positive wherever a wavelength's integrand is (the RGB colours of a
// lobe and an emitter are black only where their spectra are).
float resampled_weight(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp,
                       const Reservoir& r, const CandidateEval& e);
// The multiple of the NEE density used for resampled light sampling in the MIS weights (above).
inline float resampled_light_pdf_scale(const RenderSettings& settings) {
    return float(std::max(1, settings.ris_candidates));
}

// RIS's chosen light sample at sp (ris_reservoir without visibility reuse): the candidate evaluated
// at sp and its resampled_weight, unshadowed; weight 0 when no candidate had a positive target.
struct ResampledLight {
    CandidateEval e;
    float weight = 0.0f;
};
ResampledLight ris_light(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng);

// The RIS strategy of the RGB path tracer: ris_light, shaded in RGB through its shadow ray
// (`medium`: the one the path arrived in, scenes with media). The spectral path tracer shades
// ris_light's sample at its wavelengths instead (spectral_path.cpp).
Color ris_direct(const Scene& scene, const RenderSettings& settings, const ShadingPoint& sp, Rng& rng,
                 int32_t medium = kNoMedium);

}  // namespace smis
