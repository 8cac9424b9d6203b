// Noise-family procedural textures matching Blender 3.4 Cycles (see procedural_noise.h).
//
// Bit-exactness: Blender runs Cycles' AVX2 CPU kernel on current x86 CPUs. That kernel is built with
// -ffast-math -mfma, so some multiply-adds are fused (explicitly in its SIMD Perlin code, by compiler
// contraction elsewhere). Rounding differences matter more than usual here: high noise octaves scale
// coordinates by up to 2^15, so a 1-ulp difference in a distorted coordinate becomes a different
// noise value. fmadd() below reproduces a fused multiply-add exactly where the kernel fuses (found by
// comparing against renders bit for bit); every other expression must stay unfused, so compiler
// contraction is switched off for this file (it would fuse on -mfma / -march=native builds).
#include "shading/procedural_noise.h"

#include <cmath>
#include <cstring>

#if defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#elif defined(__GNUC__)
#pragma GCC optimize("fp-contract=off")
#endif

namespace smis::shading {

namespace {

constexpr float kTwoPi = 2.0f * kPi;

inline uint32_t rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

// lookup3's mixing of three words (used by the 4-word hash).
inline void lookup3_mix(uint32_t& a, uint32_t& b, uint32_t& c) {
    a -= c; a ^= rot(c, 4);  c += b;
    b -= a; b ^= rot(a, 6);  a += c;
    c -= b; c ^= rot(b, 8);  b += a;
    a -= c; a ^= rot(c, 16); c += b;
    b -= a; b ^= rot(a, 19); a += c;
    c -= b; c ^= rot(b, 4);  b += a;
}

// lookup3's final avalanche; the hash is c.
inline void lookup3_final(uint32_t& a, uint32_t& b, uint32_t& c) {
    c ^= b; c -= rot(b, 14);
    a ^= c; a -= rot(c, 11);
    b ^= a; b -= rot(a, 25);
    c ^= b; c -= rot(b, 16);
    a ^= c; a -= rot(c, 4);
    b ^= a; b -= rot(a, 14);
    c ^= b; c -= rot(b, 24);
}

// lookup3 seeds the state with 0xdeadbeef + (length in bytes) + initval, initval being 13 in Cycles.
constexpr uint32_t seed_for(uint32_t words) { return 0xdeadbeefu + (words << 2) + 13u; }

inline uint32_t float_bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, sizeof u);
    return u;
}

// floor(x) as an int plus the fractional part. Out-of-range and NaN inputs give INT_MIN, which is what
// the x86 conversion Cycles' CPU kernels rely on returns (a plain cast would be undefined here).
inline float floorfrac(float x, int* i) {
    float f = std::floor(x);
    *i = (f >= -2147483648.0f && f < 2147483648.0f) ? static_cast<int>(f) : INT32_MIN;
    return x - f;
}

inline uint32_t u(int i) { return static_cast<uint32_t>(i); }

// a * b + c rounded once. The float product is exact in double and the sum rarely rounds twice, so
// this is a fused multiply-add without needing FMA hardware (double arithmetic costs as much as float).
inline float fmadd(float a, float b, float c) {
    return static_cast<float>(static_cast<double>(a) * static_cast<double>(b) + static_cast<double>(c));
}

// Linear interpolation as Cycles' SIMD kernels do it (2D-4D noise): t * b + (1 - t) * a, fused.
inline float mixf(float a, float b, float t) { return fmadd(t, b, (1.0f - t) * a); }

// Quintic fade 6t^5 - 15t^4 + 10t^3 with the SIMD kernels' fused Horner steps; 1D noise (scalar in
// Cycles) multiplies the final product in a different order.
inline float fade_poly(float t) { return fmadd(t, fmadd(t, 6.0f, -15.0f), 10.0f); }
inline float fade(float t) { return (t * t) * (t * fade_poly(t)); }
inline float fade_1d(float t) { return t * t * t * fade_poly(t); }

inline float negate_if(float v, uint32_t cond) { return cond ? -v : v; }

inline float ensure_finite(float v) { return std::isfinite(v) ? v : 0.0f; }

inline float saturate(float v) { return clampf(v, 0.0f, 1.0f); }

// Perlin's improved-noise gradients, one table per dimension as in Cycles.
inline float grad1(uint32_t hash, float x) {
    uint32_t h = hash & 15u;
    float g = static_cast<float>(1u + (h & 7u));
    return negate_if(g, h & 8u) * x;
}

inline float grad2(uint32_t hash, float x, float y) {
    uint32_t h = hash & 7u;
    float a = h < 4 ? x : y;
    float b = 2.0f * (h < 4 ? y : x);
    return negate_if(a, h & 1u) + negate_if(b, h & 2u);
}

inline float grad3(uint32_t hash, float x, float y, float z) {
    uint32_t h = hash & 15u;
    float a = h < 8 ? x : y;
    float vt = (h == 12 || h == 14) ? x : z;
    float b = h < 4 ? y : vt;
    return negate_if(a, h & 1u) + negate_if(b, h & 2u);
}

inline float grad4(uint32_t hash, float x, float y, float z, float w) {
    uint32_t h = hash & 31u;
    float a = h < 24 ? x : y;
    float b = h < 16 ? y : z;
    float c = h < 8 ? z : w;
    return negate_if(a, h & 1u) + negate_if(b, h & 2u) + negate_if(c, h & 4u);
}

float perlin_1d(float x) {
    int X;
    float fx = floorfrac(x, &X);
    float a = grad1(hash_uint(u(X)), fx), b = grad1(hash_uint(u(X + 1)), fx - 1.0f);
    return a + fade_1d(fx) * (b - a);  // scalar code: not fused
}

float perlin_2d(float x, float y) {
    int X, Y;
    float fx = floorfrac(x, &X);
    float fy = floorfrac(y, &Y);
    float su = fade(fx), sv = fade(fy);
    // Interpolated along x first, then y (the order of Cycles' SIMD kernels).
    float a = mixf(grad2(hash_uint2(u(X), u(Y)), fx, fy),
                   grad2(hash_uint2(u(X + 1), u(Y)), fx - 1.0f, fy), su);
    float b = mixf(grad2(hash_uint2(u(X), u(Y + 1)), fx, fy - 1.0f),
                   grad2(hash_uint2(u(X + 1), u(Y + 1)), fx - 1.0f, fy - 1.0f), su);
    return mixf(a, b, sv);
}

// One z-slab of the 3D cube: x then y interpolation of the four corners at lattice Z + dz.
inline float perlin_3d_slab(int X, int Y, int Z, float fx, float fy, float fz, float su, float sv) {
    float a = mixf(grad3(hash_uint3(u(X), u(Y), u(Z)), fx, fy, fz),
                   grad3(hash_uint3(u(X + 1), u(Y), u(Z)), fx - 1.0f, fy, fz), su);
    float b = mixf(grad3(hash_uint3(u(X), u(Y + 1), u(Z)), fx, fy - 1.0f, fz),
                   grad3(hash_uint3(u(X + 1), u(Y + 1), u(Z)), fx - 1.0f, fy - 1.0f, fz), su);
    return mixf(a, b, sv);
}

float perlin_3d(float x, float y, float z) {
    int X, Y, Z;
    float fx = floorfrac(x, &X);
    float fy = floorfrac(y, &Y);
    float fz = floorfrac(z, &Z);
    float su = fade(fx), sv = fade(fy), sw = fade(fz);
    float lo = perlin_3d_slab(X, Y, Z, fx, fy, fz, su, sv);
    float hi = perlin_3d_slab(X, Y, Z + 1, fx, fy, fz - 1.0f, su, sv);
    return mixf(lo, hi, sw);
}

inline float perlin_4d_corner(int X, int Y, int Z, int W, float fx, float fy, float fz, float fw) {
    return grad4(hash_uint4(u(X), u(Y), u(Z), u(W)), fx, fy, fz, fw);
}

float perlin_4d(float x, float y, float z, float w) {
    int X, Y, Z, W;
    float fx = floorfrac(x, &X);
    float fy = floorfrac(y, &Y);
    float fz = floorfrac(z, &Z);
    float fw = floorfrac(w, &W);
    float su = fade(fx), sv = fade(fy), st = fade(fz), ss = fade(fw);
    // Cycles' AVX kernel interpolates along w first, then x, y and z.
    float c[2][2][2];  // [dx][dy][dz]
    for (int dx = 0; dx < 2; ++dx)
        for (int dy = 0; dy < 2; ++dy)
            for (int dz = 0; dz < 2; ++dz) {
                float gx = fx - static_cast<float>(dx), gy = fy - static_cast<float>(dy);
                float gz = fz - static_cast<float>(dz);
                c[dx][dy][dz] =
                    mixf(perlin_4d_corner(X + dx, Y + dy, Z + dz, W, gx, gy, gz, fw),
                         perlin_4d_corner(X + dx, Y + dy, Z + dz, W + 1, gx, gy, gz, fw - 1.0f), ss);
            }
    float e[2][2];  // [dy][dz]
    for (int dy = 0; dy < 2; ++dy)
        for (int dz = 0; dz < 2; ++dz) e[dy][dz] = mixf(c[0][dy][dz], c[1][dy][dz], su);
    return mixf(mixf(e[0][0], e[1][0], sv), mixf(e[0][1], e[1][1], sv), st);
}

// Points of 1..4 dimensions, so the fractal sums below are written once (Cycles repeats them per
// dimension with identical bodies).
struct P1 {
    float x;
    P1 operator*(float s) const { return {x * s}; }
    P1 operator+(const P1& o) const { return {x + o.x}; }
};
struct P2 {
    float x, y;
    P2 operator*(float s) const { return {x * s, y * s}; }
    P2 operator+(const P2& o) const { return {x + o.x, y + o.y}; }
};
struct P3 {
    float x, y, z;
    P3 operator*(float s) const { return {x * s, y * s, z * s}; }
    P3 operator+(const P3& o) const { return {x + o.x, y + o.y, z + o.z}; }
};
struct P4 {
    float x, y, z, w;
    P4 operator*(float s) const { return {x * s, y * s, z * s, w * s}; }
    P4 operator+(const P4& o) const { return {x + o.x, y + o.y, z + o.z, w + o.w}; }
};

// Perlin noise and its range-normalising factor per dimension.
inline float perlin(const P1& p) { return ensure_finite(perlin_1d(p.x)); }
inline float perlin(const P2& p) { return ensure_finite(perlin_2d(p.x, p.y)); }
inline float perlin(const P3& p) { return ensure_finite(perlin_3d(p.x, p.y, p.z)); }
inline float perlin(const P4& p) { return ensure_finite(perlin_4d(p.x, p.y, p.z, p.w)); }
inline float noise_scale(const P1&) { return 0.2500f; }
inline float noise_scale(const P2&) { return 0.6616f; }
inline float noise_scale(const P3&) { return 0.9820f; }
inline float noise_scale(const P4&) { return 0.8344f; }

template <class P> inline float snoise(const P& p) { return noise_scale(p) * perlin(p); }
template <class P> inline float unoise(const P& p) { return 0.5f * snoise(p) + 0.5f; }
// snoise(p) + offset with the scale multiply fused into the add (Musgrave's terrain types).
template <class P> inline float snoise_plus(const P& p, float offset) {
    return fmadd(noise_scale(p), perlin(p), offset);
}

template <class P> float fractal(const P& p, float octaves, float roughness) {
    float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
    octaves = clampf(octaves, 0.0f, 15.0f);
    int n = static_cast<int>(octaves);
    for (int i = 0; i <= n; ++i) {
        float t = unoise(p * fscale);
        sum = fmadd(t, amp, sum);
        maxamp += amp;
        amp *= clampf(roughness, 0.0f, 1.0f);
        fscale *= 2.0f;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd == 0.0f) return sum / maxamp;
    // Fractional detail: blend the normalised sums without and with one more octave.
    float t = unoise(p * fscale);
    float sum2 = fmadd(t, amp, sum);
    sum /= maxamp;
    sum2 /= maxamp + amp;
    return fmadd(1.0f - rmd, sum, rmd * sum2);
}

// ---- Musgrave (F. K. Musgrave's terrain functions as Cycles 3.4 has them) ----

template <class P> float musgrave_fbm(P p, float H, float lacunarity, float octaves) {
    float value = 0.0f, pwr = 1.0f;
    float pwHL = std::pow(lacunarity, -H);
    for (int i = 0; i < static_cast<int>(octaves); ++i) {
        value = fmadd(snoise(p), pwr, value);
        pwr *= pwHL;
        p = p * lacunarity;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) value = fmadd(rmd * snoise(p), pwr, value);
    return value;
}

template <class P> float musgrave_multifractal(P p, float H, float lacunarity, float octaves) {
    float value = 1.0f, pwr = 1.0f;
    float pwHL = std::pow(lacunarity, -H);
    for (int i = 0; i < static_cast<int>(octaves); ++i) {
        value *= fmadd(pwr, snoise(p), 1.0f);
        pwr *= pwHL;
        p = p * lacunarity;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) value *= fmadd(rmd * pwr, snoise(p), 1.0f);
    return value;
}

template <class P>
float musgrave_hetero_terrain(P p, float H, float lacunarity, float octaves, float offset) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    // The first octave is unscaled; later ones are scaled by the running value.
    float value = snoise_plus(p, offset);
    p = p * lacunarity;
    for (int i = 1; i < static_cast<int>(octaves); ++i) {
        value = fmadd(snoise_plus(p, offset) * pwr, value, value);  // value += increment
        pwr *= pwHL;
        p = p * lacunarity;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f) {
        float increment = snoise_plus(p, offset) * pwr * value;
        value = fmadd(rmd, increment, value);
    }
    return value;
}

template <class P>
float musgrave_hybrid_multifractal(P p, float H, float lacunarity, float octaves, float offset,
                                   float gain) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = 1.0f, value = 0.0f, weight = 1.0f;
    for (int i = 0; weight > 0.001f && i < static_cast<int>(octaves); ++i) {
        if (weight > 1.0f) weight = 1.0f;
        float signal = snoise_plus(p, offset) * pwr;
        pwr *= pwHL;
        value = fmadd(weight, signal, value);
        weight *= gain * signal;
        p = p * lacunarity;
    }
    float rmd = octaves - std::floor(octaves);
    if (rmd != 0.0f && weight > 0.001f) {
        if (weight > 1.0f) weight = 1.0f;
        float signal = snoise_plus(p, offset) * pwr;
        value = fmadd(rmd * weight, signal, value);
    }
    return value;
}

// Cycles 3.4's ridged multifractal ignores the fractional part of the octave count.
template <class P>
float musgrave_ridged_multifractal(P p, float H, float lacunarity, float octaves, float offset,
                                   float gain) {
    float pwHL = std::pow(lacunarity, -H);
    float pwr = pwHL;
    float signal = offset - std::fabs(snoise(p));
    signal *= signal;
    float value = signal;
    float weight = 1.0f;
    for (int i = 1; i < static_cast<int>(octaves); ++i) {
        p = p * lacunarity;
        weight = saturate(signal * gain);
        signal = offset - std::fabs(snoise(p));
        signal *= signal;
        signal *= weight;
        value = fmadd(signal, pwr, value);
        pwr *= pwHL;
    }
    return value;
}

template <class P>
float musgrave(MusgraveType type, const P& p, float H, float lacunarity, float octaves, float offset,
               float gain) {
    switch (type) {
        case MusgraveType::Multifractal: return musgrave_multifractal(p, H, lacunarity, octaves);
        case MusgraveType::Fbm: return musgrave_fbm(p, H, lacunarity, octaves);
        case MusgraveType::HybridMultifractal:
            return musgrave_hybrid_multifractal(p, H, lacunarity, octaves, offset, gain);
        case MusgraveType::RidgedMultifractal:
            return musgrave_ridged_multifractal(p, H, lacunarity, octaves, offset, gain);
        case MusgraveType::HeteroTerrain:
            return musgrave_hetero_terrain(p, H, lacunarity, octaves, offset);
    }
    return 0.0f;
}

// Random offsets (in [100, 200]) that decorrelate the noise texture's distortion and colour channels.
inline float random_float_offset(float seed) { return 100.0f + hash_float_to_float(seed) * 100.0f; }
inline float random_component_offset(float seed, float component) {
    return 100.0f + hash_float2_to_float(seed, component) * 100.0f;
}
inline P1 random_offset(P1, float seed) { return {random_float_offset(seed)}; }
inline P2 random_offset(P2, float seed) {
    return {random_component_offset(seed, 0.0f), random_component_offset(seed, 1.0f)};
}
inline P3 random_offset(P3, float seed) {
    return {random_component_offset(seed, 0.0f), random_component_offset(seed, 1.0f),
            random_component_offset(seed, 2.0f)};
}
inline P4 random_offset(P4, float seed) {
    return {random_component_offset(seed, 0.0f), random_component_offset(seed, 1.0f),
            random_component_offset(seed, 2.0f), random_component_offset(seed, 3.0f)};
}

// Distortion displaces each axis by signed noise at a per-axis random offset; seeds 0..N-1 are used
// for the N axes, then N and N+1 for the colour's green and blue channels. The kernel fuses the
// displacement's multiply-add in 1D, 2D and 4D but not in 3D.
template <class P> inline float distortion_noise(const P& p, float seed) {
    return snoise(p + random_offset(p, seed));
}
inline P1 distort(P1 p, float d) { return {fmadd(distortion_noise(p, 0.0f), d, p.x)}; }
inline P2 distort(P2 p, float d) {
    float dx = distortion_noise(p, 0.0f), dy = distortion_noise(p, 1.0f);
    return {fmadd(dx, d, p.x), fmadd(dy, d, p.y)};
}
inline P3 distort(P3 p, float d) {
    return p + P3{distortion_noise(p, 0.0f) * d, distortion_noise(p, 1.0f) * d,
                  distortion_noise(p, 2.0f) * d};
}
inline P4 distort(P4 p, float d) {
    float dx = distortion_noise(p, 0.0f), dy = distortion_noise(p, 1.0f);
    float dz = distortion_noise(p, 2.0f), dw = distortion_noise(p, 3.0f);
    return {fmadd(dx, d, p.x), fmadd(dy, d, p.y), fmadd(dz, d, p.z), fmadd(dw, d, p.w)};
}

template <class P>
TextureOut noise_texture_nd(P p, int axes, float detail, float roughness, float distortion, bool color) {
    if (distortion != 0.0f) p = distort(p, distortion);
    TextureOut out;
    out.fac = fractal(p, detail, roughness);
    if (!color) return out;  // Cycles skips the colour too when nothing reads it
    float seed = static_cast<float>(axes);
    out.color = Color(out.fac, fractal(p + random_offset(p, seed), detail, roughness),
                      fractal(p + random_offset(p, seed + 1.0f), detail, roughness));
    return out;
}

}  // namespace

// ---- Hashes ----

uint32_t hash_uint(uint32_t kx) {
    uint32_t a, b, c;
    a = b = c = seed_for(1);
    a += kx;
    lookup3_final(a, b, c);
    return c;
}

uint32_t hash_uint2(uint32_t kx, uint32_t ky) {
    uint32_t a, b, c;
    a = b = c = seed_for(2);
    b += ky;
    a += kx;
    lookup3_final(a, b, c);
    return c;
}

uint32_t hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz) {
    uint32_t a, b, c;
    a = b = c = seed_for(3);
    c += kz;
    b += ky;
    a += kx;
    lookup3_final(a, b, c);
    return c;
}

uint32_t hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    uint32_t a, b, c;
    a = b = c = seed_for(4);
    a += kx;
    b += ky;
    c += kz;
    lookup3_mix(a, b, c);
    a += kw;
    lookup3_final(a, b, c);
    return c;
}

float uint_to_float_incl(uint32_t n) {
    return static_cast<float>(n) * (1.0f / static_cast<float>(0xFFFFFFFFu));
}

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
    return {hash_float3_to_float(k), hash_float4_to_float(k, 1.0f), hash_float4_to_float(k, 2.0f)};
}

Float4 hash_float4_to_float4(const Vec3& k, float w) {
    // Cycles rotates the components for the later channels.
    return {hash_float4_to_float(k, w), hash_float4_to_float(Vec3(w, k.x, k.y), k.z),
            hash_float4_to_float(Vec3(k.z, w, k.x), k.y), hash_float4_to_float(Vec3(k.y, k.z, w), k.x)};
}

Vec3 hash_float_to_float3(float k) {
    return {hash_float_to_float(k), hash_float2_to_float(k, 1.0f), hash_float2_to_float(k, 2.0f)};
}

Vec3 hash_float2_to_float3(float x, float y) {
    return {hash_float2_to_float(x, y), hash_float3_to_float(Vec3(x, y, 1.0f)),
            hash_float3_to_float(Vec3(x, y, 2.0f))};
}

Vec3 hash_float4_to_float3(const Vec3& k, float w) {
    return {hash_float4_to_float(k, w), hash_float4_to_float(Vec3(k.z, k.x, w), k.y),
            hash_float4_to_float(Vec3(w, k.z, k.y), k.x)};
}

// ---- Perlin noise ----
// The per-dimension factors remap Perlin noise's actual range to about [-1, 1].

float snoise_1d(float p) { return snoise(P1{p}); }
float snoise_2d(float x, float y) { return snoise(P2{x, y}); }
float snoise_3d(const Vec3& p) { return snoise(P3{p.x, p.y, p.z}); }
float snoise_4d(const Vec3& p, float w) { return snoise(P4{p.x, p.y, p.z, w}); }

float noise_1d(float p) { return unoise(P1{p}); }
float noise_2d(float x, float y) { return unoise(P2{x, y}); }
float noise_3d(const Vec3& p) { return unoise(P3{p.x, p.y, p.z}); }
float noise_4d(const Vec3& p, float w) { return unoise(P4{p.x, p.y, p.z, w}); }

float fractal_noise_1d(float p, float octaves, float roughness) {
    return fractal(P1{p}, octaves, roughness);
}
float fractal_noise_2d(float x, float y, float octaves, float roughness) {
    return fractal(P2{x, y}, octaves, roughness);
}
float fractal_noise_3d(const Vec3& p, float octaves, float roughness) {
    return fractal(P3{p.x, p.y, p.z}, octaves, roughness);
}
float fractal_noise_4d(const Vec3& p, float w, float octaves, float roughness) {
    return fractal(P4{p.x, p.y, p.z, w}, octaves, roughness);
}

// ---- Texture nodes ----

TextureOut noise_texture(int dimensions, const Vec3& co, float w, float scale, float detail,
                         float roughness, float distortion, bool color) {
    Vec3 c = co * scale;
    float ws = w * scale;
    switch (dimensions) {
        case 1: return noise_texture_nd(P1{ws}, 1, detail, roughness, distortion, color);
        case 2: return noise_texture_nd(P2{c.x, c.y}, 2, detail, roughness, distortion, color);
        case 3: return noise_texture_nd(P3{c.x, c.y, c.z}, 3, detail, roughness, distortion, color);
        case 4: return noise_texture_nd(P4{c.x, c.y, c.z, ws}, 4, detail, roughness, distortion, color);
        default: return {};
    }
}

float musgrave_texture(int dimensions, MusgraveType type, const Vec3& co, float w, float scale,
                       float detail, float dimension, float lacunarity, float offset, float gain) {
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
    TextureOut out;
    switch (dimensions) {
        case 1:
            out.fac = hash_float_to_float(w);
            out.color = hash_float_to_float3(w);
            break;
        case 2:
            out.fac = hash_float2_to_float(co.x, co.y);
            out.color = hash_float2_to_float3(co.x, co.y);
            break;
        case 3:
            out.fac = hash_float3_to_float(co);
            out.color = hash_float3_to_float3(co);
            break;
        case 4:
            out.fac = hash_float4_to_float(co, w);
            out.color = hash_float4_to_float3(co, w);
            break;
        default:
            out.color = Color(1.0f, 0.0f, 1.0f);  // Cycles' "invalid" magenta
            break;
    }
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
