// Hashed uniform grid over points, built by counting sorts in O(n) (no per-cell allocation).
// Points are stored cell by cell (structure of arrays), and a table of cells, grouped by hash bucket,
// gives each cell's key and range: a query compares one key per cell (so cells sharing a bucket are
// told apart, and no point is reported twice), then tests its cell's points in a tight loop.
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
        const size_t n = indices.size();
        buckets_ = 1;
        while (buckets_ < 2 * n) buckets_ <<= 1;
        std::vector<uint64_t> keys(n);
        std::vector<uint32_t> count(buckets_ + 1, 0);
        for (size_t k = 0; k < n; ++k) {
            keys[k] = key_of(points[indices[k]]);
            count[bucket(keys[k]) + 1]++;
        }
        for (size_t b = 0; b < buckets_; ++b) count[b + 1] += count[b];
        // Counting sort by bucket, in the given order (so every cell lists its points in a fixed order).
        std::vector<uint32_t> order(n), fill(count.begin(), count.end() - 1);
        for (size_t k = 0; k < n; ++k) order[fill[bucket(keys[k])]++] = static_cast<uint32_t>(k);
        // Within a bucket, group the points by cell: a stable insertion sort by key, over a bucket's
        // few points (they share a bucket because they share a cell, save for rare collisions).
        for (size_t b = 0; b < buckets_; ++b)
            for (uint32_t i = count[b] + 1; i < count[b + 1]; ++i)
                for (uint32_t j = i; j > count[b] && keys[order[j]] < keys[order[j - 1]]; --j) std::swap(order[j], order[j - 1]);
        xs_.resize(n), ys_.resize(n), zs_.resize(n), index_.resize(n);
        cells_.clear();
        bucket_cells_.assign(buckets_ + 1, 0);
        for (size_t b = 0, e = 0; b < buckets_; ++b) {
            bucket_cells_[b] = static_cast<uint32_t>(cells_.size());
            for (; e < count[b + 1]; ++e) {
                uint32_t k = order[e];
                if (e == count[b] || keys[k] != cells_.back().key) cells_.push_back({keys[k], uint32_t(e), uint32_t(e)});
                cells_.back().end = uint32_t(e + 1);
                const Vec3& p = points[indices[k]];
                xs_[e] = p.x, ys_[e] = p.y, zs_[e] = p.z;
                index_[e] = indices[k];
            }
        }
        bucket_cells_[buckets_] = static_cast<uint32_t>(cells_.size());
    }

    // Appends to `out` the index of every point within distance r of p (squared distance <= r^2),
    // each once, in a fixed order (cells in x, y, z order, a cell's points in insertion order).
    void query_ball(const Vec3& p, float r, std::vector<uint32_t>& out) const {
        if (index_.empty() || !(r >= 0.0f)) return;
        int lo[3], hi[3];
        for (int a = 0; a < 3; ++a) {
            lo[a] = cell_coord(p[a] - r);
            hi[a] = cell_coord(p[a] + r);
        }
        // A ball far larger than the cells (an infinite or huge radius, e.g. a pixel seeing geometry
        // at 1e5 while the median radius is tiny) spans up to (2e6)^3 cells: the cell loop below then
        // never ends (a hang found by fuzz_test). When the box covers far more cells than there are
        // points, every point is tested instead: the same set (only the visiting order differs).
        // Ordinary queries (8-27 cells) never take this branch.
        double cells = 1.0;
        for (int a = 0; a < 3; ++a) cells *= double(hi[a]) - double(lo[a]) + 1.0;
        if (cells > 8.0 * double(index_.size()) + 1024.0) {
            test_points(p, r * r, 0, uint32_t(index_.size()), out);
            return;
        }
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    uint64_t key = pack(x, y, z);
                    size_t b = bucket(key);
                    for (uint32_t c = bucket_cells_[b]; c < bucket_cells_[b + 1]; ++c)
                        if (cells_[c].key == key) test_points(p, r * r, cells_[c].begin, cells_[c].end, out);
                }
    }
    float cell_size() const { return cell_; }
    size_t memory_bytes() const {
        return (xs_.capacity() + ys_.capacity() + zs_.capacity()) * sizeof(float) + index_.capacity() * sizeof(uint32_t) +
               cells_.capacity() * sizeof(Cell) + bucket_cells_.capacity() * sizeof(uint32_t);
    }

private:
    struct Cell {
        uint64_t key;
        uint32_t begin, end;  // its points in xs_/ys_/zs_/index_
    };
    // Without branches on the distance test (about a third of the box's points are in the ball, an
    // unpredictable branch): every index is written, the count advances only for points inside.
    void test_points(const Vec3& p, float r2, uint32_t begin, uint32_t end, std::vector<uint32_t>& out) const {
        size_t m = out.size();
        out.resize(m + (end - begin));
        uint32_t* o = out.data();
        for (uint32_t e = begin; e < end; ++e) {
            float dx = xs_[e] - p.x, dy = ys_[e] - p.y, dz = zs_[e] - p.z;
            o[m] = index_[e];
            m += (dx * dx + dy * dy + dz * dz <= r2) ? 1 : 0;
        }
        out.resize(m);
    }
    int cell_coord(float v) const {
        float c = std::floor(v * inv_cell_);
        return static_cast<int>(clampf(c, -1e6f, 1e6f));  // far-away points share the border cells
    }
    static uint64_t pack(int x, int y, int z) {
        auto u = [](int v) { return static_cast<uint64_t>(static_cast<uint32_t>(v + (1 << 20)) & 0x1FFFFF); };
        return (u(x) << 42) | (u(y) << 21) | u(z);
    }
    uint64_t key_of(const Vec3& p) const { return pack(cell_coord(p.x), cell_coord(p.y), cell_coord(p.z)); }
    // A full 64-bit mix: a plain multiplicative hash keeps x out of the low bits, and cells that
    // differ only in x then all share one bucket.
    size_t bucket(uint64_t key) const { return static_cast<size_t>(mix64(key)) & (buckets_ - 1); }
    float cell_ = 1.0f, inv_cell_ = 1.0f;
    size_t buckets_ = 1;
    std::vector<float> xs_, ys_, zs_;
    std::vector<uint32_t> index_;
    std::vector<Cell> cells_;
    std::vector<uint32_t> bucket_cells_;  // bucket b's cells: cells_[bucket_cells_[b] .. bucket_cells_[b + 1])
};

}  // namespace smis
