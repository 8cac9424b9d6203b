// Cycles' integer hashes (util/hash.h): Bob Jenkins' lookup3 on 1-4 words, with Cycles' initial
// value. Inline, so that the procedural textures' loops over lattice corners and cells vectorise;
// shared by procedural_noise.cpp and procedural_cells.cpp.
#pragma once
#include <cstdint>

#define SMIS_HASH_INLINE inline __attribute__((always_inline))

namespace smis::shading::lookup3 {

SMIS_HASH_INLINE uint32_t rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

// The mixing of three words (used by the 4-word hash).
SMIS_HASH_INLINE void mix(uint32_t& a, uint32_t& b, uint32_t& c) {
    a -= c; a ^= rot(c, 4);  c += b;
    b -= a; b ^= rot(a, 6);  a += c;
    c -= b; c ^= rot(b, 8);  b += a;
    a -= c; a ^= rot(c, 16); c += b;
    b -= a; b ^= rot(a, 19); a += c;
    c -= b; c ^= rot(b, 4);  b += a;
}

// The final avalanche; the hash is c.
SMIS_HASH_INLINE void final(uint32_t& a, uint32_t& b, uint32_t& c) {
    c ^= b; c -= rot(b, 14);
    a ^= c; a -= rot(c, 11);
    b ^= a; b -= rot(a, 25);
    c ^= b; c -= rot(b, 16);
    a ^= c; a -= rot(c, 4);
    b ^= a; b -= rot(a, 14);
    c ^= b; c -= rot(b, 24);
}

// The state starts at 0xdeadbeef + (length in bytes) + initval, initval being 13 in Cycles.
constexpr uint32_t seed_for(uint32_t words) { return 0xdeadbeefu + (words << 2) + 13u; }

SMIS_HASH_INLINE uint32_t hash1(uint32_t kx) {
    uint32_t a = seed_for(1) + kx, b = seed_for(1), c = seed_for(1);
    final(a, b, c);
    return c;
}
SMIS_HASH_INLINE uint32_t hash2(uint32_t kx, uint32_t ky) {
    uint32_t a = seed_for(2) + kx, b = seed_for(2) + ky, c = seed_for(2);
    final(a, b, c);
    return c;
}
SMIS_HASH_INLINE uint32_t hash3(uint32_t kx, uint32_t ky, uint32_t kz) {
    uint32_t a = seed_for(3) + kx, b = seed_for(3) + ky, c = seed_for(3) + kz;
    final(a, b, c);
    return c;
}
SMIS_HASH_INLINE uint32_t hash4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw) {
    uint32_t a = seed_for(4) + kx, b = seed_for(4) + ky, c = seed_for(4) + kz;
    mix(a, b, c);
    a += kw;
    final(a, b, c);
    return c;
}

}  // namespace smis::shading::lookup3
