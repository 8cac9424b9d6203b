// Voronoi and Brick textures following Cycles 3.4's SVM kernels (svm/voronoi.h, svm/brick.h). The
// feature points come from Cycles' Jenkins lookup3 hashes of the cell coordinates' float bits, so
// the cells (and their colours) land exactly where Cycles puts them. Loops visit neighbour cells in
// Cycles' order (x fastest) because Smooth F1's blend and F2's tie-breaking depend on it.
//
// Speed: the feature points of a whole block of neighbour cells (3^N, or 5^N for Smooth F1) are
// hashed and measured first, as loops over arrays that the compiler vectorises; only the choice of
// the nearest point (and Smooth F1's blend) then runs cell by cell in Cycles' order. Each lane does
// the scalar code's operations, so the values are those of a cell-by-cell evaluation. The metric is
// a template parameter, so its switch is outside the loops. voronoi_texture is compiled twice
// (baseline x86-64 and AVX2, chosen at load time); AVX2 alone enables no FMA contraction, so both
// compute the same values.
#include "shading/procedural_cells.h"

#include "shading/lookup3.h"

#include <cstdint>
#include <cstring>

#define SMIS_CELLS_INLINE inline __attribute__((always_inline))
#define SMIS_CELLS_CLONES __attribute__((target_clones("avx2", "default")))
#if defined(__GNUC__) && !defined(__clang__)
#define SMIS_CELLS_NO_VECTORIZE __attribute__((optimize("no-tree-vectorize")))
#else
#define SMIS_CELLS_NO_VECTORIZE
#endif

namespace smis::shading {

namespace {

// ---- Cycles' hashes (util/hash.h): Bob Jenkins' lookup3 on the float bit patterns ----

SMIS_CELLS_INLINE uint32_t cell_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof(u));
    return u;
}

constexpr uint32_t kBitsOne = 0x3f800000u;  // 1.0f
constexpr uint32_t kBitsTwo = 0x40000000u;  // 2.0f

// [0, 2^32-1] -> [0, 1] inclusive, as Cycles' uint_to_float_incl.
SMIS_CELLS_INLINE float cell_uint_to_unit(uint32_t n) {
    return static_cast<float>(n) * (1.0f / static_cast<float>(0xFFFFFFFFu));
}

SMIS_CELLS_INLINE float cell_hash_float_to_float(float k) {
    return cell_uint_to_unit(lookup3::hash1(cell_bits(k)));
}

// ---- Neighbour blocks ----

constexpr int ipow(int b, int e) { return e == 0 ? 1 : b * ipow(b, e - 1); }

// The offsets of the (2R+1)^N cells around a cell, x varying fastest as Cycles' nested loops.
template <int N, int R> struct Block {
    static constexpr int K = ipow(2 * R + 1, N);
    static constexpr int kCentre = K / 2;  // the all-zero offset
    float off[N][K] = {};
};
template <int N, int R> constexpr Block<N, R> make_block() {
    Block<N, R> b;
    for (int k = 0; k < Block<N, R>::K; ++k) {
        int idx = k;
        for (int d = 0; d < N; ++d) {
            b.off[d][k] = static_cast<float>(idx % (2 * R + 1) - R);
            idx /= 2 * R + 1;
        }
    }
    return b;
}
template <int N, int R> constexpr Block<N, R> kBlock = make_block<N, R>();

// The hash keys (float bits of cell + offset) of K cells given as offsets from `cell`.
template <int N, int K>
SMIS_CELLS_INLINE void cell_keys(const float* cell, const float (&off)[N][K], uint32_t (&key)[N][K]) {
    for (int d = 0; d < N; ++d)
        for (int k = 0; k < K; ++k) key[d][k] = cell_bits(cell[d] + off[d][k]);
}

// Cycles' point hash per dimension (hash_float{,2,3,4}_to_float{,2,3,4}) of K keys, as raw uint32.
template <int N, int K>
SMIS_CELLS_INLINE void point_hashes(const uint32_t (&key)[N][K], uint32_t (&h)[N][K]) {
    for (int k = 0; k < K; ++k) {
        if constexpr (N == 1) {
            h[0][k] = lookup3::hash1(key[0][k]);
        } else if constexpr (N == 2) {
            h[0][k] = lookup3::hash2(key[0][k], key[1][k]);
            h[1][k] = lookup3::hash3(key[0][k], key[1][k], kBitsOne);
        } else if constexpr (N == 3) {
            h[0][k] = lookup3::hash3(key[0][k], key[1][k], key[2][k]);
            h[1][k] = lookup3::hash4(key[0][k], key[1][k], key[2][k], kBitsOne);
            h[2][k] = lookup3::hash4(key[0][k], key[1][k], key[2][k], kBitsTwo);
        } else {
            h[0][k] = lookup3::hash4(key[0][k], key[1][k], key[2][k], key[3][k]);
            h[1][k] = lookup3::hash4(key[3][k], key[0][k], key[1][k], key[2][k]);
            h[2][k] = lookup3::hash4(key[2][k], key[3][k], key[0][k], key[1][k]);
            h[3][k] = lookup3::hash4(key[1][k], key[2][k], key[3][k], key[0][k]);
        }
    }
}

// Cycles' cell colour hash per dimension (hash_float{,2,3,4}_to_float3) of one key. Its first
// components are the point hash's (all three in 3D), so callers holding those pass them in.
template <int N>
SMIS_CELLS_INLINE Vec3 cell_color(const uint32_t* key, const uint32_t* point_hash) {
    uint32_t c0 = point_hash[0], c1, c2;
    if constexpr (N == 1) {
        c1 = lookup3::hash2(key[0], kBitsOne);
        c2 = lookup3::hash2(key[0], kBitsTwo);
    } else if constexpr (N == 2) {
        c1 = point_hash[1];
        c2 = lookup3::hash3(key[0], key[1], kBitsTwo);
    } else if constexpr (N == 3) {
        c1 = point_hash[1];
        c2 = point_hash[2];
    } else {
        c1 = lookup3::hash4(key[2], key[0], key[3], key[1]);
        c2 = lookup3::hash4(key[3], key[2], key[1], key[0]);
    }
    return {cell_uint_to_unit(c0), cell_uint_to_unit(c1), cell_uint_to_unit(c2)};
}

// The feature points (offset + hash * randomness, relative to `cell`) of K cells, plus their keys and
// point hashes for the colour.
template <int N, int K> struct CellPoints {
    uint32_t key[N][K];
    uint32_t hash[N][K];
    float p[N][K];
};
template <int N, int K>
SMIS_CELLS_INLINE void feature_points(const float* cell, const float (&off)[N][K], float randomness,
                                      CellPoints<N, K>& cp) {
    cell_keys(cell, off, cp.key);
    point_hashes(cp.key, cp.hash);
    for (int d = 0; d < N; ++d)
        for (int k = 0; k < K; ++k) cp.p[d][k] = off[d][k] + cell_uint_to_unit(cp.hash[d][k]) * randomness;
}

// The colour of cell k of a CellPoints block.
template <int N, int K> SMIS_CELLS_INLINE Vec3 color_of(const CellPoints<N, K>& cp, int k) {
    uint32_t key[N], hash[N];
    for (int d = 0; d < N; ++d) key[d] = cp.key[d][k], hash[d] = cp.hash[d][k];
    return cell_color<N>(key, hash);
}

// Distance of feature point k to `local` (both relative to the cell) under metric M; 1D ignores the
// metric (Cycles' voronoi_distance_1d is always |b - a|). Sums start with their first term rather
// than 0 + it: squares, absolute values and their powers are never -0, so 0 + x == x.
template <VoronoiMetric M, int N, int K>
SMIS_CELLS_INLINE float metric_distance(const float (&p)[N][K], int k, const float* local, float exponent) {
    if constexpr (N == 1) {
        return std::fabs(local[0] - p[0][k]);
    } else if constexpr (M == VoronoiMetric::Euclidean) {
        float s = (p[0][k] - local[0]) * (p[0][k] - local[0]);
        for (int d = 1; d < N; ++d) s += (p[d][k] - local[d]) * (p[d][k] - local[d]);
        return std::sqrt(s);
    } else if constexpr (M == VoronoiMetric::Manhattan) {
        float s = std::fabs(p[0][k] - local[0]);
        for (int d = 1; d < N; ++d) s += std::fabs(p[d][k] - local[d]);
        return s;
    } else if constexpr (M == VoronoiMetric::Chebychev) {
        float m = std::fabs(p[N - 1][k] - local[N - 1]);
        for (int d = N - 2; d >= 0; --d) m = std::max(std::fabs(p[d][k] - local[d]), m);
        return m;
    } else {
        float s = std::pow(std::fabs(p[0][k] - local[0]), exponent);
        for (int d = 1; d < N; ++d) s += std::pow(std::fabs(p[d][k] - local[d]), exponent);
        return std::pow(s, 1.0f / exponent);
    }
}

template <VoronoiMetric M, int N, int K>
SMIS_CELLS_INLINE void distances(const CellPoints<N, K>& cp, const float* local, float exponent,
                                 float (&dist)[K]) {
    for (int k = 0; k < K; ++k) dist[k] = metric_distance<M, N, K>(cp.p, k, local, exponent);
}

// Euclidean length of a - b for N-vectors (|a - b| in 1D).
template <int N> SMIS_CELLS_INLINE float euclidean(const float* a, const float* b) {
    if constexpr (N == 1) {
        return std::fabs(a[0] - b[0]);
    } else {
        float s = (a[0] - b[0]) * (a[0] - b[0]);
        for (int d = 1; d < N; ++d) s += (a[d] - b[d]) * (a[d] - b[d]);
        return std::sqrt(s);
    }
}

SMIS_CELLS_INLINE float smoothstep01(float x) {
    if (x < 0.0f) return 0.0f;
    if (x >= 1.0f) return 1.0f;
    return (3.0f - 2.0f * x) * (x * x);
}

// Result in scaled space: position is absolute (cell + local), not yet divided by scale.
template <int N> struct CellResult {
    float distance = 0.0f;
    Vec3 color{0.0f};
    float position[N] = {};
    float radius = 0.0f;
};

template <int N> SMIS_CELLS_INLINE void split(const float* coord, float* cell, float* local) {
    for (int d = 0; d < N; ++d) {
        cell[d] = std::floor(coord[d]);
        local[d] = coord[d] - cell[d];
    }
}

// Colour and absolute position of block cell `k`; k < 0 (no distance below the initial 8, e.g. NaN
// input) stands for Cycles' zero-initialised offset and position: the cell itself, position = cell.
template <int N, int K>
SMIS_CELLS_INLINE void pick(const CellPoints<N, K>& cp, int k, const float* cell, CellResult<N>& r) {
    r.color = color_of(cp, k < 0 ? Block<N, 1>::kCentre : k);
    for (int d = 0; d < N; ++d) r.position[d] = (k < 0 ? 0.0f : cp.p[d][k]) + cell[d];
}

// The metric's distances of the feature points to `local`; metric values outside the enum
// (`no_metric`) measure every distance as 0, as Cycles' switch without a matching case does.
template <VoronoiMetric M, int N, int K>
SMIS_CELLS_INLINE void block_distances(const CellPoints<N, K>& cp, const float* local, float exponent,
                                       bool no_metric, float (&dist)[K]) {
    if (no_metric) {
        for (int k = 0; k < K; ++k) dist[k] = 0.0f;
        return;
    }
    distances<M>(cp, local, exponent, dist);
}

template <VoronoiMetric M, int N>
SMIS_CELLS_INLINE CellResult<N> voronoi_f1(const float* coord, float exponent, bool no_metric,
                                           float randomness) {
    using B = Block<N, 1>;
    float cell[N], local[N];
    split<N>(coord, cell, local);
    CellPoints<N, B::K> cp;
    feature_points(cell, kBlock<N, 1>.off, randomness, cp);
    float dist[B::K];
    block_distances<M>(cp, local, exponent, no_metric, dist);
    float min_distance = 8.0f;
    int best = -1;
    for (int k = 0; k < B::K; ++k)
        if (dist[k] < min_distance) min_distance = dist[k], best = k;
    CellResult<N> r;
    r.distance = min_distance;
    pick(cp, best, cell, r);
    return r;
}

template <VoronoiMetric M, int N>
SMIS_CELLS_INLINE CellResult<N> voronoi_f2(const float* coord, float exponent, bool no_metric,
                                           float randomness) {
    using B = Block<N, 1>;
    float cell[N], local[N];
    split<N>(coord, cell, local);
    CellPoints<N, B::K> cp;
    feature_points(cell, kBlock<N, 1>.off, randomness, cp);
    float dist[B::K];
    block_distances<M>(cp, local, exponent, no_metric, dist);
    float d1 = 8.0f, d2 = 8.0f;
    int i1 = -1, i2 = -1;
    for (int k = 0; k < B::K; ++k) {
        float d = dist[k];
        if (d < d1) {
            d2 = d1, i2 = i1;
            d1 = d, i1 = k;
        } else if (d < d2) {
            d2 = d, i2 = k;
        }
    }
    CellResult<N> r;
    r.distance = d2;
    pick(cp, i2, cell, r);
    return r;
}

// Smooth F1 blends every point of a 5^N block with a polynomial smooth minimum; smoothness is
// already halved and clamped to [0, 0.5] as the node does. The blend is a chain through the cells
// in order; the points and distances feeding it are computed beforehand.
//
// Most cells of the block are too far to contribute: their blend weight h is exactly 0 (their
// distance exceeds the running one by more than the smoothness). With finite distances such a
// cell changes nothing (the correction is +0 and x + 0 * (y - x) - 0 == x, the sums never being
// -0), so it is passed over, and colours are hashed only for the cells blended in (in 2D the
// block is small and the colours are cheaper hashed all at once, with the points).
template <VoronoiMetric M, int N>
SMIS_CELLS_INLINE CellResult<N> voronoi_smooth_f1(const float* coord, float smoothness, float exponent,
                                                  bool no_metric, float randomness) {
    using B = Block<N, 2>;
    constexpr int K = B::K;
    constexpr bool kColorsAhead = N == 2;
    float cell[N], local[N];
    split<N>(coord, cell, local);
    CellPoints<N, K> cp;
    feature_points(cell, kBlock<N, 2>.off, randomness, cp);
    float dist[K];
    block_distances<M>(cp, local, exponent, no_metric, dist);
    uint32_t color2[kColorsAhead ? K : 1];  // 2D: the third colour hash; the others are point hashes
    if constexpr (kColorsAhead)
        for (int k = 0; k < K; ++k) color2[k] = lookup3::hash3(cp.key[0][k], cp.key[1][k], kBitsTwo);

    const float correction_scale = 1.0f + 3.0f * smoothness;
    float smooth_distance = 8.0f;
    float sc[3] = {0.0f, 0.0f, 0.0f};
    float sp[N] = {};
    for (int k = 0; k < K; ++k) {
        float d = dist[k];
        float x = 0.5f + 0.5f * (smooth_distance - d) / smoothness;
        if (x < 0.0f && std::isfinite(d) && std::isfinite(smooth_distance)) continue;  // h == 0
        float h = smoothstep01(x);
        float correction = smoothness * h * (1.0f - h);
        smooth_distance = smooth_distance + h * (d - smooth_distance) - correction;
        correction /= correction_scale;
        Vec3 color;
        if constexpr (kColorsAhead)
            color = Vec3(cell_uint_to_unit(cp.hash[0][k]), cell_uint_to_unit(cp.hash[1][k]),
                         cell_uint_to_unit(color2[k]));
        else
            color = color_of(cp, k);
        for (int c = 0; c < 3; ++c) sc[c] = sc[c] + h * (color[c] - sc[c]) - correction;
        for (int i = 0; i < N; ++i) sp[i] = sp[i] + h * (cp.p[i][k] - sp[i]) - correction;
    }
    CellResult<N> r;
    r.distance = smooth_distance;
    r.color = Vec3(sc[0], sc[1], sc[2]);
    for (int i = 0; i < N; ++i) r.position[i] = cell[i] + sp[i];
    return r;
}

// Distance to the nearest Voronoi edge (always Euclidean), Quilez' two-pass method on a 3^N block;
// both passes visit the same feature points, so they are computed once.
template <int N> SMIS_CELLS_INLINE float voronoi_distance_to_edge(const float* coord, float randomness) {
    using B = Block<N, 1>;
    constexpr int K = B::K;
    float cell[N], local[N];
    split<N>(coord, cell, local);
    CellPoints<N, K> cp;
    feature_points(cell, kBlock<N, 1>.off, randomness, cp);
    float to_point[N][K], dist_sq[K];
    for (int d = 0; d < N; ++d)
        for (int k = 0; k < K; ++k) to_point[d][k] = cp.p[d][k] - local[d];
    for (int k = 0; k < K; ++k) {
        float s = 0.0f;
        for (int d = 0; d < N; ++d) s += to_point[d][k] * to_point[d][k];
        dist_sq[k] = s;
    }
    float min_distance = 8.0f;
    int closest = -1;
    for (int k = 0; k < K; ++k)
        if (dist_sq[k] < min_distance) min_distance = dist_sq[k], closest = k;
    float to_closest[N];
    for (int d = 0; d < N; ++d) to_closest[d] = closest < 0 ? 0.0f : to_point[d][closest];

    // Distance to the perpendicular bisector of the closest point and each other point.
    float edge[K];
    bool valid[K];
    for (int k = 0; k < K; ++k) {
        float perp[N], perp_sq = 0.0f;
        for (int d = 0; d < N; ++d) perp[d] = to_point[d][k] - to_closest[d];
        for (int d = 0; d < N; ++d) perp_sq += perp[d] * perp[d];
        valid[k] = perp_sq > 0.0001f;
        float len = std::sqrt(perp_sq);
        float e = 0.0f;
        for (int d = 0; d < N; ++d) e += ((to_closest[d] + to_point[d][k]) / 2.0f) * (perp[d] / len);
        edge[k] = e;
    }
    min_distance = 8.0f;
    for (int k = 0; k < K; ++k)
        if (valid[k]) min_distance = std::min(min_distance, edge[k]);
    return min_distance;
}

// 1D has its own edge rule: the midpoints towards the left and right neighbours' points.
SMIS_CELLS_INLINE float voronoi_distance_to_edge_1d(float w, float randomness) {
    float cell = std::floor(w);
    float local = w - cell;
    float mid = cell_hash_float_to_float(cell) * randomness;
    float left = -1.0f + cell_hash_float_to_float(cell - 1.0f) * randomness;
    float right = 1.0f + cell_hash_float_to_float(cell + 1.0f) * randomness;
    float to_left = std::fabs((mid + left) / 2.0f - local);
    float to_right = std::fabs((mid + right) / 2.0f - local);
    return std::min(to_left, to_right);
}

// Half the distance from the nearest point to its own nearest neighbour (Euclidean).
template <int N> SMIS_CELLS_INLINE float voronoi_n_sphere_radius(const float* coord, float randomness) {
    using B = Block<N, 1>;
    constexpr int K = B::K;
    float cell[N], local[N];
    split<N>(coord, cell, local);
    CellPoints<N, K> cp;
    feature_points(cell, kBlock<N, 1>.off, randomness, cp);
    float dist[K];
    for (int k = 0; k < K; ++k) {
        float p[N];
        for (int d = 0; d < N; ++d) p[d] = cp.p[d][k];
        dist[k] = euclidean<N>(p, local);
    }
    float min_distance = 8.0f;
    int best = -1;
    for (int k = 0; k < K; ++k)
        if (dist[k] < min_distance) min_distance = dist[k], best = k;
    float closest[N], closest_offset[N];
    for (int d = 0; d < N; ++d) {
        closest[d] = best < 0 ? 0.0f : cp.p[d][best];
        closest_offset[d] = best < 0 ? 0.0f : kBlock<N, 1>.off[d][best];
    }

    // The block around the closest point's cell (its own cell, the centre, is skipped).
    float off[N][K];
    for (int d = 0; d < N; ++d)
        for (int k = 0; k < K; ++k) off[d][k] = kBlock<N, 1>.off[d][k] + closest_offset[d];
    CellPoints<N, K> np;
    feature_points(cell, off, randomness, np);
    for (int k = 0; k < K; ++k) {
        float p[N];
        for (int d = 0; d < N; ++d) p[d] = np.p[d][k];
        dist[k] = euclidean<N>(closest, p);
    }
    min_distance = 8.0f;
    float closest_to_closest[N] = {};
    for (int k = 0; k < K; ++k) {
        if (k == B::kCentre) continue;
        if (dist[k] < min_distance) {
            min_distance = dist[k];
            for (int d = 0; d < N; ++d) closest_to_closest[d] = np.p[d][k];
        }
    }
    return euclidean<N>(closest_to_closest, closest) / 2.0f;
}

template <int N, VoronoiMetric M>
SMIS_CELLS_INLINE CellResult<N> voronoi_feature(const float* coord, VoronoiFeature feature,
                                                float smoothness, float exponent, bool no_metric,
                                                float randomness) {
    CellResult<N> r;
    switch (feature) {
        case VoronoiFeature::F1: return voronoi_f1<M, N>(coord, exponent, no_metric, randomness);
        case VoronoiFeature::F2: return voronoi_f2<M, N>(coord, exponent, no_metric, randomness);
        case VoronoiFeature::SmoothF1:
            return voronoi_smooth_f1<M, N>(coord, smoothness, exponent, no_metric, randomness);
        case VoronoiFeature::DistanceToEdge:
            if constexpr (N == 1) r.distance = voronoi_distance_to_edge_1d(coord[0], randomness);
            else r.distance = voronoi_distance_to_edge<N>(coord, randomness);
            return r;
        case VoronoiFeature::NSphereRadius:
            r.radius = voronoi_n_sphere_radius<N>(coord, randomness);
            return r;
    }
    return r;
}

// The metric as a template argument. 1D ignores it; Distance to Edge and N-Sphere Radius are always
// Euclidean.
template <int N>
SMIS_CELLS_INLINE CellResult<N> voronoi_nd(const float* coord, VoronoiFeature feature, VoronoiMetric metric,
                                           float smoothness, float exponent, float randomness) {
    using F = VoronoiFeature;
    using M = VoronoiMetric;
    if (N == 1 || feature == F::DistanceToEdge || feature == F::NSphereRadius) metric = M::Euclidean;
    const float sm = smoothness, ex = exponent, rn = randomness;
    switch (metric) {
        case M::Euclidean: return voronoi_feature<N, M::Euclidean>(coord, feature, sm, ex, false, rn);
        case M::Manhattan: return voronoi_feature<N, M::Manhattan>(coord, feature, sm, ex, false, rn);
        case M::Chebychev: return voronoi_feature<N, M::Chebychev>(coord, feature, sm, ex, false, rn);
        case M::Minkowski: return voronoi_feature<N, M::Minkowski>(coord, feature, sm, ex, false, rn);
    }
    return voronoi_feature<N, M::Euclidean>(coord, feature, sm, ex, true, rn);  // not a metric
}

// One function per dimension, so each has a stack frame of its own size; 2D-4D in two versions.
// 1D blocks have 3 or 5 cells, too few for vectors (the split into vector and scalar parts costs
// more than it saves), so 1D stays scalar.
SMIS_CELLS_NO_VECTORIZE CellResult<1> voronoi_1d(const float* coord, VoronoiFeature feature,
                                                  VoronoiMetric metric, float smoothness, float exponent,
                                                  float randomness) {
    return voronoi_nd<1>(coord, feature, metric, smoothness, exponent, randomness);
}
SMIS_CELLS_CLONES CellResult<2> voronoi_2d(const float* coord, VoronoiFeature feature, VoronoiMetric metric,
                                           float smoothness, float exponent, float randomness) {
    return voronoi_nd<2>(coord, feature, metric, smoothness, exponent, randomness);
}
SMIS_CELLS_CLONES CellResult<3> voronoi_3d(const float* coord, VoronoiFeature feature, VoronoiMetric metric,
                                           float smoothness, float exponent, float randomness) {
    return voronoi_nd<3>(coord, feature, metric, smoothness, exponent, randomness);
}
SMIS_CELLS_CLONES CellResult<4> voronoi_4d(const float* coord, VoronoiFeature feature, VoronoiMetric metric,
                                           float smoothness, float exponent, float randomness) {
    return voronoi_nd<4>(coord, feature, metric, smoothness, exponent, randomness);
}

SMIS_CELLS_INLINE float safe_divide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }

}  // namespace

VoronoiOut voronoi_texture(int dimensions, VoronoiFeature feature, VoronoiMetric metric,
                           const Vec3& co, float w, float scale, float smoothness, float exponent,
                           float randomness) {
    randomness = clampf(randomness, 0.0f, 1.0f);
    smoothness = clampf(smoothness / 2.0f, 0.0f, 0.5f);
    Vec3 p = co * scale;
    float pw = w * scale;

    VoronoiOut out;
    auto fill = [&](float distance, const Vec3& color, float radius) {
        out.distance = distance;
        out.color = color;
        out.radius = radius;
    };
    // Distance to Edge / N-Sphere Radius leave Position and W at zero.
    const bool has_position = feature == VoronoiFeature::F1 || feature == VoronoiFeature::F2 ||
                              feature == VoronoiFeature::SmoothF1;
    switch (dimensions) {
        case 1: {
            const float coord[1] = {pw};
            CellResult<1> r = voronoi_1d(coord, feature, metric, smoothness, exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position) out.w = safe_divide(r.position[0], scale);
            break;
        }
        case 2: {
            const float coord[2] = {p.x, p.y};
            CellResult<2> r = voronoi_2d(coord, feature, metric, smoothness, exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position)
                out.position =
                    Vec3(safe_divide(r.position[0], scale), safe_divide(r.position[1], scale), 0.0f);
            break;
        }
        case 3: {
            const float coord[3] = {p.x, p.y, p.z};
            CellResult<3> r = voronoi_3d(coord, feature, metric, smoothness, exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position)
                out.position = Vec3(safe_divide(r.position[0], scale), safe_divide(r.position[1], scale),
                                    safe_divide(r.position[2], scale));
            break;
        }
        case 4: {
            const float coord[4] = {p.x, p.y, p.z, pw};
            CellResult<4> r = voronoi_4d(coord, feature, metric, smoothness, exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position) {
                out.position = Vec3(safe_divide(r.position[0], scale), safe_divide(r.position[1], scale),
                                    safe_divide(r.position[2], scale));
                out.w = safe_divide(r.position[3], scale);
            }
            break;
        }
        default: break;
    }
    return out;
}

// ---- Brick ----

namespace {

// Cycles' brick_noise: a fast integer hash of the brick id, in [0, 1).
float brick_noise(uint32_t n) {
    n = (n + 1013u) & 0x7fffffffu;
    n = (n >> 13) ^ n;
    uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
    return 0.5f * (static_cast<float>(nn) / 1073741824.0f);
}

// Cycles' smoothstepf (clamped to [0, 1] outside the unit interval).
float brick_smoothstep(float f) {
    if (f <= 0.0f) return 0.0f;
    if (f >= 1.0f) return 1.0f;
    float ff = f * f;
    return 3.0f * ff - 2.0f * ff * f;
}

}  // namespace

BrickOut brick_texture(const Vec3& co, const Color& color1, const Color& color2, const Color& mortar,
                       float scale, float mortar_size, float mortar_smooth, float bias,
                       float brick_width, float row_height, float offset_amount, int offset_frequency,
                       float squash_amount, int squash_frequency) {
    const Vec3 p = co * scale;
    const int rownum = static_cast<int>(std::floor(p.y / row_height));
    float offset = 0.0f;
    if (offset_frequency && squash_frequency) {
        // Every squash_frequency-th row is narrower, every offset_frequency-th row shifted.
        brick_width *= (rownum % squash_frequency) ? 1.0f : squash_amount;
        offset = (rownum % offset_frequency) ? 0.0f : brick_width * offset_amount;
    }
    const int bricknum = static_cast<int>(std::floor((p.x + offset) / brick_width));
    const float x = (p.x + offset) - brick_width * static_cast<float>(bricknum);
    const float y = p.y - row_height * static_cast<float>(rownum);

    // The brick id packs the row into the high half, as Cycles' (rownum << 16) + (bricknum & 0xFFFF).
    const uint32_t id = (static_cast<uint32_t>(rownum) << 16) + (static_cast<uint32_t>(bricknum) & 0xFFFFu);
    const float tint = clampf(brick_noise(id) + bias, 0.0f, 1.0f);
    float min_dist = std::min(std::min(x, y), std::min(brick_width - x, row_height - y));

    float fac;
    if (min_dist >= mortar_size) {
        fac = 0.0f;
    } else if (mortar_smooth == 0.0f) {
        fac = 1.0f;
    } else {
        min_dist = 1.0f - min_dist / mortar_size;
        fac = brick_smoothstep(min_dist / mortar_smooth);
    }

    Color brick = color1;
    if (fac != 1.0f) brick = color1 * (1.0f - tint) + color2 * tint;
    BrickOut out;
    out.fac = fac;
    out.color = brick * (1.0f - fac) + mortar * fac;
    return out;
}

}  // namespace smis::shading
