// Build-time generator of the multiple-scattering table of anisotropic multiscatter GGX
// (lobes/multiscatter_aniso_ggx.h): Heitz et al.'s random walk on the anisotropic microsurface as
// Cycles 3.4 runs it (scene/ggx_walk.h, walk(wi, ax, ay)), from a fixed seed, and where the walks of
// two or more bounces leave:
//
//   ggx_aniso_gen OUT.inc [WALKS [ROW]]   (ROW: a slice, the ROW-th pair rx <= ry; scene/tools/walk_rows.h)
//
// Why a table over both roughnesses: the stretch (x / alpha_x, y / alpha_y, z) maps the anisotropic
// microsurface onto the isotropic one of alpha 1 and keeps a ray a ray, so heights, masking (Lambda)
// and the visible normals are those of the stretched direction (that is how Lambda and the sampling
// are computed), but it does not keep reflection: the mirror direction about a normal, stretched, is
// not the mirror of the stretched direction about the stretched normal unless alpha_x = alpha_y. After
// the first bounce the walk is no longer the isotropic one stretched, so its multiple scattering
// depends on (alpha_x, alpha_y) and on the view's azimuth from the tangent, not on one alpha. (The
// previous attempt, the isotropic table at an averaged alpha, kept 71-119% of a white furnace.) What
// the walk does keep: the microsurface is symmetric under x -> -x and y -> -y (the view's azimuth is
// folded into [0, pi/2], the exit mirrored with it), and swapping x and y swaps alpha_x and alpha_y
// (phi -> pi/2 - phi): the rows alpha_x > alpha_y are the mirrored rows alpha_x < alpha_y, not walked.
//
// Writes, for roughness rows rx, ry (sqrt alpha = r / (kRough - 1), alpha clamped to 1e-4 as Cycles),
// the view at kThetaO x kPhiO nodes (polar angle from the normal, azimuth at cell centres), the exit in
// cells of cos_i^2 (equal projected solid angle) and of its azimuth phi_i in [0, 2 pi) from the tangent:
//   kAnisoBrdf[rx][ry][o][p][i][k]  the white BRDF of the multiple scattering f_ms (the cell's mean),
//   kAnisoEnergy[rx][ry][o][p]      its albedo from that view,
//   kAnisoAverage[rx][ry]           the albedo averaged over a cosine-weighted view (walks from views
//                                   drawn cosine-weighted: the nodes are not a quadrature),
//   kAnisoHalf[rx][ry]              that average with a colour of 0.5 applied at each bounce after the
//                                   first (as Cycles' walk does), over the white one.
// Deterministic (std::mt19937 per cell, seeded by its indices). Runs its rows on all cores (about 100 s
// of CPU); the build reads the copy committed as engine/scene/tables/ggx_aniso_table.inc.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "scene/ggx_aniso_layout.h"
#include "scene/ggx_walk.h"
#include "scene/tools/walk_rows.h"

using namespace smis;
using namespace smis::ggx_aniso;

namespace {

constexpr int kCells = kCosI * kPhiI;

struct Row {  // one (rx, ry) pair, rx <= ry
    std::vector<double> brdf = std::vector<double>(size_t(kThetaO * kPhiO * kCells), 0.0);
    std::vector<double> energy = std::vector<double>(size_t(kThetaO * kPhiO), 0.0);
    double white = 0.0, half = 0.0;
};

float alpha_of_row(int r) { return std::max(sqr(float(r) / float(kRough - 1)), 1e-4f); }

Row walk_row(int rx, int ry, long walks) {
    Row row;
    float ax = alpha_of_row(rx), ay = alpha_of_row(ry);
    for (int o = 0; o < kThetaO; ++o)
        for (int p = 0; p < kPhiO; ++p) {
            std::mt19937 gen(uint32_t(((rx * kRough + ry) * kThetaO + o) * kPhiO + p + 1));
            auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
            float theta = theta_o_of_node(o), phi_o = phi_o_of_cell(p), s = std::sin(theta);
            Vec3 wo(s * std::cos(phi_o), s * std::sin(phi_o), std::cos(theta));
            double white = 0.0;
            double* cells = &row.brdf[size_t((o * kPhiO + p) * kCells)];
            for (long n = 0; n < walks; ++n) {
                ggx_walk::Exit e = ggx_walk::walk(wo, ax, ay, rand);
                if (e.bounces < 2 || !(e.dir.z > 0.0f)) continue;
                int ci = std::min(int(e.dir.z * e.dir.z * kCosI), kCosI - 1);
                float d = std::atan2(e.dir.y, e.dir.x);
                while (d < 0.0f) d += 2.0f * kPi;
                int k = std::min(int(d / (2.0f * kPi) * kPhiI), kPhiI - 1);
                cells[ci * kPhiI + k] += 1.0;
                white += 1.0;
            }
            // A cell's projected solid angle: 1/kCosI of cos^2 over 2, 2 pi / kPhiI of azimuth.
            double measure = (1.0 / kCosI) * 0.5 * (2.0 * kPi / kPhiI);
            for (int c = 0; c < kCells; ++c) cells[c] /= double(walks) * measure;
            row.energy[size_t(o * kPhiO + p)] = white / double(walks);
        }
    // The averages over a cosine-weighted view: as many walks again, each from its own view.
    std::mt19937 gen(uint32_t((rx * kRough + ry) * 7919 + 3));
    auto rand = [&] { return float(gen() >> 8) * 0x1p-24f; };
    long views = walks * kThetaO * kPhiO / 4;
    for (long n = 0; n < views; ++n) {
        float mu = std::sqrt(rand()), phi = 2.0f * kPi * rand(), s = std::sqrt(1.0f - mu * mu);
        ggx_walk::Exit e = ggx_walk::walk(Vec3(s * std::cos(phi), s * std::sin(phi), mu), ax, ay, rand);
        if (e.bounces < 2 || !(e.dir.z > 0.0f)) continue;
        row.white += 1.0 / double(views);
        row.half += std::pow(0.5, e.bounces - 1) / double(views);
    }
    return row;
}

}  // namespace

int main(int argc, char** argv) {
    walk_rows::Args args;
    if (!walk_rows::parse(argc, argv, "ggx_aniso_gen", 300000, &args)) return 2;
    const long walks = args.walks;
    std::vector<std::pair<int, int>> pairs;
    for (int rx = 0; rx < kRough; ++rx)
        for (int ry = rx; ry < kRough; ++ry) pairs.push_back({rx, ry});
    Row unwalked;
    walk_rows::mark_not_walked(unwalked.brdf, unwalked.energy);
    unwalked.white = unwalked.half = walk_rows::kNotWalked;
    std::vector<Row> rows = walk_rows::run(int(pairs.size()), args, unwalked,
                                           [&](int j) { return walk_row(pairs[size_t(j)].first, pairs[size_t(j)].second, walks); });
    // The row of (rx, ry) and whether it is the mirror (x <-> y) of the walked row (ry, rx).
    auto row_of = [&](int rx, int ry, bool* mirrored) -> const Row& {
        *mirrored = rx > ry;
        int a = std::min(rx, ry), b = std::max(rx, ry);
        for (size_t j = 0; j < pairs.size(); ++j)
            if (pairs[j].first == a && pairs[j].second == b) return rows[j];
        return rows[0];
    };

    FILE* f = std::fopen(args.out, "w");
    if (!f) return 1;
    std::fprintf(f, "// Generated by ggx_aniso_gen (engine/scene/tools/ggx_aniso_gen.cpp), %ld walks per view.\n", walks);
    std::fprintf(f, "const float kAnisoBrdf[%d][%d][%d][%d][%d] = {\n", kRough * kRough, kThetaO, kPhiO, kCosI, kPhiI);
    for (int rx = 0; rx < kRough; ++rx)
        for (int ry = 0; ry < kRough; ++ry) {
            bool m;
            const Row& row = row_of(rx, ry, &m);
            std::fprintf(f, "{");
            for (int o = 0; o < kThetaO; ++o) {
                std::fprintf(f, "{");
                for (int p = 0; p < kPhiO; ++p) {
                    std::fprintf(f, "{");
                    int src_p = m ? kPhiO - 1 - p : p;
                    for (int i = 0; i < kCosI; ++i) {
                        std::fprintf(f, "{");
                        for (int k = 0; k < kPhiI; ++k) {
                            // phi -> pi/2 - phi: cell k from cell (kPhiI/4 - 1 - k) mod kPhiI
                            int src_k = m ? (kPhiI + kPhiI / 4 - 1 - k) % kPhiI : k;
                            std::fprintf(f, "%.5g,", row.brdf[size_t((o * kPhiO + src_p) * kCells + i * kPhiI + src_k)]);
                        }
                        std::fprintf(f, "},");
                    }
                    std::fprintf(f, "},\n");
                }
                std::fprintf(f, "},");
            }
            std::fprintf(f, "},\n");
        }
    std::fprintf(f, "};\nconst float kAnisoEnergy[%d][%d][%d] = {\n", kRough * kRough, kThetaO, kPhiO);
    for (int rx = 0; rx < kRough; ++rx)
        for (int ry = 0; ry < kRough; ++ry) {
            bool m;
            const Row& row = row_of(rx, ry, &m);
            std::fprintf(f, "{");
            for (int o = 0; o < kThetaO; ++o) {
                std::fprintf(f, "{");
                for (int p = 0; p < kPhiO; ++p)
                    std::fprintf(f, "%.6g,", row.energy[size_t(o * kPhiO + (m ? kPhiO - 1 - p : p))]);
                std::fprintf(f, "},");
            }
            std::fprintf(f, "},\n");
        }
    std::fprintf(f, "};\nconst float kAnisoAverage[%d] = {", kRough * kRough);
    for (int rx = 0; rx < kRough; ++rx)
        for (int ry = 0; ry < kRough; ++ry) {
            bool m;
            std::fprintf(f, "%.6g,", row_of(rx, ry, &m).white);
        }
    std::fprintf(f, "};\nconst float kAnisoHalf[%d] = {", kRough * kRough);
    for (int rx = 0; rx < kRough; ++rx)
        for (int ry = 0; ry < kRough; ++ry) {
            bool m;
            const Row& row = row_of(rx, ry, &m);
            std::fprintf(f, "%.6g,", row.white == 0.0 ? 0.5 : row.half / row.white);
        }
    std::fprintf(f, "};\n");
    return std::fclose(f) == 0 ? 0 : 1;
}
