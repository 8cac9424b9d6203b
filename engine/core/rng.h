// PCG32 (O'Neill 2014) plus a seed hash, so every (pixel, sample, seed) owns an independent stream:
// that is what makes images identical whatever the thread count.
#pragma once
#include <cstdint>

#include "core/features.h"

namespace smis {

inline uint64_t mix64(uint64_t z) {  // splitmix64 finaliser
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

class Rng {
public:
    Rng() { seed(0, 0); }
    Rng(uint64_t seq, uint64_t offset) { seed(seq, offset); }
    void seed(uint64_t seq, uint64_t offset) {
        prefix_left_ = 0;
        state_ = 0u;
        inc_ = (seq << 1u) | 1u;
        next_u32();
        state_ += offset;
        next_u32();
    }
    uint32_t next_u32() {
        uint64_t old = state_;
        state_ = old * 6364136223846793005ull + inc_;
        uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
    }
    // Uniform in [0, 1): 24 random mantissa bits, never rounds up to 1. The first values can come
    // from a stratified prefix (set_prefix, core/stratified.h) instead of the PCG stream.
    float next_float() {
        if (kWithStratified && prefix_left_ != 0) return prefix_[--prefix_left_];
        return static_cast<float>(next_u32() >> 8) * 0x1p-24f;
    }
    // The next n (<= kMaxPrefix) calls of next_float() return v[0..n); the PCG stream is untouched.
    static constexpr int kMaxPrefix = 10;
    void set_prefix(const float* v, int n) {
        prefix_left_ = static_cast<uint8_t>(n < kMaxPrefix ? n : kMaxPrefix);
        // Stored last first, so that next_float() tests one counter (every call pays for the test).
        for (int i = 0; i < prefix_left_; ++i) prefix_[prefix_left_ - 1 - i] = v[i];
    }
    double next_double() {
        uint64_t v = (static_cast<uint64_t>(next_u32()) << 32) | next_u32();
        return static_cast<double>(v >> 11) * 0x1p-53;
    }

private:
    uint64_t state_ = 0, inc_ = 1;
    uint8_t prefix_left_ = 0;
    float prefix_[kMaxPrefix];
};

// The stream for one pixel sample: a pure function of its coordinates and the user's seed.
inline Rng pixel_sample_rng(uint32_t px, uint32_t py, uint32_t sample, uint32_t seed) {
    uint64_t key = mix64((static_cast<uint64_t>(py) << 32) | px);
    uint64_t seq = mix64(key ^ (static_cast<uint64_t>(seed) * 0x632be59bd9b4e019ull));
    return Rng(seq, mix64(seq + sample));
}

}  // namespace smis
