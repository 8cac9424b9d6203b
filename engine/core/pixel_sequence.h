// One dimension stratified over the samples of a pixel: the base-2 radical inverse (van der Corput)
// of the sample index, Cranley-Patterson rotated by a random shift of the pixel. Any 2^k consecutive
// samples starting at a multiple of 2^k fall one per interval of length 2^-k, so a pixel's samples
// cover the dimension evenly instead of clumping like independent numbers; the rotation makes every
// sample's value uniform on [0, 1) (an unbiased replacement for Rng::next_float()) and the pixels
// independent of each other. A pure function of (pixel, sample, seed): thread-count independent.
#pragma once
#include <cstdint>

#include "core/rng.h"
#include "core/stratified.h"

namespace smis {

// `salt` names the dimension, so different users of the sequence get independent rotations.
inline float pixel_sequence(uint32_t px, uint32_t py, uint32_t sample, uint32_t seed, uint64_t salt) {
    uint64_t key = mix64(((static_cast<uint64_t>(py) << 32) | px) ^ mix64(seed ^ mix64(salt)));
    uint32_t shift = static_cast<uint32_t>(key >> 32);
    uint32_t v = stratified::reverse_bits(sample) + shift;  // wraps: the rotation modulo 1 in 32-bit fixed point
    return static_cast<float>(v >> 8) * 0x1p-24f;  // 24 bits as Rng::next_float(): never rounds up to 1
}

}  // namespace smis
