// Colorimetry for spectral rendering: the wavelength range, the CIE 1931 2-degree observer and the
// conversion of spectra to Blender's scene-linear RGB (Rec.709 primaries, D65 white).
//
// Normalisation: a spectral radiance s(l) has XYZ = int s(l) (xbar, ybar, zbar)(l) dl / int ybar dl,
// so a spectrum whose ybar-weighted mean is 1 has luminance Y = 1, and the CIE D65 illuminant scaled
// to Y = 1 maps to RGB (1, 1, 1). Integrals over the 1 nm tables are rectangle sums over 360-830 nm.
#pragma once
#include "core/math.h"
#include "spectral/tables.h"

namespace smis::spectral {

constexpr float kLambdaMin = 360.0f, kLambdaMax = 830.0f;
constexpr float kLambdaRange = kLambdaMax - kLambdaMin;
constexpr int kTableSamples = 471;           // 1 nm samples of the CIE tables over [360, 830]
constexpr double kCieYIntegral = 106.856895;  // rectangle sum of ybar over the 1 nm table

// Linear interpolation in a 1 nm / 5 nm table; 0 outside its range.
float sample_table(const tables::UniformTable& t, float lambda);

// Linear interpolation in the CIE observer; 0 outside [360, 830].
Vec3 cie_xyz(float lambda);
inline float cie_y(float lambda) { return cie_xyz(lambda).y; }

// XYZ <-> linear Rec.709 (sRGB primaries, D65 white), IEC 61966-2-1 matrices.
Color xyz_to_rgb(const Vec3& xyz);
Vec3 rgb_to_xyz(const Color& rgb);

// RGB contribution of unit spectral radiance at one wavelength per nm: M (xbar, ybar, zbar) / int ybar.
// For a spectrum s, int s(l) rgb_response(l) dl is its linear RGB.
Color rgb_response(float lambda);

}  // namespace smis::spectral
