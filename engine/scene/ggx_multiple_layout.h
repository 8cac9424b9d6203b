// The layout of the multiscatter GGX table (scene/tools/ggx_multiple_gen.cpp writes it,
// scene/ggx_multiple.cpp reads it): roughness rows, incident-cosine cells, leaving cells of cos^2 and
// of the azimuth.
#pragma once

namespace smis::ggx_multiple {

constexpr int kRough = 11;  // roughness sqrt(alpha) = r / 10
constexpr int kCosO = 12;   // cos theta_o at the cell centres (o + 0.5) / kCosO
constexpr int kCosI = 12;   // cos^2 theta_i in [i, i + 1) / kCosI
constexpr int kPhi = 8;     // |phi_i - phi_o| in [p, p + 1) pi / kPhi

inline float cos_o_of_cell(int o) { return (float(o) + 0.5f) / float(kCosO); }

}  // namespace smis::ggx_multiple
