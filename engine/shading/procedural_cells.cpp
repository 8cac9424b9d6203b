// Voronoi and Brick textures following Cycles 3.4's SVM kernels (svm/voronoi.h, svm/brick.h). The
// feature points come from Cycles' Jenkins lookup3 hashes of the cell coordinates' float bits, so
// the cells (and their colours) land exactly where Cycles puts them. Loops visit neighbour cells in
// Cycles' order (x fastest) because Smooth F1's blend and F2's tie-breaking depend on it.
#include "shading/procedural_cells.h"

#include <cstdint>
#include <cstring>

namespace smis::shading {

namespace {

// ---- Cycles' hashes (util/hash.h): Bob Jenkins' lookup3 on the float bit patterns ----

inline uint32_t cell_rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

inline void cell_mix(uint32_t& a, uint32_t& b, uint32_t& c) {
    a -= c; a ^= cell_rot(c, 4);  c += b;
    b -= a; b ^= cell_rot(a, 6);  a += c;
    c -= b; c ^= cell_rot(b, 8);  b += a;
    a -= c; a ^= cell_rot(c, 16); c += b;
    b -= a; b ^= cell_rot(a, 19); a += c;
    c -= b; c ^= cell_rot(b, 4);  b += a;
}

inline void cell_final(uint32_t& a, uint32_t& b, uint32_t& c) {
    c ^= b; c -= cell_rot(b, 14);
    a ^= c; a -= cell_rot(c, 11);
    b ^= a; b -= cell_rot(a, 25);
    c ^= b; c -= cell_rot(b, 16);
    a ^= c; a -= cell_rot(c, 4);
    b ^= a; b -= cell_rot(a, 14);
    c ^= b; c -= cell_rot(b, 24);
}

uint32_t cell_hash_uint(uint32_t kx) {
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (1u << 2) + 13u;
    a += kx;
    cell_final(a, b, c);
    return c;
}

uint32_t cell_hash_uint2(uint32_t kx, uint32_t ky) {
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (2u << 2) + 13u;
    b += ky;
    a += kx;
    cell_final(a, b, c);
    return c;
}

uint32_t cell_hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz) {
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (3u << 2) + 13u;
    c += kz;
    b += ky;
    a += kx;
    cell_final(a, b, c);
    return c;
}

uint32_t cell_hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (4u << 2) + 13u;
    a += kx;
    b += ky;
    c += kz;
    cell_mix(a, b, c);
    a += kw;
    cell_final(a, b, c);
    return c;
}

inline uint32_t cell_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof(u));
    return u;
}

// [0, 2^32-1] -> [0, 1] inclusive, as Cycles' uint_to_float_incl.
inline float cell_uint_to_unit(uint32_t n) { return static_cast<float>(n) * (1.0f / static_cast<float>(0xFFFFFFFFu)); }

float cell_hash_float_to_float(float k) { return cell_uint_to_unit(cell_hash_uint(cell_bits(k))); }
float cell_hash_float2_to_float(float x, float y) {
    return cell_uint_to_unit(cell_hash_uint2(cell_bits(x), cell_bits(y)));
}
float cell_hash_float3_to_float(float x, float y, float z) {
    return cell_uint_to_unit(cell_hash_uint3(cell_bits(x), cell_bits(y), cell_bits(z)));
}
float cell_hash_float4_to_float(float x, float y, float z, float w) {
    return cell_uint_to_unit(cell_hash_uint4(cell_bits(x), cell_bits(y), cell_bits(z), cell_bits(w)));
}

Vec3 cell_hash_float_to_float3(float k) {
    return {cell_hash_float_to_float(k), cell_hash_float2_to_float(k, 1.0f),
            cell_hash_float2_to_float(k, 2.0f)};
}
Vec3 cell_hash_float2_to_float3(float x, float y) {
    return {cell_hash_float2_to_float(x, y), cell_hash_float3_to_float(x, y, 1.0f),
            cell_hash_float3_to_float(x, y, 2.0f)};
}
Vec3 cell_hash_float3_to_float3(float x, float y, float z) {
    return {cell_hash_float3_to_float(x, y, z), cell_hash_float4_to_float(x, y, z, 1.0f),
            cell_hash_float4_to_float(x, y, z, 2.0f)};
}
Vec3 cell_hash_float4_to_float3(float x, float y, float z, float w) {
    return {cell_hash_float4_to_float(x, y, z, w), cell_hash_float4_to_float(z, x, w, y),
            cell_hash_float4_to_float(w, z, y, x)};
}

// ---- N-dimensional helpers ----

template <int N>
struct VecN {
    float v[N] = {};
    float& operator[](int i) { return v[i]; }
    float operator[](int i) const { return v[i]; }
};

template <int N>
VecN<N> add(const VecN<N>& a, const VecN<N>& b) {
    VecN<N> r;
    for (int i = 0; i < N; ++i) r[i] = a[i] + b[i];
    return r;
}
template <int N>
VecN<N> sub(const VecN<N>& a, const VecN<N>& b) {
    VecN<N> r;
    for (int i = 0; i < N; ++i) r[i] = a[i] - b[i];
    return r;
}
template <int N>
float dotn(const VecN<N>& a, const VecN<N>& b) {
    float s = 0.0f;
    for (int i = 0; i < N; ++i) s += a[i] * b[i];
    return s;
}

// Cycles' point hash per dimension: hash_float{,2,3,4}_to_float{,2,3,4}.
template <int N>
VecN<N> cell_point_hash(const VecN<N>& k);
template <>
VecN<1> cell_point_hash<1>(const VecN<1>& k) { return {{cell_hash_float_to_float(k[0])}}; }
template <>
VecN<2> cell_point_hash<2>(const VecN<2>& k) {
    return {{cell_hash_float2_to_float(k[0], k[1]), cell_hash_float3_to_float(k[0], k[1], 1.0f)}};
}
template <>
VecN<3> cell_point_hash<3>(const VecN<3>& k) {
    Vec3 h = cell_hash_float3_to_float3(k[0], k[1], k[2]);
    return {{h.x, h.y, h.z}};
}
template <>
VecN<4> cell_point_hash<4>(const VecN<4>& k) {
    return {{cell_hash_float4_to_float(k[0], k[1], k[2], k[3]),
             cell_hash_float4_to_float(k[3], k[0], k[1], k[2]),
             cell_hash_float4_to_float(k[2], k[3], k[0], k[1]),
             cell_hash_float4_to_float(k[1], k[2], k[3], k[0])}};
}

// Cycles' cell colour hash per dimension: hash_float{,2,3,4}_to_float3.
template <int N>
Vec3 cell_color_hash(const VecN<N>& k);
template <>
Vec3 cell_color_hash<1>(const VecN<1>& k) { return cell_hash_float_to_float3(k[0]); }
template <>
Vec3 cell_color_hash<2>(const VecN<2>& k) { return cell_hash_float2_to_float3(k[0], k[1]); }
template <>
Vec3 cell_color_hash<3>(const VecN<3>& k) { return cell_hash_float3_to_float3(k[0], k[1], k[2]); }
template <>
Vec3 cell_color_hash<4>(const VecN<4>& k) { return cell_hash_float4_to_float3(k[0], k[1], k[2], k[3]); }

template <int N>
float euclidean(const VecN<N>& a, const VecN<N>& b) {
    if (N == 1) return std::fabs(a[0] - b[0]);
    VecN<N> d = sub(a, b);
    return std::sqrt(dotn(d, d));
}

// 1D ignores the metric (Cycles' voronoi_distance_1d is always |b - a|).
template <int N>
float metric_distance(const VecN<N>& a, const VecN<N>& b, VoronoiMetric metric, float exponent) {
    if (N == 1) return std::fabs(b[0] - a[0]);
    switch (metric) {
        case VoronoiMetric::Euclidean: return euclidean(a, b);
        case VoronoiMetric::Manhattan: {
            float s = 0.0f;
            for (int i = 0; i < N; ++i) s += std::fabs(a[i] - b[i]);
            return s;
        }
        case VoronoiMetric::Chebychev: {
            float m = std::fabs(a[N - 1] - b[N - 1]);
            for (int i = N - 2; i >= 0; --i) m = std::max(std::fabs(a[i] - b[i]), m);
            return m;
        }
        case VoronoiMetric::Minkowski: {
            float s = 0.0f;
            for (int i = 0; i < N; ++i) s += std::pow(std::fabs(a[i] - b[i]), exponent);
            return std::pow(s, 1.0f / exponent);
        }
    }
    return 0.0f;
}

constexpr int ipow(int b, int e) { return e == 0 ? 1 : b * ipow(b, e - 1); }

// Offset of neighbour number idx in a (2r+1)^N block, x varying fastest as Cycles' nested loops.
template <int N>
VecN<N> neighbour_offset(int idx, int r) {
    VecN<N> o;
    int side = 2 * r + 1;
    for (int i = 0; i < N; ++i) {
        o[i] = static_cast<float>(idx % side - r);
        idx /= side;
    }
    return o;
}

template <int N>
VecN<N> feature_point(const VecN<N>& cell, const VecN<N>& offset, float randomness) {
    VecN<N> h = cell_point_hash<N>(add(cell, offset));
    VecN<N> p;
    for (int i = 0; i < N; ++i) p[i] = offset[i] + h[i] * randomness;
    return p;
}

inline float smoothstep01(float x) {
    if (x < 0.0f) return 0.0f;
    if (x >= 1.0f) return 1.0f;
    return (3.0f - 2.0f * x) * (x * x);
}

// Result in scaled space: position is absolute (cell + local), not yet divided by scale.
template <int N>
struct CellResult {
    float distance = 0.0f;
    Vec3 color{0.0f};
    VecN<N> position;
    float radius = 0.0f;
};

template <int N>
void split(const VecN<N>& coord, VecN<N>& cell, VecN<N>& local) {
    for (int i = 0; i < N; ++i) {
        cell[i] = std::floor(coord[i]);
        local[i] = coord[i] - cell[i];
    }
}

template <int N>
CellResult<N> voronoi_f1(const VecN<N>& coord, float exponent, float randomness, VoronoiMetric metric) {
    VecN<N> cell, local;
    split(coord, cell, local);
    float min_distance = 8.0f;
    VecN<N> target_offset, target_position;
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 1);
        VecN<N> p = feature_point(cell, off, randomness);
        float d = metric_distance(p, local, metric, exponent);
        if (d < min_distance) {
            target_offset = off;
            min_distance = d;
            target_position = p;
        }
    }
    CellResult<N> r;
    r.distance = min_distance;
    r.color = cell_color_hash<N>(add(cell, target_offset));
    r.position = add(target_position, cell);
    return r;
}

template <int N>
CellResult<N> voronoi_f2(const VecN<N>& coord, float exponent, float randomness, VoronoiMetric metric) {
    VecN<N> cell, local;
    split(coord, cell, local);
    float d1 = 8.0f, d2 = 8.0f;
    VecN<N> off1, pos1, off2, pos2;
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 1);
        VecN<N> p = feature_point(cell, off, randomness);
        float d = metric_distance(p, local, metric, exponent);
        if (d < d1) {
            d2 = d1;
            d1 = d;
            off2 = off1;
            off1 = off;
            pos2 = pos1;
            pos1 = p;
        } else if (d < d2) {
            d2 = d;
            off2 = off;
            pos2 = p;
        }
    }
    CellResult<N> r;
    r.distance = d2;
    r.color = cell_color_hash<N>(add(cell, off2));
    r.position = add(pos2, cell);
    return r;
}

// Smooth F1 blends every point of a 5^N block with a polynomial smooth minimum; smoothness is
// already halved and clamped to [0, 0.5] as the node does.
template <int N>
CellResult<N> voronoi_smooth_f1(const VecN<N>& coord, float smoothness, float exponent,
                                float randomness, VoronoiMetric metric) {
    VecN<N> cell, local;
    split(coord, cell, local);
    float smooth_distance = 8.0f;
    Vec3 smooth_color(0.0f);
    VecN<N> smooth_position;
    for (int idx = 0; idx < ipow(5, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 2);
        VecN<N> p = feature_point(cell, off, randomness);
        float d = metric_distance(p, local, metric, exponent);
        float h = smoothstep01(0.5f + 0.5f * (smooth_distance - d) / smoothness);
        float correction = smoothness * h * (1.0f - h);
        smooth_distance = smooth_distance + h * (d - smooth_distance) - correction;
        correction /= 1.0f + 3.0f * smoothness;
        Vec3 c = cell_color_hash<N>(add(cell, off));
        smooth_color = smooth_color + h * (c - smooth_color) - Vec3(correction);
        for (int i = 0; i < N; ++i)
            smooth_position[i] = smooth_position[i] + h * (p[i] - smooth_position[i]) - correction;
    }
    CellResult<N> r;
    r.distance = smooth_distance;
    r.color = smooth_color;
    r.position = add(cell, smooth_position);
    return r;
}

// Distance to the nearest Voronoi edge (always Euclidean), Quilez' two-pass method on a 3^N block.
template <int N>
float voronoi_distance_to_edge(const VecN<N>& coord, float randomness) {
    VecN<N> cell, local;
    split(coord, cell, local);
    VecN<N> to_closest;
    float min_distance = 8.0f;
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 1);
        VecN<N> to_point = sub(feature_point(cell, off, randomness), local);
        float d = dotn(to_point, to_point);
        if (d < min_distance) {
            min_distance = d;
            to_closest = to_point;
        }
    }
    min_distance = 8.0f;
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 1);
        VecN<N> to_point = sub(feature_point(cell, off, randomness), local);
        VecN<N> perp = sub(to_point, to_closest);
        float perp_sq = dotn(perp, perp);
        if (perp_sq > 0.0001f) {
            float len = std::sqrt(perp_sq);
            VecN<N> mid, dir;
            for (int i = 0; i < N; ++i) {
                mid[i] = (to_closest[i] + to_point[i]) / 2.0f;
                dir[i] = perp[i] / len;
            }
            min_distance = std::min(min_distance, dotn(mid, dir));
        }
    }
    return min_distance;
}

// 1D has its own edge rule: the midpoints towards the left and right neighbours' points.
float voronoi_distance_to_edge_1d(float w, float randomness) {
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
template <int N>
float voronoi_n_sphere_radius(const VecN<N>& coord, float randomness) {
    VecN<N> cell, local;
    split(coord, cell, local);
    VecN<N> closest, closest_offset;
    float min_distance = 8.0f;
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        VecN<N> off = neighbour_offset<N>(idx, 1);
        VecN<N> p = feature_point(cell, off, randomness);
        float d = euclidean(p, local);
        if (d < min_distance) {
            min_distance = d;
            closest = p;
            closest_offset = off;
        }
    }
    min_distance = 8.0f;
    VecN<N> closest_to_closest;
    const int centre = ipow(3, N) / 2;  // the all-zero offset
    for (int idx = 0; idx < ipow(3, N); ++idx) {
        if (idx == centre) continue;
        VecN<N> off = add(neighbour_offset<N>(idx, 1), closest_offset);
        VecN<N> p = feature_point(cell, off, randomness);
        float d = euclidean(closest, p);
        if (d < min_distance) {
            min_distance = d;
            closest_to_closest = p;
        }
    }
    return euclidean(closest_to_closest, closest) / 2.0f;
}

template <int N>
CellResult<N> voronoi_dispatch(const VecN<N>& coord, VoronoiFeature feature, VoronoiMetric metric,
                               float smoothness, float exponent, float randomness) {
    CellResult<N> r;
    switch (feature) {
        case VoronoiFeature::F1: return voronoi_f1(coord, exponent, randomness, metric);
        case VoronoiFeature::F2: return voronoi_f2(coord, exponent, randomness, metric);
        case VoronoiFeature::SmoothF1:
            return voronoi_smooth_f1(coord, smoothness, exponent, randomness, metric);
        case VoronoiFeature::DistanceToEdge:
            r.distance = N == 1 ? voronoi_distance_to_edge_1d(coord[0], randomness)
                                : voronoi_distance_to_edge(coord, randomness);
            return r;
        case VoronoiFeature::NSphereRadius:
            r.radius = voronoi_n_sphere_radius(coord, randomness);
            return r;
    }
    return r;
}

inline float safe_divide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }

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
            CellResult<1> r = voronoi_dispatch<1>({{pw}}, feature, metric, smoothness, exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position) out.w = safe_divide(r.position[0], scale);
            break;
        }
        case 2: {
            CellResult<2> r = voronoi_dispatch<2>({{p.x, p.y}}, feature, metric, smoothness, exponent,
                                                  randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position)
                out.position = Vec3(safe_divide(r.position[0], scale), safe_divide(r.position[1], scale), 0.0f);
            break;
        }
        case 3: {
            CellResult<3> r = voronoi_dispatch<3>({{p.x, p.y, p.z}}, feature, metric, smoothness,
                                                  exponent, randomness);
            fill(r.distance, r.color, r.radius);
            if (has_position)
                out.position = Vec3(safe_divide(r.position[0], scale), safe_divide(r.position[1], scale),
                                    safe_divide(r.position[2], scale));
            break;
        }
        case 4: {
            CellResult<4> r = voronoi_dispatch<4>({{p.x, p.y, p.z, pw}}, feature, metric, smoothness,
                                                  exponent, randomness);
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
