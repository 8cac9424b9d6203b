// Cycles 3.4's random-walk subsurface scattering (integrator/subsurface_random_walk.h; Chiang, Kutz
// and Burley 2016, "Practical and Controllable Subsurface Scattering for Production Path Tracing",
// with Wrenninge et al.'s anisotropic phase function and Dwivedi-guided sampling after Krivanek and
// d'Eon 2014, Meng et al. 2016 and d'Eon and Krivanek 2020).
//
// A path whose BSDF sample picked a Subsurface lobe (lobes/subsurface.h) enters the object there:
// a cosine direction about the inward normal, then free flights in a homogeneous medium whose
// extinction sigma_t = 1 / (radius (1 - g)) and single-scattering albedo alpha are fitted so that the
// medium's multiple scattering reflects the surface albedo, until a flight crosses the object's own
// surface (rays against that object alone, Scene::intersect_instance). The path goes on from the
// exit with a diffuse lobe on the exit's normal (principled: Cycles' (1 - FL/2) Lambert), whose
// light samples and bounce count as the entry vertex's bounce, as in Cycles.
#pragma once
#include "integrators/path_tracing.h"

namespace smis {

// The channels a subsurface step carries: RGB's three, or a spectral path's n wavelengths (up to
// kCapacity): per channel the lobe's surface albedo and mean free path there (the Lobe's f0 and
// kind_colour, upsampled for a spectral path), and the path throughput.
template <int N>
struct SubsurfaceChannels {
    static constexpr int kCapacity = N;
    int n = N;
    float albedo[N], radius[N], beta[N];
};
using SpectralSubsurface = SubsurfaceChannels<512>;  // spectral::kMaxWavelengths

// RGB's channels of Subsurface lobe `lobe` with the path throughput beta.
inline SubsurfaceChannels<3> rgb_channels(const Lobe& lobe, const Color& beta) {
    SubsurfaceChannels<3> ch;
    for (int k = 0; k < 3; ++k) {
        ch.albedo[k] = lobe.f0[k];
        ch.radius[k] = lobe.kind_colour[k];
        ch.beta[k] = beta[k];
    }
    return ch;
}

// The walk from `entry` for its Subsurface lobe `lobe`: *beta holds the path throughput including
// the lobe's weight / P(pick) on entry, and the throughput at the exit on success, where *exit is
// the exit's shading point. False: the walk left no exit (absorbed, escaped an open mesh, 256
// scattering events), and the path ends.
bool subsurface_walk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, Color* beta,
                     ShadingPoint* exit);
// The same for a spectral path's wavelengths (ch.n of them, ch.beta their throughputs): each flight
// is drawn from one wavelength and weighed by the mixture density over all (one-sample MIS), as RGB
// mixes its three channels, so each wavelength's estimate is unbiased given the path's wavelengths.
bool subsurface_walk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng,
                     SpectralSubsurface& ch, ShadingPoint* exit);

// The exit shading point both subsurface methods go on from: `hit` seen from its front
// (backfacing: from its back), with the diffuse lobe of the entry's Subsurface lobe `lobe` (plain
// Lambert, or principled's (1 - FL/2) Lambert for kPrincipledExit) of weight 1.
void subsurface_exit(const SurfaceHit& hit, bool backfacing, const Lobe& lobe, ShadingPoint* exit);

namespace subsurface_detail {
// Per channel: extinction sigma_t and single-scattering albedo alpha of a walk with surface albedo
// `albedo`, mean free path `radius` and anisotropy g (Chiang et al. 2016, eq. 6 with Cycles' fits
// in g). Exposed for tests.
void walk_coefficients(float albedo, float radius, float g, float* sigma_t, float* alpha);
}  // namespace subsurface_detail

}  // namespace smis
