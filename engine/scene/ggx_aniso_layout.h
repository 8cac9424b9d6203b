// The layout of the anisotropic multiscatter GGX table (scene/tools/ggx_aniso_gen.cpp writes it,
// scene/ggx_aniso.cpp reads it): rows of the two roughnesses, nodes of the view direction (its polar
// angle, and its azimuth from the tangent folded into the first quadrant) and of where the walk leaves (cos^2
// and its azimuth from the tangent, all the way round). The exit's azimuth is the tangent's, not the
// view's: the lobe is stretched along the tangent whatever the view, and interpolating between view
// cells then keeps that stretch (measured from the view's, it smeared it: <x^2 - y^2> of the exit 20-25%
// short of the walk's; 16 azimuths from the tangent's: 10-18% short; 32: 5-10%).
//
// The view's polar angle is sampled in theta, not in its cosine, and normal incidence is a node: where
// alpha_x and alpha_y differ, the exit's azimuthal profile turns from behind the view (cos theta_o 0.8)
// to across the tangent (normal incidence) over the last 20 degrees, evenly in theta (squeezed into
// 0.94-1 in cos theta). Cells centred on cos theta_o = (o + 0.5) / 8 left that range flat beyond 0.9375:
// 31% (cos 0.97) and 64% (cos 0.99) mean error per exit cell against fresh walks at alphas 0.18 / 1.
#pragma once

namespace smis::ggx_aniso {

constexpr int kRough = 8;   // roughness sqrt(alpha_x), sqrt(alpha_y) = r / (kRough - 1)
constexpr int kThetaO = 12;        // theta_o at the nodes o kThetaMax / (kThetaO - 1), o = 0 at the normal
constexpr float kThetaMax = 1.5f;  // the last node (cos 0.07); flat beyond it
constexpr int kPhiO = 4;    // phi_o from the tangent at the cell centres (p + 0.5) (pi / 2) / kPhiO
constexpr int kCosI = 8;    // cos^2 theta_i in [i, i + 1) / kCosI
constexpr int kPhiI = 32;   // phi_i in [k, k + 1) 2 pi / kPhiI (a multiple of 4: the x <-> y mirror)

inline float theta_o_of_node(int o) { return float(o) * kThetaMax / float(kThetaO - 1); }
inline float phi_o_of_cell(int p) { return (float(p) + 0.5f) * 1.57079633f / float(kPhiO); }

}  // namespace smis::ggx_aniso
