// Stratified random numbers for the first dimensions of a pixel's samples: padded, Owen-scrambled
// Sobol points (Burley 2020, "Practical Hash-based Owen Scrambling"; pbrt-v4's PaddedSobolSampler).
//
// Sample s of a pixel takes point s of a 2D Sobol (0,2)-sequence for each pair of dimensions (and
// of van der Corput's sequence for each single dimension). Every pixel, every dimension group and
// every seed has its own random nested-uniform (Owen) scramble and its own scramble of the sample
// index, so:
//  * one sample alone is uniformly distributed over [0,1)^n, independently in every group: any
//    estimator stays unbiased, exactly as with independent random numbers;
//  * the first 2^k samples of a pixel are stratified in every group (one point per elementary
//    interval), which is where the variance goes down: pixel position, the first light sample,
//    the first BSDF sample.
// Groups are padded (independently scrambled indices), not a high-dimensional Sobol sequence,
// because the dimensions of a path are not all equally important and Sobol's higher dimensions
// have poor 2D projections.
#pragma once
#include <cstdint>

#include "core/rng.h"

namespace smis {
namespace stratified {

constexpr uint32_t reverse_bits(uint32_t x) {
    x = __builtin_bswap32(x);  // the bytes in one instruction, then the bits within each byte
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
}

// Laine and Karras' hash: bit i of the result depends only on bits <= i of x, so, applied to
// bit-reversed values, it is a nested uniform (Owen) scramble.
inline uint32_t laine_karras_permutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

inline uint32_t owen_scramble(uint32_t x, uint32_t seed) {
    return reverse_bits(laine_karras_permutation(reverse_bits(x), seed));
}

// The second Sobol dimension (the first is reverse_bits(i), van der Corput's sequence). Its
// generator matrix is linear over GF(2): the value is the XOR of one column per set bit of i, so
// four tables of the XORs of 8 columns give it in four lookups. The tables hold the columns with
// their bits reversed (reversal commutes with XOR), because the Owen scramble reverses the value
// first: one bit reversal less per point.
struct SobolDim1Tables {
    uint32_t t[4][256]{};
    constexpr SobolDim1Tables() {
        uint32_t column[32]{};
        for (uint32_t b = 0, v = 1u << 31; b < 32; ++b, v ^= v >> 1) column[b] = reverse_bits(v);
        for (int byte = 0; byte < 4; ++byte)
            for (uint32_t x = 0; x < 256; ++x) {
                uint32_t r = 0;
                for (int b = 0; b < 8; ++b)
                    if (x & (1u << b)) r ^= column[8 * byte + b];
                t[byte][x] = r;
            }
    }
};
// Built by the compiler: a function-local static would test its guard at every call.
inline constexpr SobolDim1Tables kSobolDim1Tables{};
// reverse_bits(sobol_dim1(i))
inline uint32_t sobol_dim1_reversed(uint32_t i) {
    const SobolDim1Tables& tables = kSobolDim1Tables;
    return tables.t[0][i & 255u] ^ tables.t[1][(i >> 8) & 255u] ^ tables.t[2][(i >> 16) & 255u] ^
           tables.t[3][i >> 24];
}

inline float to_unit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

// The three scramble seeds of a dimension group (index shuffle, first and second coordinate).
// They depend on the pixel and the group only: a pixel's samples can share them (sample_2d below).
struct GroupSeeds {
    uint32_t index = 0, x = 0, y = 0;
    GroupSeeds() = default;
    GroupSeeds(uint64_t pixel_key, uint32_t group) {
        uint64_t h = mix64(pixel_key ^ (uint64_t(group) * 0x9e3779b97f4a7c15ull));
        index = static_cast<uint32_t>(h);
        x = static_cast<uint32_t>(h >> 32);
        y = static_cast<uint32_t>((h * 0xd6e8feb86659fd93ull) >> 32);
    }
};

// Point `sample` of dimension group `group` for the pixel whose scrambles derive from `pixel_key`.
inline float sample_1d(uint32_t sample, uint64_t pixel_key, uint32_t group) {
    GroupSeeds seeds(pixel_key, group);
    uint32_t index = owen_scramble(sample, seeds.index);
    // owen_scramble(reverse_bits(index)), with the two inner reversals cancelled
    return to_unit(reverse_bits(laine_karras_permutation(index, seeds.x)));
}

// sample_2d below with the sample index's bits already reversed (the first step of owen_scramble):
// a pixel sample asks for several groups with one index, so it reverses the index once (Sampler).
inline void sample_2d_of_reversed(uint32_t sample_reversed, const GroupSeeds& seeds, float* out) {
    uint32_t index = reverse_bits(laine_karras_permutation(sample_reversed, seeds.index));  // owen_scramble
    out[0] = to_unit(reverse_bits(laine_karras_permutation(index, seeds.x)));  // as in sample_1d
    // owen_scramble(sobol_dim1(index)), with the inner reversal in the table
    out[1] = to_unit(reverse_bits(laine_karras_permutation(sobol_dim1_reversed(index), seeds.y)));
}
inline void sample_2d(uint32_t sample, const GroupSeeds& seeds, float* out) {
    sample_2d_of_reversed(reverse_bits(sample), seeds, out);
}
inline void sample_2d(uint32_t sample, uint64_t pixel_key, uint32_t group, float* out) {
    sample_2d(sample, GroupSeeds(pixel_key, group), out);
}

}  // namespace stratified
}  // namespace smis
