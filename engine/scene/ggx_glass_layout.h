// The layout of the multiscatter glass table (scene/tools/ggx_glass_gen.cpp writes it,
// scene/ggx_glass.cpp reads it): roughness rows, relative-IOR rows, incident-cosine cells, and the
// leaving cells on each side of the interface (cos^2 and the azimuth).
#pragma once

namespace smis::ggx_glass {

constexpr int kRough = 11;  // roughness sqrt(alpha) = r / 10
// The relative IOR e = eta (seen from the incident side) at the nodes kEtaNodes for eta >= 1, and
// 1 / kEtaNodes for eta < 1: rows k (eta >= 1) and kEta + k (eta < 1). Interpolated linearly in e.
constexpr int kEta = 9;
constexpr float kEtaNodes[kEta] = {1.0f, 1.15f, 1.3f, 1.45f, 1.6f, 1.8f, 2.0f, 2.4f, 3.0f};
constexpr int kEtaRows = 2 * kEta;
constexpr int kCosO = 12;   // cos theta_o at the cell centres (o + 0.5) / kCosO
constexpr int kSides = 2;   // 0: back on the incident side (reflection), 1: through (transmission)
constexpr int kCosI = 8;    // cos^2 theta_i in [i, i + 1) / kCosI, on that side
constexpr int kPhi = 6;     // |phi_i - phi_o| in [p, p + 1) pi / kPhi (0: wi on wo's side of the normal)

// The colour counts: bounces after the first (1 .. kBounceBins, the walk's at most 10 bounces).
constexpr int kBounceBins = 9;
// The Principled walk's colour, a polynomial in the base colour b (one factor per refraction) and the
// Specular Tint's cspec0 = x (one factor FH + (1 - FH) x per reflection, Cycles' interpolated Fresnel
// colour): its coefficient of b^n x^k, n + k <= kMaxWalkBounces, at term tint_term(n, k) (triangular).
constexpr int kMaxWalkBounces = 10;
constexpr int kTintTerms = (kMaxWalkBounces + 1) * (kMaxWalkBounces + 2) / 2;
constexpr int tint_term(int n, int k) { return n * (2 * kMaxWalkBounces + 3 - n) / 2 + k; }

inline float cos_o_of_cell(int o) { return (float(o) + 0.5f) / float(kCosO); }
// The relative IOR of row e.
inline float eta_of_row(int e) { return e < kEta ? kEtaNodes[e] : 1.0f / kEtaNodes[e - kEta]; }

}  // namespace smis::ggx_glass
