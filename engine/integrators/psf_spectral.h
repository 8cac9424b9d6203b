// Spectral path-space filtering (paper §4 with §5's wavelength sampling). Each iteration draws one
// wavelength set, as the spectral path tracer draws a pixel sample's (spectral_throughput.h,
// wavelength_offsets: the sequence runs over the iterations), and every pixel's path carries it:
// a gathered suffix's radiance is then radiance at the gathering pixel's wavelengths too. The
// prefix throughput beta_i = f(ybar, l_i) / p(ybar | l_c), the suffix's L_out(z1) and z1's two
// re-evaluated estimators are kept per wavelength, and the gather evaluates x1's BSDF towards z1 at
// every wavelength: a pixel adds sum_i response_i beta_i f_1(l_i) L_out(l_i), the spectral path
// tracer's estimate of the same path (response_i = rgb(l_i) / q_i). The wavelength MIS weight
// 1 / sum_j a_j r_j of every emission along the suffix is folded into L_out: it depends on the whole
// path's relative densities r_j = r_j(prefix) r_j(suffix), so a suffix is shared only between
// prefixes with the same r(prefix) (the record's spectral class, below). Given its set an iteration
// is the spectral path tracer's estimator filtered; the filter weights (eq. 17, Keller's, the
// unbiased variant's) are densities of directions over the techniques' non-Dirac lobes and do not
// depend on the wavelength, so they stay as in RGB.
#pragma once
#include <memory>

#include "integrators/psf_density.h"
#include "integrators/psf_records.h"
#include "spectral/wavelength_sampling.h"

namespace smis {

class PsfSpectrum {
public:
    PsfSpectrum(const Scene& scene, spectral::SpectralMode mode, int wavelengths);
    ~PsfSpectrum();
    int count() const;
    // The set of iteration s, and per-wavelength storage for `records` records (`exact`: also z1's
    // estimators and, with media, the own segment's transmittance, for the unbiased gather).
    void begin_iteration(const RenderSettings& settings, uint32_t s, size_t records, bool exact, bool media);
    // Stage 1 of record k, as psf_rgb.h's trace_rgb_record (same arguments) at the
    // iteration's wavelengths. The record's beta is 1: its throughput is per wavelength here.
    psf_detail::PathRecord trace_record(bool media, size_t k, const Scene& scene, const RenderSettings& settings,
                                        Ray ray, Sampler& sampler, LocalCounters& counters, const Camera& camera,
                                        psf_detail::RecordAttribs* attribs, TechniqueDensity* model,
                                        const psf_detail::PixelStrata* strata, int extra_paths,
                                        psf_detail::PrivateSuffix* extra, bool dirac_z1_per_pixel,
                                        psf_detail::RecordMedia* record_media) const;
    // f(wo -> wi) |cos| of `bsdf` (of material `material`) at each wavelength into f; false: 0 at all.
    bool eval(uint32_t material, const Bsdf& bsdf, const Vec3& wo, const Vec3& wi, float* f) const;
    // The RGB of sum_i response_i beta_k,i f_i L_i (tr_i): record k's prefix, x1's BSDF values f and a
    // suffix's radiance L (times a connection's transmittance tr, when given).
    Color combine(size_t k, const float* f, const float* L, const float* tr = nullptr) const;
    // Record k's suffix radiance L_out (with media: as it arrives at x1), and its segment's transmittance.
    const float* L_out(size_t k) const;
    const float* suffix_tr(size_t k) const;
    // The unbiased gather: record j's z1 (its BSDF bz, of material z_material) re-evaluated towards
    // z_wo from its two estimators (nee_dir, next_dir: the record's), into out.
    void reevaluate(size_t j, const Bsdf& bz, uint32_t z_material, const Vec3& z_wo, const Vec3& nee_dir,
                    const Vec3& next_dir, float* out) const;
    // A reconnection's transmittance at each wavelength into tr; false when an opaque surface blocks it
    // (media_segments.h, connection_through_media).
    bool connection_tr(const Scene& scene, const ShadowRay& s, uint32_t visibility, int32_t medium, float* tr) const;
    double bytes_per_record() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace smis
