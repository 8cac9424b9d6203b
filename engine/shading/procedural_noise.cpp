// Noise-family procedural textures matching Blender 3.4 Cycles (see procedural_noise.h).
//
// Bit-exactness: Blender runs Cycles' AVX2 CPU kernel on current x86 CPUs. That kernel is built with
// -ffast-math -mfma, so some multiply-adds are fused (explicitly in its SIMD Perlin code, by compiler
// contraction elsewhere). Rounding differences matter more than usual here: high noise octaves scale
// coordinates by up to 2^15, so a 1-ulp difference in a distorted coordinate becomes a different
// noise value. fmadd() below reproduces a fused multiply-add exactly where the kernel fuses (found by
// comparing against renders bit for bit); every other expression must stay unfused, so compiler
// contraction is switched off for this file (it would fuse on -mfma / -march=native builds).
//
// Speed: Perlin noise is evaluated for all the points a texture needs at once (every octave of a
// fractal sum, the colour's extra sums, the distortion's axes), step by step as loops over points
// and lattice corners that the compiler vectorises; the lookup3 hashes are integer code, the
// gradients branch-free bit selects, and fmadd's double arithmetic vectorises too. The sums then
// run in Cycles' order on the precomputed values. The public entry points are compiled twice
// (baseline x86-64 and AVX2, chosen at load time). Every lane and both versions perform exactly
// the scalar IEEE operations (AVX2 alone brings no FMA instructions to contract into), so values
// are unchanged; the build adds -fno-math-errno -fno-trapping-math, which change no value either.
#include "shading/procedural_noise.h"

#include "shading/lookup3.h"

#include <cmath>
#include <cstring>

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

// The sums are forced inline down to the lattice code, so that each version of the entry points
// carries its own vectorised copy (a call would go to the baseline version).
#define SMIS_NOISE_INLINE inline __attribute__((always_inline))
#define SMIS_NOISE_CLONES __attribute__((target_clones("avx2", "default")))

namespace smis::shading {

namespace {

constexpr float kTwoPi = 2.0f * kPi;

using lookup3::hash1;
using lookup3::hash2;
using lookup3::hash3;
using lookup3::hash4;

// [0, 2^32-1] -> [0, 1] (inclusive), as Cycles' uint_to_float_incl.
SMIS_NOISE_INLINE float unit_incl(uint32_t n) {
    return static_cast<float>(n) * (1.0f / static_cast<float>(0xFFFFFFFFu));
}

constexpr uint32_t kBitsOne = 0x3f800000u;  // 1.0f
constexpr uint32_t kBitsTwo = 0x40000000u;  // 2.0f

// Cycles' hash_float{,2,3,4}_to_float3 on float bit patterns (three independent hashes).
SMIS_NOISE_INLINE Vec3 hash_bits_to_float3(uint32_t x) {
    return {unit_incl(hash1(x)), unit_incl(hash2(x, kBitsOne)),
            unit_incl(hash2(x, kBitsTwo))};
}
SMIS_NOISE_INLINE Vec3 hash_bits_to_float3(uint32_t x, uint32_t y) {
    return {unit_incl(hash2(x, y)), unit_incl(hash3(x, y, kBitsOne)),
            unit_incl(hash3(x, y, kBitsTwo))};
}
SMIS_NOISE_INLINE Vec3 hash_bits_to_float3(uint32_t x, uint32_t y, uint32_t z) {
    return {unit_incl(hash3(x, y, z)), unit_incl(hash4(x, y, z, kBitsOne)),
            unit_incl(hash4(x, y, z, kBitsTwo))};
}
SMIS_NOISE_INLINE Vec3 hash_bits_to_float3(uint32_t x, uint32_t y, uint32_t z, uint32_t w) {
    // Cycles permutes the components for the later channels.
    return {unit_incl(hash4(x, y, z, w)), unit_incl(hash4(z, x, w, y)),
            unit_incl(hash4(w, z, y, x))};
}

SMIS_NOISE_INLINE uint32_t float_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// floor(x) as an int plus the fractional part. Out-of-range and NaN inputs give INT_MIN, which is what
// the x86 conversion Cycles' CPU kernels rely on returns (a plain cast would be undefined here).
SMIS_NOISE_INLINE float floorfrac(float x, int* i) {
    float f = std::floor(x);
    *i = (f >= -2147483648.0f && f < 2147483648.0f) ? static_cast<int>(f) : INT32_MIN;
    return x - f;
}

SMIS_NOISE_INLINE uint32_t u(int i) { return static_cast<uint32_t>(i); }

// a * b + c rounded once. The float product is exact in double and the sum rarely rounds twice, so
// this is a fused multiply-add without needing FMA hardware (double arithmetic costs as much as float).
SMIS_NOISE_INLINE float fmadd(float a, float b, float c) {
    return static_cast<float>(static_cast<double>(a) * static_cast<double>(b) + static_cast<double>(c));
}

// Linear interpolation as Cycles' SIMD kernels do it (2D-4D noise): t * b + (1 - t) * a, fused.
SMIS_NOISE_INLINE float mixf(float a, float b, float t) { return fmadd(t, b, (1.0f - t) * a); }

// Quintic fade 6t^5 - 15t^4 + 10t^3 with the SIMD kernels' fused Horner steps; 1D noise (scalar in
// Cycles) multiplies the final product in a different order.
SMIS_NOISE_INLINE float fade_poly(float t) { return fmadd(t, fmadd(t, 6.0f, -15.0f), 10.0f); }
SMIS_NOISE_INLINE float fade(float t) { return (t * t) * (t * fade_poly(t)); }
SMIS_NOISE_INLINE float fade_1d(float t) { return t * t * t * fade_poly(t); }

SMIS_NOISE_INLINE float bits_float(uint32_t u) {
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
}

// Branch-free building blocks for the gradients: the corner hashes are random, so branches on them
// would be mispredicted half the time, and bit selects let the corner loops vectorise. Both give
// the values of the plain `cond ? a : b` / `cond ? -v : v`, NaN and signed zeros included.
SMIS_NOISE_INLINE uint32_t select_bits(bool cond, uint32_t a, uint32_t b) {
    uint32_t m = 0u - static_cast<uint32_t>(cond);
    return (a & m) | (b & ~m);
}
// Flips the sign of v when `bit` (a power of two) is set in h.
SMIS_NOISE_INLINE uint32_t negate_if_bit(uint32_t v, uint32_t h, uint32_t bit) {
    return v ^ ((h & bit) ? 0x80000000u : 0u);
}
SMIS_NOISE_INLINE float negate_if(float v, uint32_t h, uint32_t bit) {
    return bits_float(negate_if_bit(float_bits(v), h, bit));
}

SMIS_NOISE_INLINE float ensure_finite(float v) { return std::isfinite(v) ? v : 0.0f; }

SMIS_NOISE_INLINE float saturate(float v) { return clampf(v, 0.0f, 1.0f); }

// Perlin's improved-noise gradients, one table per dimension as in Cycles.
SMIS_NOISE_INLINE float grad1(uint32_t hash, float x) {
    uint32_t h = hash & 15u;
    float g = static_cast<float>(1u + (h & 7u));
    return negate_if(g, h, 8u) * x;
}

SMIS_NOISE_INLINE float grad2(uint32_t hash, float x, float y) {
    uint32_t h = hash & 7u, xb = float_bits(x), yb = float_bits(y);
    float a = bits_float(negate_if_bit(select_bits(h < 4, xb, yb), h, 1u));
    float b = 2.0f * bits_float(select_bits(h < 4, yb, xb));
    return a + negate_if(b, h, 2u);
}

SMIS_NOISE_INLINE float grad3(uint32_t hash, float x, float y, float z) {
    uint32_t h = hash & 15u, xb = float_bits(x), yb = float_bits(y), zb = float_bits(z);
    uint32_t a = select_bits(h < 8, xb, yb);
    uint32_t vt = select_bits(h == 12 || h == 14, xb, zb);
    uint32_t b = select_bits(h < 4, yb, vt);
    return bits_float(negate_if_bit(a, h, 1u)) + bits_float(negate_if_bit(b, h, 2u));
}

SMIS_NOISE_INLINE float grad4(uint32_t hash, float x, float y, float z, float w) {
    uint32_t h = hash & 31u, xb = float_bits(x), yb = float_bits(y), zb = float_bits(z), wb = float_bits(w);
    uint32_t a = select_bits(h < 24, xb, yb);
    uint32_t b = select_bits(h < 16, yb, zb);
    uint32_t c = select_bits(h < 8, zb, wb);
    return bits_float(negate_if_bit(a, h, 1u)) + bits_float(negate_if_bit(b, h, 2u)) +
           bits_float(negate_if_bit(c, h, 4u));
}

// ---- Perlin noise ----
// Points of 1..4 dimensions, so the sums below are written once (Cycles repeats them per dimension
// with identical bodies).
template <int D> struct Pt {
    float v[D];
    SMIS_NOISE_INLINE Pt operator*(float s) const {
        Pt r;
        for (int d = 0; d < D; ++d) r.v[d] = v[d] * s;
        return r;
    }
    SMIS_NOISE_INLINE Pt operator+(const Pt& o) const {
        Pt r;
        for (int d = 0; d < D; ++d) r.v[d] = v[d] + o.v[d];
        return r;
    }
};
using P1 = Pt<1>;
using P2 = Pt<2>;
using P3 = Pt<3>;
using P4 = Pt<4>;

// Factors that remap Perlin noise's actual range to about [-1, 1], per dimension.
constexpr float kNoiseScale[5] = {0.0f, 0.2500f, 0.6616f, 0.9820f, 0.8344f};

// The fractal sums need the noise of up to 16 points (detail 15: 16 octaves; below: up to 15 and a
// blended one), the noise texture's colour three such sums.
constexpr int kMaxOctaves = 16;

// Perlin noise at pts[0..n) (n <= MaxN) into out, non-finite results replaced by 0. All points are
// evaluated together, step by step, as loops over points and lattice corners: the steps of
// different points are independent, so they vectorise (the corner loops: 4 lanes on baseline
// x86-64, 8 in the AVX2 clones) and overlap instead of forming one long dependency chain per octave.
// Every lane performs the scalar code's operations, so values do not change. Corner i of a point
// has offset bit k of i along the axis noted at each function; corner hash keys are (X + dx) as
// unsigned, two's complement wrap-around as the kernel's int arithmetic gives.
//
// Points are passed as n * D coordinates, point after point (PointList).
template <int D, int MaxN> struct PointList {
    float c[D * MaxN];
    int n = 0;
    SMIS_NOISE_INLINE void push(const Pt<D>& p) {
        for (int d = 0; d < D; ++d) c[n * D + d] = p.v[d];
        ++n;
    }
};

// Lattice cell (floor as an int), position in the cell and its fade weight of n * D coordinates.
template <int D>
SMIS_NOISE_INLINE void lattice_cells(const float* coords, int n, uint32_t* cell, float* frac, float* fade_t) {
    for (int j = 0; j < n * D; ++j) {
        int i;
        float t = floorfrac(coords[j], &i);
        cell[j] = u(i);
        frac[j] = t;
        fade_t[j] = D == 1 ? fade_1d(t) : fade(t);
    }
}

template <int MaxN> SMIS_NOISE_INLINE void perlin_batch_1d(const float* coords, int n, float* out) {
    uint32_t X[MaxN], h[2 * MaxN];
    float fx[MaxN], s[MaxN];
    lattice_cells<1>(coords, n, X, fx, s);
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 2; ++i) h[2 * k + i] = hash1(X[k] + static_cast<uint32_t>(i));
    for (int k = 0; k < n; ++k) {
        float a = grad1(h[2 * k], fx[k]), b = grad1(h[2 * k + 1], fx[k] - 1.0f);
        out[k] = ensure_finite(a + s[k] * (b - a));  // scalar code in Cycles: not fused
    }
}

// Corner i = dy + 2 dx: the x interpolation (done first, as in Cycles' SIMD kernels) pairs i, i + 2.
template <int MaxN> SMIS_NOISE_INLINE void perlin_batch_2d(const float* coords, int n, float* out) {
    uint32_t c[2 * MaxN], h[4 * MaxN];
    float f[2 * MaxN], s[2 * MaxN], g[4 * MaxN];
    lattice_cells<2>(coords, n, c, f, s);
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 4; ++i)
            h[4 * k + i] = hash2(c[2 * k] + static_cast<uint32_t>(i >> 1),
                                          c[2 * k + 1] + static_cast<uint32_t>(i & 1));
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 4; ++i)
            g[4 * k + i] = grad2(h[4 * k + i], f[2 * k] - static_cast<float>(i >> 1),
                                 f[2 * k + 1] - static_cast<float>(i & 1));
    for (int k = 0; k < n; ++k) {
        const float* gk = g + 4 * k;
        float a = mixf(gk[0], gk[2], s[2 * k]), b = mixf(gk[1], gk[3], s[2 * k]);
        out[k] = ensure_finite(mixf(a, b, s[2 * k + 1]));
    }
}

// Corner i = dz + 2 dy + 4 dx; interpolated along x, then y, then z.
template <int MaxN> SMIS_NOISE_INLINE void perlin_batch_3d(const float* coords, int n, float* out) {
    uint32_t c[3 * MaxN], h[8 * MaxN];
    float f[3 * MaxN], s[3 * MaxN], g[8 * MaxN], a[4 * MaxN];
    lattice_cells<3>(coords, n, c, f, s);
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 8; ++i)
            h[8 * k + i] = hash3(c[3 * k] + static_cast<uint32_t>(i >> 2),
                                          c[3 * k + 1] + static_cast<uint32_t>((i >> 1) & 1),
                                          c[3 * k + 2] + static_cast<uint32_t>(i & 1));
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 8; ++i)
            g[8 * k + i] = grad3(h[8 * k + i], f[3 * k] - static_cast<float>(i >> 2),
                                 f[3 * k + 1] - static_cast<float>((i >> 1) & 1),
                                 f[3 * k + 2] - static_cast<float>(i & 1));
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 4; ++i)  // a[dz + 2 dy]
            a[4 * k + i] = mixf(g[8 * k + i], g[8 * k + i + 4], s[3 * k]);
    for (int k = 0; k < n; ++k) {
        const float* ak = a + 4 * k;
        float lo = mixf(ak[0], ak[2], s[3 * k + 1]), hi = mixf(ak[1], ak[3], s[3 * k + 1]);
        out[k] = ensure_finite(mixf(lo, hi, s[3 * k + 2]));
    }
}

// Corner i = dx + 2 dy + 4 dz + 8 dw. Cycles' AVX kernel interpolates along w first, then x, y, z.
template <int MaxN> SMIS_NOISE_INLINE void perlin_batch_4d(const float* coords, int n, float* out) {
    uint32_t c[4 * MaxN], h[16 * MaxN];
    float f[4 * MaxN], s[4 * MaxN], g[16 * MaxN], e[8 * MaxN];
    lattice_cells<4>(coords, n, c, f, s);
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 16; ++i)
            h[16 * k + i] = hash4(c[4 * k] + static_cast<uint32_t>(i & 1),
                                           c[4 * k + 1] + static_cast<uint32_t>((i >> 1) & 1),
                                           c[4 * k + 2] + static_cast<uint32_t>((i >> 2) & 1),
                                           c[4 * k + 3] + static_cast<uint32_t>(i >> 3));
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 16; ++i)
            g[16 * k + i] = grad4(h[16 * k + i], f[4 * k] - static_cast<float>(i & 1),
                                  f[4 * k + 1] - static_cast<float>((i >> 1) & 1),
                                  f[4 * k + 2] - static_cast<float>((i >> 2) & 1),
                                  f[4 * k + 3] - static_cast<float>(i >> 3));
    for (int k = 0; k < n; ++k)
        for (int i = 0; i < 8; ++i)  // c[dx + 2 dy + 4 dz]
            e[8 * k + i] = mixf(g[16 * k + i], g[16 * k + i + 8], s[4 * k + 3]);
    for (int k = 0; k < n; ++k) {
        const float* ek = e + 8 * k;
        float y0 = mixf(ek[0], ek[1], s[4 * k]), y1 = mixf(ek[2], ek[3], s[4 * k]);  // [dy + 2 dz]
        float y2 = mixf(ek[4], ek[5], s[4 * k]), y3 = mixf(ek[6], ek[7], s[4 * k]);
        float z0 = mixf(y0, y1, s[4 * k + 1]), z1 = mixf(y2, y3, s[4 * k + 1]);
        out[k] = ensure_finite(mixf(z0, z1, s[4 * k + 2]));
    }
}

// Signed noise (Cycles' snoise) and unsigned noise from a Perlin value of D dimensions.
template <int D> SMIS_NOISE_INLINE float snoise_of(float perlin) { return kNoiseScale[D] * perlin; }
template <int D> SMIS_NOISE_INLINE float unoise_of(float perlin) {
    return 0.5f * snoise_of<D>(perlin) + 0.5f;
}
// snoise + offset with the scale multiply fused into the add (Musgrave's terrain types).
template <int D> SMIS_NOISE_INLINE float snoise_plus_of(float perlin, float offset) {
    return fmadd(kNoiseScale[D], perlin, offset);
}

template <int D, int MaxN>
SMIS_NOISE_INLINE void perlin_batch(const PointList<D, MaxN>& pts, float* out) {
    if constexpr (D == 1) perlin_batch_1d<MaxN>(pts.c, pts.n, out);
    if constexpr (D == 2) perlin_batch_2d<MaxN>(pts.c, pts.n, out);
    if constexpr (D == 3) perlin_batch_3d<MaxN>(pts.c, pts.n, out);
    if constexpr (D == 4) perlin_batch_4d<MaxN>(pts.c, pts.n, out);
}

template <int D> SMIS_NOISE_INLINE float perlin(const Pt<D>& p) {
    PointList<D, 1> pts;
    pts.push(p);
    float r;
    perlin_batch(pts, &r);
    return r;
}

// ---- Fractal noise ----
// The points a fractal sum samples: p scaled by 1, 2, 4, ...; returns their count.
template <int D, int MaxN>
SMIS_NOISE_INLINE int fractal_points(const Pt<D>& p, float octaves, PointList<D, MaxN>& pts) {
    octaves = clampf(octaves, 0.0f, 15.0f);
    int n = static_cast<int>(octaves) + 1 + (octaves - std::floor(octaves) != 0.0f ? 1 : 0);
    float fscale = 1.0f;
    for (int i = 0; i < n; ++i) {
        pts.push(p * fscale);
        fscale *= 2.0f;
    }
    return n;
}

// The normalised sum of the octaves' unsigned noise, from the Perlin values at fractal_points.
template <int D>
SMIS_NOISE_INLINE float fractal_sum(const float* perlin, float octaves, float roughness) {
    float amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
    octaves = clampf(octaves, 0.0f, 15.0f);
    int n = static_cast<int>(octaves);
    for (int i = 0; i <= n; ++i) {
        float t = unoise_of<D>(perlin[i]);
        sum = fmadd(t, amp, sum);
        maxamp += amp;
        amp *= clampf(roughness, 0.0f, 1.0f);
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd == 0.0f) return sum / maxamp;
    // Fractional detail: blend the normalised sums without and with one more octave.
    float t = unoise_of<D>(perlin[n + 1]);
    float sum2 = fmadd(t, amp, sum);
    sum /= maxamp;
    sum2 /= maxamp + amp;
    return fmadd(1.0f - rmd, sum, rmd * sum2);
}

template <int D> SMIS_NOISE_INLINE float fractal(const Pt<D>& p, float octaves, float roughness) {
    PointList<D, kMaxOctaves> pts;
    float noise[kMaxOctaves];
    fractal_points(p, octaves, pts);
    perlin_batch(pts, noise);
    return fractal_sum<D>(noise, octaves, roughness);
}

// ---- Musgrave (F. K. Musgrave's terrain functions as Cycles 3.4 has them) ----
// Octave i samples p * lacunarity^i (repeatedly multiplied, as Cycles does). The Perlin values of
// all the octaves a type uses are computed together first, then summed in Cycles' order.
constexpr int kMaxMusgraveOctaves = 16;  // detail <= 15, plus the blended octave

// How many octaves each type samples; `octaves` is the clamped detail.
SMIS_NOISE_INLINE int musgrave_octave_count(MusgraveType type, float octaves) {
    const int whole = static_cast<int>(octaves);
    const int blended = octaves - std::floor(octaves) != 0.0f ? 1 : 0;
    switch (type) {
        case MusgraveType::Fbm:
        case MusgraveType::Multifractal:
        // Hybrid stops early once its weight is small; its octaves are cheap enough together that
        // computing all of them costs less than the first one alone did before.
        case MusgraveType::HybridMultifractal: return whole + blended;
        case MusgraveType::RidgedMultifractal: return std::max(whole, 1);  // never blended
        case MusgraveType::HeteroTerrain: return std::max(whole, 1) + blended;  // first one always
    }
    return 0;
}

template <int D>
SMIS_NOISE_INLINE float musgrave_fbm(const float* noise, float H, float lacunarity, float octaves) {
    float value = 0.0f, pwr = 1.0f;
    float pwHL = std::pow(lacunarity, -H);
    const int whole = static_cast<int>(octaves);
    for (int i = 0; i < whole; ++i) {
        value = fmadd(snoise_of<D>(noise[i]), pwr, value);
        pwr *= pwHL;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) value = fmadd(rmd * snoise_of<D>(noise[whole]), pwr, value);
    return value;
}

template <int D>
SMIS_NOISE_INLINE float musgrave_multifractal(const float* noise, float H, float lacunarity, float octaves) {
    float value = 1.0f, pwr = 1.0f;
    float pwHL = std::pow(lacunarity, -H);
    const int whole = static_cast<int>(octaves);
    for (int i = 0; i < whole; ++i) {
        value *= fmadd(pwr, snoise_of<D>(noise[i]), 1.0f);
        pwr *= pwHL;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) value *= fmadd(rmd * pwr, snoise_of<D>(noise[whole]), 1.0f);
    return value;
}

template <int D>
SMIS_NOISE_INLINE float musgrave_hetero_terrain(const float* noise, float H, float lacunarity, float octaves,
                                                float offset) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    // The first octave is unscaled; later ones are scaled by the running value.
    float value = snoise_plus_of<D>(noise[0], offset);
    const int whole = std::max(static_cast<int>(octaves), 1);
    for (int i = 1; i < whole; ++i) {
        value = fmadd(snoise_plus_of<D>(noise[i], offset) * pwr, value, value);  // value += increment
        pwr *= pwHL;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) {
        float increment = snoise_plus_of<D>(noise[whole], offset) * pwr * value;
        value = fmadd(rmd, increment, value);
    }
    return value;
}

template <int D>
SMIS_NOISE_INLINE float musgrave_hybrid_multifractal(const float* noise, float H, float lacunarity,
                                                     float octaves, float offset, float gain) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = 1.0f, value = 0.0f, weight = 1.0f;
    const int whole = static_cast<int>(octaves);
    for (int i = 0; weight > 0.001f && i < whole; ++i) {
        if (weight > 1.0f) weight = 1.0f;
        float signal = snoise_plus_of<D>(noise[i], offset) * pwr;
        pwr *= pwHL;
        value = fmadd(weight, signal, value);
        weight *= gain * signal;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f && weight > 0.001f) {  // only reached with all whole octaves taken
        if (weight > 1.0f) weight = 1.0f;
        float signal = snoise_plus_of<D>(noise[whole], offset) * pwr;
        value = fmadd(rmd * weight, signal, value);
    }
    return value;
}

// Cycles 3.4's ridged multifractal ignores the fractional part of the octave count.
template <int D>
SMIS_NOISE_INLINE float musgrave_ridged_multifractal(const float* noise, float H, float lacunarity,
                                                     float octaves, float offset, float gain) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    float signal = offset - std::fabs(snoise_of<D>(noise[0]));
    signal *= signal;
    float value = signal;
    float weight = 1.0f;
    const int whole = static_cast<int>(octaves);
    for (int i = 1; i < whole; ++i) {
        weight = saturate(signal * gain);
        signal = offset - std::fabs(snoise_of<D>(noise[i]));
        signal *= signal;
        signal *= weight;
        value = fmadd(signal, pwr, value);
        pwr *= pwHL;
    }
    return value;
}

template <int D>
SMIS_NOISE_INLINE float musgrave(MusgraveType type, Pt<D> p, float H, float lacunarity, float octaves,
                                 float offset, float gain) {
    PointList<D, kMaxMusgraveOctaves> pts;
    for (int i = 0, n = musgrave_octave_count(type, octaves); i < n; ++i) {
        pts.push(p);
        p = p * lacunarity;
    }
    float noise[kMaxMusgraveOctaves];
    perlin_batch(pts, noise);
    switch (type) {
        case MusgraveType::Multifractal: return musgrave_multifractal<D>(noise, H, lacunarity, octaves);
        case MusgraveType::Fbm: return musgrave_fbm<D>(noise, H, lacunarity, octaves);
        case MusgraveType::HybridMultifractal:
            return musgrave_hybrid_multifractal<D>(noise, H, lacunarity, octaves, offset, gain);
        case MusgraveType::RidgedMultifractal:
            return musgrave_ridged_multifractal<D>(noise, H, lacunarity, octaves, offset, gain);
        case MusgraveType::HeteroTerrain:
            return musgrave_hetero_terrain<D>(noise, H, lacunarity, octaves, offset);
    }
    return 0.0f;
}

// ---- Noise texture ----
// Random offsets (in [100, 200]) that decorrelate the noise texture's distortion and colour channels:
// per seed 0..5, 1D's offset and the 2D-4D components 0..3. They depend on nothing else, so they are
// computed once.
struct RandomOffsets {
    float one[6];
    float comp[6][4];
};
const RandomOffsets& random_offsets() {
    static const RandomOffsets table = [] {
        RandomOffsets t{};
        for (int seed = 0; seed < 6; ++seed) {
            float s = static_cast<float>(seed);
            t.one[seed] = 100.0f + hash_float_to_float(s) * 100.0f;
            for (int c = 0; c < 4; ++c)
                t.comp[seed][c] = 100.0f + hash_float2_to_float(s, static_cast<float>(c)) * 100.0f;
        }
        return t;
    }();
    return table;
}
template <int D> SMIS_NOISE_INLINE Pt<D> random_offset(const RandomOffsets& t, int seed) {
    Pt<D> r;
    for (int d = 0; d < D; ++d) r.v[d] = D == 1 ? t.one[seed] : t.comp[seed][d];
    return r;
}

// Distortion displaces each axis by signed noise at a per-axis random offset; seeds 0..D-1 are used
// for the D axes, then D and D+1 for the colour's green and blue channels. The kernel fuses the
// displacement's multiply-add in 1D, 2D and 4D but not in 3D.
template <int D> SMIS_NOISE_INLINE Pt<D> distort(const Pt<D>& p, float d) {
    const RandomOffsets& t = random_offsets();
    PointList<D, D> pts;
    float noise[D];
    for (int a = 0; a < D; ++a) pts.push(p + random_offset<D>(t, a));
    perlin_batch(pts, noise);
    Pt<D> r;
    for (int a = 0; a < D; ++a) {
        float n = snoise_of<D>(noise[a]);
        r.v[a] = D == 3 ? p.v[a] + n * d : fmadd(n, d, p.v[a]);
    }
    return r;
}

template <int D>
SMIS_NOISE_INLINE TextureOut noise_texture_nd(Pt<D> p, float detail, float roughness, float distortion,
                                              bool color) {
    if (distortion != 0.0f) p = distort(p, distortion);
    // The value's fractal sum and, when the colour is read (Cycles skips it otherwise), the colour's
    // green and blue sums at offset points.
    PointList<D, 3 * kMaxOctaves> pts;
    float noise[3 * kMaxOctaves];
    int n = fractal_points(p, detail, pts);
    if (color) {
        const RandomOffsets& t = random_offsets();
        fractal_points(p + random_offset<D>(t, D), detail, pts);
        fractal_points(p + random_offset<D>(t, D + 1), detail, pts);
    }
    perlin_batch(pts, noise);
    TextureOut out;
    out.fac = fractal_sum<D>(noise, detail, roughness);
    if (color)
        out.color = Color(out.fac, fractal_sum<D>(noise + n, detail, roughness),
                          fractal_sum<D>(noise + 2 * n, detail, roughness));
    return out;
}

}  // namespace

// ---- Hashes ----

uint32_t hash_uint(uint32_t kx) { return hash1(kx); }
uint32_t hash_uint2(uint32_t kx, uint32_t ky) { return hash2(kx, ky); }
uint32_t hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz) { return hash3(kx, ky, kz); }
uint32_t hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    return hash4(kx, ky, kz, kw);
}

float uint_to_float_incl(uint32_t n) { return unit_incl(n); }

float uint_to_float_excl(uint32_t n) {
    // 4294967808 rather than 2^32 so that the largest input still rounds below 1.
    return static_cast<float>(n) * (1.0f / 4294967808.0f);
}

float hash_uint_to_float(uint32_t kx) { return uint_to_float_incl(hash_uint(kx)); }
float hash_uint2_to_float(uint32_t kx, uint32_t ky) { return uint_to_float_incl(hash_uint2(kx, ky)); }
float hash_uint3_to_float(uint32_t kx, uint32_t ky, uint32_t kz) {
    return uint_to_float_incl(hash_uint3(kx, ky, kz));
}
float hash_uint4_to_float(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    return uint_to_float_incl(hash_uint4(kx, ky, kz, kw));
}

float hash_float_to_float(float k) { return hash_uint_to_float(float_bits(k)); }
float hash_float2_to_float(float x, float y) {
    return hash_uint2_to_float(float_bits(x), float_bits(y));
}
float hash_float3_to_float(const Vec3& k) {
    return hash_uint3_to_float(float_bits(k.x), float_bits(k.y), float_bits(k.z));
}
float hash_float4_to_float(const Vec3& k, float w) {
    return hash_uint4_to_float(float_bits(k.x), float_bits(k.y), float_bits(k.z), float_bits(w));
}

Float2 hash_float2_to_float2(float x, float y) {
    return {hash_float2_to_float(x, y), hash_float3_to_float(Vec3(x, y, 1.0f))};
}

Vec3 hash_float3_to_float3(const Vec3& k) {
    return hash_bits_to_float3(float_bits(k.x), float_bits(k.y), float_bits(k.z));
}

Float4 hash_float4_to_float4(const Vec3& k, float w) {
    // Cycles rotates the components for the later channels.
    return {hash_float4_to_float(k, w), hash_float4_to_float(Vec3(w, k.x, k.y), k.z),
            hash_float4_to_float(Vec3(k.z, w, k.x), k.y), hash_float4_to_float(Vec3(k.y, k.z, w), k.x)};
}

Vec3 hash_float_to_float3(float k) { return hash_bits_to_float3(float_bits(k)); }

Vec3 hash_float2_to_float3(float x, float y) { return hash_bits_to_float3(float_bits(x), float_bits(y)); }

Vec3 hash_float4_to_float3(const Vec3& k, float w) {
    return hash_bits_to_float3(float_bits(k.x), float_bits(k.y), float_bits(k.z), float_bits(w));
}

// ---- Perlin noise ----

SMIS_NOISE_CLONES float snoise_1d(float p) { return snoise_of<1>(perlin(P1{p})); }
SMIS_NOISE_CLONES float snoise_2d(float x, float y) { return snoise_of<2>(perlin(P2{x, y})); }
SMIS_NOISE_CLONES float snoise_3d(const Vec3& p) { return snoise_of<3>(perlin(P3{p.x, p.y, p.z})); }
SMIS_NOISE_CLONES float snoise_4d(const Vec3& p, float w) {
    return snoise_of<4>(perlin(P4{p.x, p.y, p.z, w}));
}

SMIS_NOISE_CLONES float noise_1d(float p) { return unoise_of<1>(perlin(P1{p})); }
SMIS_NOISE_CLONES float noise_2d(float x, float y) { return unoise_of<2>(perlin(P2{x, y})); }
SMIS_NOISE_CLONES float noise_3d(const Vec3& p) { return unoise_of<3>(perlin(P3{p.x, p.y, p.z})); }
SMIS_NOISE_CLONES float noise_4d(const Vec3& p, float w) {
    return unoise_of<4>(perlin(P4{p.x, p.y, p.z, w}));
}

SMIS_NOISE_CLONES float fractal_noise_1d(float p, float octaves, float roughness) {
    return fractal(P1{p}, octaves, roughness);
}
SMIS_NOISE_CLONES float fractal_noise_2d(float x, float y, float octaves, float roughness) {
    return fractal(P2{x, y}, octaves, roughness);
}
SMIS_NOISE_CLONES float fractal_noise_3d(const Vec3& p, float octaves, float roughness) {
    return fractal(P3{p.x, p.y, p.z}, octaves, roughness);
}
SMIS_NOISE_CLONES float fractal_noise_4d(const Vec3& p, float w, float octaves, float roughness) {
    return fractal(P4{p.x, p.y, p.z, w}, octaves, roughness);
}

// ---- Texture nodes ----

SMIS_NOISE_CLONES TextureOut noise_texture(int dimensions, const Vec3& co, float w, float scale,
                                            float detail, float roughness, float distortion, bool color) {
    Vec3 c = co * scale;
    float ws = w * scale;
    switch (dimensions) {
        case 1: return noise_texture_nd(P1{ws}, detail, roughness, distortion, color);
        case 2: return noise_texture_nd(P2{c.x, c.y}, detail, roughness, distortion, color);
        case 3: return noise_texture_nd(P3{c.x, c.y, c.z}, detail, roughness, distortion, color);
        case 4: return noise_texture_nd(P4{c.x, c.y, c.z, ws}, detail, roughness, distortion, color);
        default: return {};
    }
}

SMIS_NOISE_CLONES float musgrave_texture(int dimensions, MusgraveType type, const Vec3& co, float w,
                                         float scale, float detail, float dimension, float lacunarity,
                                         float offset, float gain) {
    dimension = std::fmax(dimension, 1e-5f);
    detail = clampf(detail, 0.0f, 15.0f);
    lacunarity = std::fmax(lacunarity, 1e-5f);
    switch (dimensions) {
        case 1: return musgrave(type, P1{w * scale}, dimension, lacunarity, detail, offset, gain);
        case 2:
            return musgrave(type, P2{co.x * scale, co.y * scale}, dimension, lacunarity, detail,
                            offset, gain);
        case 3:
            return musgrave(type, P3{co.x * scale, co.y * scale, co.z * scale}, dimension, lacunarity,
                            detail, offset, gain);
        case 4:
            return musgrave(type, P4{co.x * scale, co.y * scale, co.z * scale, w * scale}, dimension,
                            lacunarity, detail, offset, gain);
        default: return 0.0f;
    }
}

TextureOut white_noise_texture(int dimensions, const Vec3& co, float w) {
    // The colour's first channel is the fac hash (hash_float*_to_float3(k).x == hash_float*_to_float(k)).
    TextureOut out;
    switch (dimensions) {
        case 1: out.color = hash_bits_to_float3(float_bits(w)); break;
        case 2: out.color = hash_bits_to_float3(float_bits(co.x), float_bits(co.y)); break;
        case 3: out.color = hash_bits_to_float3(float_bits(co.x), float_bits(co.y), float_bits(co.z)); break;
        case 4:
            out.color =
                hash_bits_to_float3(float_bits(co.x), float_bits(co.y), float_bits(co.z), float_bits(w));
            break;
        default: return {0.0f, Color(1.0f, 0.0f, 1.0f)};  // Cycles' "invalid" magenta
    }
    out.fac = out.color.x;
    return out;
}

TextureOut wave_texture(WaveType type, WaveDirection dir, WaveProfile profile, const Vec3& co,
                        float scale, float distortion, float detail, float detail_scale,
                        float detail_roughness, float phase_offset) {
    // Nudge coordinates off exact integers so band edges on unit coordinates are stable (the kernel
    // fuses the scale into the nudge).
    Vec3 p = Vec3(fmadd(co.x, scale, 0.000001f), fmadd(co.y, scale, 0.000001f),
                  fmadd(co.z, scale, 0.000001f)) *
             0.999999f;
    float n;
    if (type == WaveType::Bands) {
        switch (dir) {
            case WaveDirection::X: n = p.x * 20.0f; break;
            case WaveDirection::Y: n = p.y * 20.0f; break;
            case WaveDirection::Z: n = p.z * 20.0f; break;
            default: n = (p.x + p.y + p.z) * 10.0f; break;
        }
    } else {
        Vec3 rp = p;
        switch (dir) {
            case WaveDirection::X: rp *= Vec3(0.0f, 1.0f, 1.0f); break;
            case WaveDirection::Y: rp *= Vec3(1.0f, 0.0f, 1.0f); break;
            case WaveDirection::Z: rp *= Vec3(1.0f, 1.0f, 0.0f); break;
            default: break;  // spherical
        }
        // Unfused sum of squares (math.h's length() may be compiled with contraction).
        n = std::sqrt(rp.x * rp.x + rp.y * rp.y + rp.z * rp.z) * 20.0f;
    }
    n += phase_offset;
    if (distortion != 0.0f) {
        float detail_noise = fractal_noise_3d(p * detail_scale, detail, detail_roughness);
        n = fmadd(distortion, detail_noise * 2.0f - 1.0f, n);
    }

    float f;
    switch (profile) {
        case WaveProfile::Sine: f = 0.5f + 0.5f * std::sin(n - 0.5f * kPi); break;
        case WaveProfile::Saw:
            n /= kTwoPi;
            f = n - std::floor(n);
            break;
        default:
            n /= kTwoPi;
            f = std::fabs(n - std::floor(n + 0.5f)) * 2.0f;
            break;
    }
    TextureOut out;
    out.fac = f;
    out.color = Color(f);
    return out;
}

TextureOut magic_texture(int depth, const Vec3& co, float scale, float distortion) {
    int n = std::max(0, std::min(depth, 10));
    // Cycles wraps the *unscaled* coordinate to [0, 2pi) against precision loss in sin/cos and only
    // then applies the scale, so the texture is not simply periodic in co * scale.
    float px = std::fmod(co.x, kTwoPi);
    float py = std::fmod(co.y, kTwoPi);
    float pz = std::fmod(co.z, kTwoPi);

    float x = std::sin((px + py + pz) * 5.0f * scale);
    float y = std::cos((-px + py - pz) * 5.0f * scale);
    float z = -std::cos((-px - py + pz) * 5.0f * scale);

    if (n > 0) {
        // The kernel fuses y * distortion into the first sum (y's only use); the other products have
        // uses in later depth branches and stay unfused.
        float y0 = y;
        x *= distortion;
        z *= distortion;
        y = -std::cos(fmadd(-y0, distortion, x) + z);
        y *= distortion;
        if (n > 1) { x = std::cos(x - y - z); x *= distortion; }
        if (n > 2) { z = std::sin(-x - y - z); z *= distortion; }
        if (n > 3) { x = -std::cos(-x + y - z); x *= distortion; }
        if (n > 4) { y = -std::sin(-x + y + z); y *= distortion; }
        if (n > 5) { y = -std::cos(-x + y + z); y *= distortion; }
        if (n > 6) { x = std::cos(x + y + z); x *= distortion; }
        if (n > 7) { z = std::sin(x + y - z); z *= distortion; }
        if (n > 8) { x = -std::cos(-x - y + z); x *= distortion; }
        if (n > 9) { y = -std::sin(x - y + z); y *= distortion; }
    }

    if (distortion != 0.0f) {
        float d2 = distortion * 2.0f;
        x /= d2;
        y /= d2;
        z /= d2;
    }

    TextureOut out;
    out.color = Color(0.5f - x, 0.5f - y, 0.5f - z);
    out.fac = average(out.color);
    return out;
}

TextureOut checker_texture(const Vec3& co, const Color& color1, const Color& color2, float scale) {
    Vec3 p = co * scale;
    // Cycles' nudge against precision issues on unit coordinates (it moves integer borders towards 0).
    int parity[3];
    for (int i = 0; i < 3; ++i) {
        float q = (p[i] + 0.000001f) * 0.999999f;
        int cell;
        floorfrac(q, &cell);
        parity[i] = cell & 1;  // == |cell| % 2 (Cycles' form) in two's complement, without abs()
    }
    bool on = ((parity[0] == parity[1]) ? 1 : 0) == parity[2];
    TextureOut out;
    out.fac = on ? 1.0f : 0.0f;
    out.color = on ? color1 : color2;
    return out;
}

TextureOut gradient_texture(GradientType type, const Vec3& co) {
    float x = co.x, y = co.y, z = co.z;
    float f = 0.0f;
    switch (type) {
        case GradientType::Linear: f = x; break;
        case GradientType::Quadratic: {
            float r = std::fmax(x, 0.0f);
            f = r * r;
            break;
        }
        case GradientType::Easing: {
            float r = std::fmin(std::fmax(x, 0.0f), 1.0f);
            float t = r * r;
            f = fmadd(3.0f, t, -(2.0f * t * r));
            break;
        }
        case GradientType::Diagonal: f = (x + y) * 0.5f; break;
        case GradientType::Radial: f = std::atan2(y, x) / kTwoPi + 0.5f; break;
        case GradientType::QuadraticSphere:
        case GradientType::Spherical: {
            // The 0.999999 bias gives exactly 0 on unit-length vectors.
            float r = std::fmax(0.999999f - std::sqrt(fmadd(z, z, fmadd(x, x, y * y))), 0.0f);
            f = type == GradientType::QuadraticSphere ? r * r : r;
            break;
        }
    }
    TextureOut out;
    out.fac = saturate(f);
    out.color = Color(out.fac);
    return out;
}

}  // namespace smis::shading
