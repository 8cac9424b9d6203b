// The hashed grid of path-space filtering: a ball query reports exactly the points within the
// radius, each once, whatever the hash collisions, the cell size and the radius (down to zero,
// up to a radius covering far more cells than there are points); a sampled ball query draws a
// uniform random subset of that set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
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

// sample_ball(k) returns min(k, m) distinct points of the ball (m its points other than `skip`),
// never `skip`, and each point of the ball with probability k/m: checked by a chi-square test of
// the selection counts over many draws, for balls that take the rejection route (few of a box's
// points needed), the exhaustive end (a ball holding about k points, or a thin ball in a full
// box) and the huge-box fallback.
TEST(HashGrid, SampledBallQueryIsAUniformSubsetOfTheBall) {
    Rng rng(5, 1);
    std::vector<Vec3> points;
    for (int i = 0; i < 4000; ++i) {  // a plane, as most stored vertices lie on surfaces, and a cloud
        float u = rng.next_float(), v = rng.next_float(), w = rng.next_float();
        points.push_back(i % 4 ? Vec3(u * 4.0f, v * 4.0f, 1.0f) : Vec3(u * 4.0f, v * 4.0f, w * 4.0f));
    }
    std::vector<uint32_t> indices;
    for (uint32_t i = 0; i < points.size(); ++i) indices.push_back(i);
    HashGrid grid;
    grid.build(points, indices, 0.3f);
    HashGrid::SampleScratch scratch;
    struct Case {
        Vec3 c;
        float r;
        size_t k;
    };
    const Case cases[] = {{Vec3(2.0f, 2.0f, 1.0f), 0.3f, 15},  {Vec3(2.0f, 2.0f, 1.0f), 0.1f, 15},
                          {Vec3(2.0f, 2.0f, 2.5f), 0.45f, 6},  {Vec3(1.0f, 3.0f, 1.1f), 0.2f, 40},
                          {Vec3(2.0f, 2.0f, 1.0f), 1e7f, 15}};
    for (const Case& cs : cases) {
        std::vector<uint32_t> ball;
        grid.query_ball(cs.c, cs.r, ball);
        std::sort(ball.begin(), ball.end());
        const uint32_t skip = ball.empty() ? 0u : ball[ball.size() / 2];
        ball.erase(std::remove(ball.begin(), ball.end(), skip), ball.end());
        const size_t m = ball.size(), want = std::min(cs.k, m);
        ASSERT_GT(m, 0u);
        std::map<uint32_t, int> hits;
        const int draws = 20000;
        for (int d = 0; d < draws; ++d) {
            std::vector<uint32_t> got;
            grid.sample_ball(cs.c, cs.r, cs.k, skip, rng, scratch, got);
            ASSERT_EQ(got.size(), want) << "r " << cs.r;
            std::vector<uint32_t> sorted = got;
            std::sort(sorted.begin(), sorted.end());
            ASSERT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end()) << "a point drawn twice";
            for (uint32_t i : got) {
                ASSERT_TRUE(std::binary_search(ball.begin(), ball.end(), i)) << "point " << i << " not in the ball";
                ++hits[i];
            }
        }
        if (want == m) {  // all of them, every time
            EXPECT_EQ(hits.size(), m);
            continue;
        }
        // Each point's count is Binomial(draws, k/m); sum of squared standardised deviations is about
        // chi-square with m - 1 degrees of freedom (the counts sum to draws k). Bound: mean + 5 sd.
        const double p = double(want) / double(m), expect = draws * p;
        double chi2 = 0.0;
        for (uint32_t i : ball) {
            double o = hits.count(i) ? hits[i] : 0;
            chi2 += (o - expect) * (o - expect) / (expect * (1.0 - p));
        }
        const double dof = double(m) - 1.0;
        EXPECT_LT(chi2, dof + 5.0 * std::sqrt(2.0 * dof)) << "r " << cs.r << " m " << m;
    }
}

}  // namespace
}  // namespace smis
