// Hashed uniform grid over points, built by counting sorts in O(n) (no per-cell allocation).
// Points are stored cell by cell (structure of arrays), and a table of cells, grouped by hash bucket,
// gives each cell's key and range: a query compares one key per cell (so cells sharing a bucket are
// told apart, and no point is reported twice), then tests its cell's points in a tight loop.
#pragma once
#include <algorithm>
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
        if (!box_cells(p, r, lo, hi)) {
            test_points(p, r * r, 0, uint32_t(index_.size()), out);
            return;
        }
        for_each_cell(lo, hi, [&](const Cell& c) { test_points(p, r * r, c.begin, c.end, out); });
    }
    // Scratch of sample_ball, kept by the caller (one per thread) so a query allocates nothing.
    struct SampleScratch {
        std::vector<uint32_t> begin, offset;  // the box's non-empty cells: first point, running count
        std::vector<uint64_t> drawn;          // bit set over the box's points
        std::vector<uint32_t> rest;           // in-ball points not drawn yet (the exhaustive end)
    };

    // Appends to `out` min(k, m) points drawn uniformly without replacement from the m points within
    // distance r of p other than `skip`: the same distribution as query_ball followed by a partial
    // Fisher-Yates shuffle, without testing every point of the query's box. Points of the box are
    // drawn in uniformly random order (a bit set rejects repeats) and kept when inside the ball, so
    // the kept ones are the ball's points in uniformly random order; the first k are a uniform
    // subset. A filter keeps ~16 of the ~110 points in a 6-pixel ball out of ~340 in its box, so this
    // tests ~50 points where query_ball tests all 340. When half the box has been drawn (a ball
    // holding fewer than k, or a box mostly outside the ball), the undrawn rest is scanned and the
    // shuffle finished over its in-ball points, which continues the same random order.
    void sample_ball(const Vec3& p, float r, size_t k, uint32_t skip, Rng& rng, SampleScratch& scratch,
                     std::vector<uint32_t>& out) const {
        if (index_.empty() || !(r >= 0.0f) || k == 0) return;
        int lo[3], hi[3];
        if (!box_cells(p, r, lo, hi)) {  // a huge box: every point (see query_ball)
            std::vector<uint32_t>& all = scratch.rest;
            all.clear();
            test_points(p, r * r, 0, uint32_t(index_.size()), all);
            take_uniform_subset(all, skip, k, rng, out);
            return;
        }
        std::vector<uint32_t>& begin = scratch.begin;
        std::vector<uint32_t>& offset = scratch.offset;
        begin.clear(), offset.assign(1, 0);
        for_each_cell(lo, hi, [&](const Cell& c) {
            begin.push_back(c.begin);
            offset.push_back(offset.back() + (c.end - c.begin));
        });
        const uint32_t n = offset.back();
        if (n == 0) return;
        const float r2 = r * r;
        std::vector<uint64_t>& drawn = scratch.drawn;
        drawn.assign((n + 63) / 64, 0);
        auto point = [&](uint32_t v) {  // the box's v-th point
            size_t c = 0;
            while (offset[c + 1] <= v) ++c;
            return begin[c] + (v - offset[c]);
        };
        auto inside = [&](uint32_t e) {
            float dx = xs_[e] - p.x, dy = ys_[e] - p.y, dz = zs_[e] - p.z;
            return dx * dx + dy * dy + dz * dz <= r2 && index_[e] != skip;
        };
        size_t taken = 0;
        for (uint32_t distinct = 0; taken < k && 2 * distinct < n;) {
            uint32_t v = uint32_t((uint64_t(rng.next_u32()) * n) >> 32);
            uint64_t bit = uint64_t(1) << (v & 63);
            if (drawn[v >> 6] & bit) continue;
            drawn[v >> 6] |= bit;
            ++distinct;
            uint32_t e = point(v);
            if (inside(e)) out.push_back(index_[e]), ++taken;
        }
        if (taken == k) return;
        std::vector<uint32_t>& rest = scratch.rest;
        rest.clear();
        for (size_t c = 0; c < begin.size(); ++c)
            for (uint32_t v = offset[c]; v < offset[c + 1]; ++v)
                if (!(drawn[v >> 6] & (uint64_t(1) << (v & 63))) && inside(begin[c] + (v - offset[c])))
                    rest.push_back(index_[begin[c] + (v - offset[c])]);
        take_uniform_subset(rest, ~0u, k - taken, rng, out);
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
    // The cells of the box around the ball of radius r at p. False for a ball far larger than the
    // cells (an infinite or huge radius, e.g. a pixel seeing geometry at 1e5 while the median radius
    // is tiny): its box spans up to (2e6)^3 cells and a loop over them never ends (a hang found by
    // fuzz_test), so the caller tests every point instead, which gives the same set. Ordinary
    // queries (8-27 cells) never take that branch.
    bool box_cells(const Vec3& p, float r, int lo[3], int hi[3]) const {
        for (int a = 0; a < 3; ++a) {
            lo[a] = cell_coord(p[a] - r);
            hi[a] = cell_coord(p[a] + r);
        }
        double cells = 1.0;
        for (int a = 0; a < 3; ++a) cells *= double(hi[a]) - double(lo[a]) + 1.0;
        return cells <= 8.0 * double(index_.size()) + 1024.0;
    }
    // fn(cell) for every non-empty cell of the box, in x, y, z order.
    template <class Fn>
    void for_each_cell(const int lo[3], const int hi[3], Fn&& fn) const {
        for (int x = lo[0]; x <= hi[0]; ++x)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int z = lo[2]; z <= hi[2]; ++z) {
                    uint64_t key = pack(x, y, z);
                    size_t b = bucket(key);
                    for (uint32_t c = bucket_cells_[b]; c < bucket_cells_[b + 1]; ++c)
                        if (cells_[c].key == key) fn(cells_[c]);
                }
    }
    // Appends min(k, |from \ {skip}|) elements of `from`, a uniform subset in random order (partial
    // Fisher-Yates; `from` is shuffled in place).
    static void take_uniform_subset(std::vector<uint32_t>& from, uint32_t skip, size_t k, Rng& rng,
                                    std::vector<uint32_t>& out) {
        from.erase(std::remove(from.begin(), from.end(), skip), from.end());
        const size_t m = std::min(k, from.size());
        for (size_t i = 0; i < m; ++i) {
            size_t j = i + size_t((uint64_t(rng.next_u32()) * (from.size() - i)) >> 32);
            std::swap(from[i], from[j]);
            out.push_back(from[i]);
        }
    }
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
