// The layout of the anisotropic multiscatter GGX table (scene/tools/ggx_aniso_gen.cpp writes it,
// scene/ggx_aniso.cpp reads it): rows of the two roughnesses, cells of the view direction (its cosine
// and its azimuth from the tangent, folded into the first quadrant) and of where the walk leaves (cos^2
// and its azimuth from the tangent, all the way round). The exit's azimuth is the tangent's, not the
// view's: the lobe is stretched along the tangent whatever the view, and interpolating between view
// cells then keeps that stretch (measured from the view's, it smeared it: <x^2 - y^2> of the exit 20-25%
// short of the walk's; 16 azimuths from the tangent's: 10-18% short; 32: 5-10%).
#pragma once

namespace smis::ggx_aniso {

constexpr int kRough = 8;   // roughness sqrt(alpha_x), sqrt(alpha_y) = r / (kRough - 1)
constexpr int kCosO = 8;    // cos theta_o at the cell centres (o + 0.5) / kCosO
constexpr int kPhiO = 4;    // phi_o from the tangent at the cell centres (p + 0.5) (pi / 2) / kPhiO
constexpr int kCosI = 8;    // cos^2 theta_i in [i, i + 1) / kCosI
constexpr int kPhiI = 32;   // phi_i in [k, k + 1) 2 pi / kPhiI (a multiple of 4: the x <-> y mirror)

inline float cos_o_of_cell(int o) { return (float(o) + 0.5f) / float(kCosO); }
inline float phi_o_of_cell(int p) { return (float(p) + 0.5f) * 1.57079633f / float(kPhiO); }

}  // namespace smis::ggx_aniso
