// Hashed uniform grid over points, built by a counting sort in O(n) (no per-cell allocation).
// Every point remembers its cell key, so a query visiting a cell reports only that cell's points
// even when two cells share a hash bucket: no duplicates, whatever the collisions.
#pragma once
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/rng.h"

namespace smis {

class HashGrid {
public:
    // points[i] for i in `indices`; cell size > 0.
    void build(const std::vector<Vec3>& points, const std::vector<uint32_t>& indices, float cell_size) {
        cell_ = cell_size > 0.0f && std::isfinite(cell_size) ? cell_size : 1.0f;
        inv_cell_ = 1.0f / cell_;
        buckets_ = 1;
        while (buckets_ < 2 * indices.size()) buckets_ <<= 1;
        start_.assign(buckets_ + 1, 0);
        entries_.resize(indices.size());
        std::vector<uint64_t> keys(indices.size());
        for (size_t k = 0; k < indices.size(); ++k) {
            keys[k] = key_of(points[indices[k]]);
            start_[bucket(keys[k]) + 1]++;
        }
        for (size_t b = 0; b < buckets_; ++b) start_[b + 1] += start_[b];
        std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
        // Indices are inserted in their given order, so each bucket lists points in a fixed order.
        for (size_t k = 0; k < indices.size(); ++k) entries_[fill[bucket(keys[k])]++] = {keys[k], indices[k]};
    }

    // fn(index) for every point in the cells overlapping the ball (p, r); the caller tests distance.
    template <class Fn>
    void query(const Vec3& p, float r, Fn&& fn) const {
        if (entries_.empty()) return;
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = cell_coord(p[a] - r);
            hi[a] = cell_coord(p[a] + r);
        }
        // A ball far larger than the cells (an infinite or huge radius, e.g. a pixel seeing geometry
        // at 1e5 while the median radius is tiny) spans up to (2e6)^3 cells: the loop below then
        // never ends (a hang found by fuzz_test). When the box covers far more cells than there are
        // points, scan the points instead and report those whose cell lies in the box: the same set
        // (only the visiting order differs). Ordinary queries (8-27 cells) never take this branch.
        double cells = 1.0;
        for (int a = 0; a < 3; ++a) cells *= double(hi[a]) - double(lo[a]) + 1.0;
        if (cells > 8.0 * double(entries_.size()) + 1024.0) {
            for (const Entry& e : entries_) {
                int c[3];
                unpack(e.key, c);
                if (c[0] >= lo[0] && c[0] <= hi[0] && c[1] >= lo[1] && c[1] <= hi[1] && c[2] >= lo[2] && c[2] <= hi[2])
                    fn(e.index);
            }
            return;
        }
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    uint64_t key = pack(x, y, z);
                    size_t b = bucket(key);
                    for (uint32_t e = start_[b]; e < start_[b + 1]; ++e)
                        if (entries_[e].key == key) fn(entries_[e].index);
                }
    }
    float cell_size() const { return cell_; }
    size_t memory_bytes() const { return start_.capacity() * sizeof(uint32_t) + entries_.capacity() * sizeof(Entry); }

private:
    struct Entry {
        uint64_t key;
        uint32_t index;
    };
    int cell_coord(float v) const {
        float c = std::floor(v * inv_cell_);
        return static_cast<int>(clampf(c, -1e6f, 1e6f));  // far-away points share the border cells
    }
    static uint64_t pack(int x, int y, int z) {
        auto u = [](int v) { return static_cast<uint64_t>(static_cast<uint32_t>(v + (1 << 20)) & 0x1FFFFF); };
        return (u(x) << 42) | (u(y) << 21) | u(z);
    }
    static void unpack(uint64_t key, int* c) {
        for (int a = 0; a < 3; ++a) c[a] = int((key >> (42 - 21 * a)) & 0x1FFFFF) - (1 << 20);
    }
    uint64_t key_of(const Vec3& p) const { return pack(cell_coord(p.x), cell_coord(p.y), cell_coord(p.z)); }
    // A full 64-bit mix: a plain multiplicative hash keeps x out of the low bits, and cells that
    // differ only in x then all share one bucket.
    size_t bucket(uint64_t key) const { return static_cast<size_t>(mix64(key)) & (buckets_ - 1); }
    float cell_ = 1.0f, inv_cell_ = 1.0f;
    size_t buckets_ = 1;
    std::vector<uint32_t> start_;
    std::vector<Entry> entries_;
};

}  // namespace smis
