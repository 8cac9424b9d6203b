// Cycles 3.4's Christensen-Burley subsurface scattering by disk sampling (integrator/subsurface_disk.h,
// closure/bssrdf.h): King, Kulla, Conty and Fajardo 2013, "BSSRDF Importance Sampling", with
// Christensen and Burley 2015's profile, "Approximate Reflectance Profiles for Efficient Subsurface
// Scattering".
//
// The Subsurface lobe of a Christensen-Burley closure (lobes/subsurface.h, variant kDisk) does not
// walk inside the object: the exit is found on the object's surface near the entry. A radius r is
// drawn from the radial profile of one channel (picked uniformly among those with a radius), a point
// at r on a disk about one of three axes (the entry's geometric normal half the time, the two
// tangents a quarter each), and a probe segment through it along that axis, of half-length
// sqrt(R_max^2 - r^2), finds the object's surface (at most 4 hits, a uniform subset when there
// are more, as Cycles' BSSRDF_MAX_HITS). Each hit's weight is the profile at its true distance over
// the disk's density at r, times the MIS weight of its axis among the three (Cycles' power
// heuristic); one hit is kept, picked by its weight. The path goes on from it with the same exit
// lobe as the random walk, seen from the entry's side, at the entry's bounce depth.
//
// The profile per channel, of mean free path d = radius / (4 pi) (Cycles' bssrdf_setup_radius; its
// bssrdf_burley_setup albedo fit is never called in 3.4), as a density in r over the disk with its
// 2 pi r factor: (e^(-r/d) + e^(-r/(3d))) / (4 d), cut at R_max = 16 d and renormalised to the
// cut (Cycles' BURLEY_TRUNCATE). It integrates to 1: the closure weight (the albedo) is what a
// flat surface reflects.
#pragma once
#include "integrators/subsurface_walk.h"

namespace smis {

// The disk step from `entry` for its Subsurface lobe `lobe`: *beta holds the path throughput
// including the lobe's weight / P(pick) on entry, and the throughput at the exit on success, where
// *exit is the exit's shading point. False: the probe found no surface, and the path ends.
bool subsurface_disk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng, Color* beta,
                     ShadingPoint* exit);
// The same for a spectral path's wavelengths (subsurface_walk.h, SpectralSubsurface): the profile's
// channels are the wavelengths.
bool subsurface_disk(const Scene& scene, const ShadingPoint& entry, const Lobe& lobe, Rng& rng,
                     SpectralSubsurface& ch, ShadingPoint* exit);

namespace burley {
constexpr float kTruncate = 16.0f;  // the profile is cut at kTruncate d
// The radial profile's density in r (per unit radius) for mean free path d: 0 at r = 0 (Cycles'
// bssrdf_burley_pdf), at and beyond the cut, and for d = 0.
float radial_pdf(float d, float r);
// Its cumulative distribution at r (of the cut profile: 1 at the cut).
float radial_cdf(float d, float r);
// The radius whose cumulative distribution is u in [0, 1) (Newton's method on the closed-form cdf).
float sample_radius(float d, float u);
}  // namespace burley

}  // namespace smis
