// Build-time generator of the multiple-scattering table of multiscatter GGX glass
// (lobes/glass_multiple.h): for each roughness, relative IOR and incident cosine, the dielectric random
// walk of Cycles 3.4's multiscatter glass (scene/ggx_walk.h, glass_walk) from a fixed seed, and where
// the walks of two or more bounces leave:
//
//   ggx_glass_gen OUT.inc [WALKS [ROW]]   (ROW = roughness x 18 + IOR row: a slice, scene/tools/walk_rows.h)
//
// writes, with the layout of scene/ggx_glass_layout.h (leaving cells of cos_i^2 and of the azimuth
// |phi| in [0, pi] from wo's, on each side s of the interface):
//   kGlassBsdf[r][e][o][s][i][p]  the white BSDF of the multiple scattering, f_ms (no cosine), as
//                                 sampled by the walk (an energy density: no radiance scaling),
//   kGlassEnergy[r][e][o][s]      its albedo on side s, the sum over the cells of f_ms times their
//                                 projected measure,
//   kGlassBounces[r][e][o][s][k]     of that albedo, the share of the walks with k + 1 bounces after
//                                    the first (the Glass BSDF's walk colours each),
//                                    so that a colour c gives sum_k share_k c^k,
//   kGlassTint[r][e][o][s][t]        and the Principled BSDF's walk colour as a polynomial: its mean
//                                    coefficient of b^n x^k at t = tint_term(n, k) (ggx_glass_layout.h),
//                                    b the base colour (each refraction), x = cspec0 (each reflection
//                                    multiplies by Cycles' interpolated Fresnel colour FH + (1 - FH) x,
//                                    FH = (F(cos_i, eta) - F0) / (1 - F0) at its microfacet, F0 = F(1, eta),
//                                    eta the walk's own relative IOR: mf_sample's interpolate_fresnel_color),
//                                    so that Specular Tint t gives sum b^n (1 - t + t b)^k per channel.
// Deterministic: the same file on every machine (std::mt19937, its 32-bit outputs turned into floats
// by hand). Runs its rows on all cores; the build reads the copy committed as
// engine/scene/tables/ggx_glass_table.inc.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "scene/ggx_glass_layout.h"
#include "scene/ggx_walk.h"
#include "scene/tools/walk_rows.h"

using namespace smis;
using namespace smis::ggx_glass;

namespace {

constexpr int kCells = kSides * kCosI * kPhi;

struct Row {  // one roughness and relative IOR
    std::vector<double> bsdf = std::vector<double>(size_t(kCosO * kCells), 0.0);
    std::vector<double> energy = std::vector<double>(size_t(kCosO * kSides), 0.0);
    double bounces[kCosO][kSides][kBounceBins] = {}, tint[kCosO][kSides][kTintTerms] = {};
};

// One walk's Principled colour: the coefficients p[k] of x^k of prod_j (FH_j + (1 - FH_j) x) over its
// reflections, and its number of refractions.
struct WalkTint {
    double p[kMaxWalkBounces + 1] = {1.0};
    int reflections = 0, refractions = 0;
    float eta, f0;
    explicit WalkTint(float eta) : eta(eta), f0(ggx_walk::dielectric_fresnel(1.0f, eta)) {}
    void operator()(float cos_i, bool refracted) {
        if (refracted) {
            ++refractions;
            return;
        }
        double fh = f0 < 1.0f ? (double(ggx_walk::dielectric_fresnel(cos_i, eta)) - f0) / (1.0 - f0) : 1.0;
        ++reflections;
        for (int k = reflections; k >= 0; --k) p[k] = fh * p[k] + (k > 0 ? (1.0 - fh) * p[k - 1] : 0.0);
    }
};

Row walk_row(int r, int e, long walks) {
    Row row;
    float alpha = std::max(sqr(float(r) / float(kRough - 1)), 1e-4f);  // Cycles clamps alpha to 1e-4
    float eta = eta_of_row(e);
    for (int o = 0; o < kCosO; ++o) {
        std::mt19937 gen(uint32_t(100000 * r + 1000 * e + o + 1));
        auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
        float mu = cos_o_of_cell(o);
        Vec3 wi(std::sqrt(1.0f - mu * mu), 0.0f, mu);
        double white[kSides] = {0.0, 0.0};
        auto& bounces = row.bounces[o];
        auto& tint = row.tint[o];
        for (long k = 0; k < walks; ++k) {
            WalkTint colour(eta);
            ggx_walk::GlassExit x = ggx_walk::glass_walk(wi, alpha, eta, rand, colour);
            if (x.bounces < 2 || x.dir.z == 0.0f) continue;
            int s = x.dir.z > 0.0f ? 0 : 1;
            int ci = std::min(int(x.dir.z * x.dir.z * kCosI), kCosI - 1);
            float phi = std::atan2(std::fabs(x.dir.y), x.dir.x);  // wi's azimuth is 0
            int cp = std::min(int(phi / kPi * kPhi), kPhi - 1);
            row.bsdf[size_t(o * kCells + (s * kCosI + ci) * kPhi + cp)] += 1.0;
            white[s] += 1.0;
            bounces[s][std::min(x.bounces - 2, kBounceBins - 1)] += 1.0;
            for (int k = 0; k <= colour.reflections; ++k) tint[s][tint_term(colour.refractions, k)] += colour.p[k];
        }
        // A cell's projected solid angle: 1/kCosI of cos^2 over 2, pi/kPhi of azimuth, on both sides of wo's plane.
        double measure = (1.0 / kCosI) * 0.5 * (kPi / kPhi) * 2.0;
        for (int c = 0; c < kCells; ++c) row.bsdf[size_t(o * kCells + c)] /= double(walks) * measure;
        for (int s = 0; s < kSides; ++s) {
            row.energy[size_t(o * kSides + s)] = white[s] / double(walks);
            // The counts as shares of this side's walks; where none left here, all at the first bin.
            for (int k = 0; k < kBounceBins; ++k) bounces[s][k] = white[s] > 0.0 ? bounces[s][k] / white[s] : k == 0;
            for (int k = 0; k < kTintTerms; ++k) tint[s][k] = white[s] > 0.0 ? tint[s][k] / white[s] : k == 0;
        }
    }
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    walk_rows::Args args;
    if (!walk_rows::parse(argc, argv, "ggx_glass_gen", 100000, &args)) return 2;
    const long walks = args.walks;
    Row unwalked;
    walk_rows::mark_not_walked(unwalked.bsdf, unwalked.energy);
    for (auto& per_side : unwalked.bounces) walk_rows::mark_not_walked(per_side[0], per_side[1]);
    for (auto& per_side : unwalked.tint) walk_rows::mark_not_walked(per_side[0], per_side[1]);
    std::vector<Row> rows = walk_rows::run(kRough * kEtaRows, args, unwalked,
                                           [&](int k) { return walk_row(k / kEtaRows, k % kEtaRows, walks); });

    FILE* f = std::fopen(args.out, "w");
    if (!f) return 1;
    std::fprintf(f, "// Generated by ggx_glass_gen (engine/scene/tools/ggx_glass_gen.cpp), %ld walks per row.\n", walks);
    std::fprintf(f, "const float kGlassBsdf[%d][%d][%d][%d][%d][%d] = {\n", kRough, kEtaRows, kCosO, kSides, kCosI, kPhi);
    for (size_t k = 0; k < rows.size(); ++k) {
        const Row& row = rows[k];
        std::fprintf(f, "%s{", k % kEtaRows == 0 ? "{" : "");
        for (int o = 0; o < kCosO; ++o) {
            std::fprintf(f, "{");
            for (int s = 0; s < kSides; ++s) {
                std::fprintf(f, "{");
                for (int i = 0; i < kCosI; ++i) {
                    std::fprintf(f, "{");
                    for (int p = 0; p < kPhi; ++p)
                        std::fprintf(f, "%.5g,", row.bsdf[size_t(o * kCells + (s * kCosI + i) * kPhi + p)]);
                    std::fprintf(f, "},");
                }
                std::fprintf(f, "},");
            }
            std::fprintf(f, "},\n");
        }
        std::fprintf(f, "},%s\n", k % kEtaRows == kEtaRows - 1 ? "}," : "");
    }
    std::fprintf(f, "};\nconst float kGlassEnergy[%d][%d][%d][%d] = {\n", kRough, kEtaRows, kCosO, kSides);
    for (size_t k = 0; k < rows.size(); ++k) {
        const Row& row = rows[k];
        std::fprintf(f, "%s{", k % kEtaRows == 0 ? "{" : "");
        for (int o = 0; o < kCosO; ++o)
            std::fprintf(f, "{%.6g,%.6g},", row.energy[size_t(o * kSides)], row.energy[size_t(o * kSides + 1)]);
        std::fprintf(f, "},%s\n", k % kEtaRows == kEtaRows - 1 ? "}," : "");
    }
    auto shares = [&](const char* name, int bins, auto&& share) {
        std::fprintf(f, "};\nconst float %s[%d][%d][%d][%d][%d] = {\n", name, kRough, kEtaRows, kCosO, kSides, bins);
        for (size_t k = 0; k < rows.size(); ++k) {
            std::fprintf(f, "%s{", k % kEtaRows == 0 ? "{" : "");
            for (int o = 0; o < kCosO; ++o) {
                std::fprintf(f, "{");
                for (int s = 0; s < kSides; ++s) {
                    std::fprintf(f, "{");
                    for (int b = 0; b < bins; ++b) std::fprintf(f, "%.5g,", share(rows[k], o, s, b));
                    std::fprintf(f, "},");
                }
                std::fprintf(f, "},");
            }
            std::fprintf(f, "},%s\n", k % kEtaRows == kEtaRows - 1 ? "}," : "");
        }
    };
    shares("kGlassBounces", kBounceBins, [](const Row& row, int o, int s, int b) { return row.bounces[o][s][b]; });
    shares("kGlassTint", kTintTerms, [](const Row& row, int o, int s, int b) { return row.tint[o][s][b]; });
    std::fprintf(f, "};\n");
    return std::fclose(f) == 0 ? 0 : 1;
}
