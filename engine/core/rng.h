// PCG32 (O'Neill 2014) plus a seed hash, so every (pixel, sample, seed) owns an independent stream:
// that is what makes images identical whatever the thread count.
#pragma once
#include <cstdint>

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
        scattering_segment_ = false;
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
    // Uniform in [0, 1): 24 random mantissa bits, never rounds up to 1. (Stratified numbers are asked
    // for by name, core/sampler.h; they never pass through the stream.)
    float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }
    // A pixel sample's first scattering segment in a medium draws from stratified groups of its own
    // (volume.h, segment_numbers): the Sampler marks its stream with the pixel's key and the
    // sample's index, and the first segment takes the mark, once.
    void mark_scattering_segment(uint64_t key, uint32_t sample) {
        scattering_segment_ = true;
        segment_key_ = key, segment_sample_ = sample;
    }
    bool take_scattering_segment(uint64_t* key, uint32_t* sample) {
        if (!scattering_segment_) return false;
        scattering_segment_ = false;
        *key = segment_key_, *sample = segment_sample_;
        return true;
    }
    double next_double() {
        uint64_t v = (static_cast<uint64_t>(next_u32()) << 32) | next_u32();
        return static_cast<double>(v >> 11) * 0x1p-53;
    }

private:
    uint64_t state_ = 0, inc_ = 1;
    bool scattering_segment_ = false;
    uint32_t segment_sample_ = 0;
    uint64_t segment_key_ = 0;
};

// The stream for one pixel sample: a pure function of its coordinates and the user's seed. The
// pixel's part (pixel_stream) is the same for all its samples.
inline uint64_t pixel_stream(uint32_t px, uint32_t py, uint32_t seed) {
    uint64_t key = mix64((static_cast<uint64_t>(py) << 32) | px);
    return mix64(key ^ (static_cast<uint64_t>(seed) * 0x632be59bd9b4e019ull));
}
inline Rng pixel_sample_rng(uint64_t stream, uint32_t sample) { return Rng(stream, mix64(stream + sample)); }
inline Rng pixel_sample_rng(uint32_t px, uint32_t py, uint32_t sample, uint32_t seed) {
    return pixel_sample_rng(pixel_stream(px, py, seed), sample);
}

}  // namespace smis
