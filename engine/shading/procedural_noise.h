// Procedural textures of the noise family, reproducing Blender 3.4 Cycles' SVM nodes: Noise, Musgrave,
// White Noise, Wave, Magic, Checker and Gradient, plus the lookup3 hashes and Perlin noise they are
// built from (Voronoi and other textures reuse the hashes). All functions are pure float code that
// follows the rounding of the CPU kernel Blender 3.4.1 uses on x86 (AVX2, with its fused
// multiply-adds), so outputs match Cycles renders bit for bit on the tested inputs.
#pragma once

#include <cstdint>

#include "core/math.h"

namespace smis::shading {

// Small value types for the 2D and 4D hash variants (Vec3 covers 3D).
struct Float2 {
    float x = 0.0f, y = 0.0f;
};
struct Float4 {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

// ---- Bob Jenkins' lookup3 hashes, seeded as Cycles seeds them ----
uint32_t hash_uint(uint32_t kx);
uint32_t hash_uint2(uint32_t kx, uint32_t ky);
uint32_t hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz);
uint32_t hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw);

// [0, 2^32-1] -> [0, 1] (inclusive) and [0, 1) (exclusive) as Cycles maps them.
float uint_to_float_incl(uint32_t n);
float uint_to_float_excl(uint32_t n);

// Hash of integers to a float in [0, 1].
float hash_uint_to_float(uint32_t kx);
float hash_uint2_to_float(uint32_t kx, uint32_t ky);
float hash_uint3_to_float(uint32_t kx, uint32_t ky, uint32_t kz);
float hash_uint4_to_float(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw);

// Hash of float bit patterns to a float in [0, 1] (note: 0.0 and -0.0 hash differently, as in Cycles).
float hash_float_to_float(float k);
float hash_float2_to_float(float x, float y);
float hash_float3_to_float(const Vec3& k);
float hash_float4_to_float(const Vec3& k, float w);

// Hash of floats to several floats in [0, 1].
Float2 hash_float2_to_float2(float x, float y);
Vec3 hash_float3_to_float3(const Vec3& k);
Float4 hash_float4_to_float4(const Vec3& k, float w);
Vec3 hash_float_to_float3(float k);
Vec3 hash_float2_to_float3(float x, float y);
Vec3 hash_float4_to_float3(const Vec3& k, float w);
// Same values as the *_to_float3 hashes, named as White Noise's colour output uses them.
inline Color hash_float_to_color(float k) { return hash_float_to_float3(k); }
inline Color hash_float2_to_color(float x, float y) { return hash_float2_to_float3(x, y); }
inline Color hash_float3_to_color(const Vec3& k) { return hash_float3_to_float3(k); }
inline Color hash_float4_to_color(const Vec3& k, float w) { return hash_float4_to_float3(k, w); }

// ---- Perlin gradient noise ----
// Signed noise in about [-1, 1] (Cycles' snoise_Nd: Perlin noise times the per-dimension scale,
// non-finite results replaced by 0) and unsigned noise 0.5 * snoise + 0.5.
float snoise_1d(float p);
float snoise_2d(float x, float y);
float snoise_3d(const Vec3& p);
float snoise_4d(const Vec3& p, float w);
float noise_1d(float p);
float noise_2d(float x, float y);
float noise_3d(const Vec3& p);
float noise_4d(const Vec3& p, float w);
// Sum of octaves of unsigned noise, normalised to [0, 1]; the fractional part of `octaves` blends in
// one more octave. octaves is clamped to [0, 15], roughness to [0, 1].
float fractal_noise_1d(float p, float octaves, float roughness);
float fractal_noise_2d(float x, float y, float octaves, float roughness);
float fractal_noise_3d(const Vec3& p, float octaves, float roughness);
float fractal_noise_4d(const Vec3& p, float w, float octaves, float roughness);

// ---- Texture nodes ----
struct TextureOut {
    float fac = 0.0f;
    Color color{0.0f};
};

// Noise Texture. dimensions 1-4: 1D uses w, 2D co.x/co.y, 3D co, 4D co and w. Both co and w are
// multiplied by scale. fac is the value output, color the colour output (color.x == fac).
// `color`: compute the Color output too (three fractal sums instead of one).
TextureOut noise_texture(int dimensions, const Vec3& co, float w, float scale, float detail,
                         float roughness, float distortion, bool color = true);

// Musgrave types. Values are Blender's DNA / Cycles' (NodeMusgraveType) values, so a node's stored
// integer casts directly; Blender's UI lists them as Multifractal, Ridged, Hybrid, fBM, Hetero.
enum class MusgraveType {
    Multifractal = 0,
    Fbm = 1,
    HybridMultifractal = 2,
    RidgedMultifractal = 3,
    HeteroTerrain = 4,
};
// Musgrave Texture (dimensions 1-4 as the Noise Texture). detail is the octave count (fractional
// part blends one more octave, except for Ridged, which Cycles 3.4 truncates); output is unclamped.
float musgrave_texture(int dimensions, MusgraveType type, const Vec3& co, float w, float scale,
                       float detail, float dimension, float lacunarity, float offset, float gain);

// White Noise Texture (dimensions 1-4): fac in [0, 1] and an independent random colour.
TextureOut white_noise_texture(int dimensions, const Vec3& co, float w);

// Wave Texture. Blender stores both Diagonal (bands) and Spherical (rings) as 3; here every direction
// other than X/Y/Z means Diagonal for bands and Spherical for rings, as in Cycles.
enum class WaveType { Bands = 0, Rings = 1 };
enum class WaveDirection { X = 0, Y = 1, Z = 2, Diagonal = 3 /* bands */, Spherical = 4 /* rings */ };
enum class WaveProfile { Sine = 0, Saw = 1, Triangle = 2 };
TextureOut wave_texture(WaveType type, WaveDirection dir, WaveProfile profile, const Vec3& co,
                        float scale, float distortion, float detail, float detail_scale,
                        float detail_roughness, float phase_offset);

// Magic Texture, depth 0..10 (clamped). fac is the colour's average.
TextureOut magic_texture(int depth, const Vec3& co, float scale, float distortion);

// Checker Texture: fac 1 on color1's cells, 0 on color2's.
TextureOut checker_texture(const Vec3& co, const Color& color1, const Color& color2, float scale);

// Gradient Texture; values are Blender's DNA / Cycles' (NodeGradientType) values. fac is clamped to
// [0, 1]; color is grey fac.
enum class GradientType {
    Linear = 0,
    Quadratic = 1,
    Easing = 2,
    Diagonal = 3,
    Spherical = 6,
    QuadraticSphere = 5,
    Radial = 4,
};
TextureOut gradient_texture(GradientType type, const Vec3& co);

}  // namespace smis::shading
