// The hashed grid of path-space filtering: a ball query reports exactly the points within the
// radius, each once, whatever the hash collisions, the cell size and the radius (down to zero,
// up to a radius covering far more cells than there are points).
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/rng.h"
#include "integrators/hash_grid.h"

namespace smis {
namespace {

TEST(HashGrid, BallQueryIsExactlyTheBruteForceSet) {
    Rng rng(3, 9);
    for (int trial = 0; trial < 40; ++trial) {
        // Points on a few planes and in a cloud, some coincident, as stored vertices are.
        const size_t n = 50 + rng.next_u32() % 2000;
        std::vector<Vec3> points(n);
        for (size_t i = 0; i < n; ++i) {
            Vec3 p(rng.next_float() * 4.0f, rng.next_float() * 4.0f, rng.next_float() * 4.0f);
            if (i % 3 == 0) p.z = 1.0f;
            if (i % 17 == 0 && i > 0) p = points[i - 1];
            points[i] = p;
        }
        std::vector<uint32_t> indices;  // a subset, as only pixels with a vertex are stored
        for (uint32_t i = 0; i < n; ++i)
            if (rng.next_float() < 0.9f) indices.push_back(i);
        const float cell = 0.02f + 0.5f * rng.next_float();
        HashGrid grid;
        grid.build(points, indices, cell);
        for (int q = 0; q < 30; ++q) {
            Vec3 c(rng.next_float() * 5.0f - 0.5f, rng.next_float() * 5.0f - 0.5f, rng.next_float() * 5.0f - 0.5f);
            float r = q == 0 ? 0.0f : (q == 1 ? 1e4f : cell * 3.0f * rng.next_float());
            // Centred on stored points: with r = 0 the point itself (and its duplicates) is in the ball.
            if (q == 0 || q == 2) c = points[indices[q]];
            std::vector<uint32_t> got;
            grid.query_ball(c, r, got);
            std::vector<uint32_t> want;
            for (uint32_t i : indices)
                if (length_sq(points[i] - c) <= r * r) want.push_back(i);
            std::sort(got.begin(), got.end());
            EXPECT_EQ(got, want) << "trial " << trial << " query " << q << " r " << r;
        }
    }
}

}  // namespace
}  // namespace smis
