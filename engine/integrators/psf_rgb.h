// RGB path-space filtering's stage 1 (path_space_filtering.cpp): one pixel sample's path, traced by
// the path tracer's loop (path_loop.h) with policies that end its prefix at x1 and keep its suffix's
// parts apart, into the record stage 2 gathers. The spectral stage 1 is psf_spectral.h.
#pragma once
#include "integrators/psf_density.h"
#include "integrators/psf_records.h"

namespace smis {
namespace psf_detail {

// Stage 1 for one pixel sample; `model` receives x1's technique density model (psf_density.h), built
// here once per stored vertex rather than once per pixel that gathers it. `strata` is null when the
// sampler is not stratified or there are no extra samples at x1. `extra` receives the pixel's
// `extra_paths` private suffixes. With `dirac_z1_per_pixel` (the unbiased variant), a Dirac lobe
// sampled at z1 goes to the per-pixel part instead of L_out (see psf_rgb.cpp). `media`: the scene
// has media, and `record_media` receives x1's. `sampler`: the pixel sample's; its stream drives the
// path, and x1 asks it for its numbers by name when x1 is the camera path's first vertex.
PathRecord trace_rgb_record(bool media, const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
                            LocalCounters& counters, const Camera& camera, RecordAttribs* attribs,
                            TechniqueDensity* model, const PixelStrata* strata, int extra_paths, PrivateSuffix* extra,
                            bool dirac_z1_per_pixel, RecordMedia* record_media);

}  // namespace psf_detail
}  // namespace smis
