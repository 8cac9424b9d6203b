// Pointiness and Random Per Island as Cycles derives them from a mesh (scene/mesh_attributes.h).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "scene/mesh_attributes.h"
#include "shading/lookup3.h"

namespace smis {
namespace {

// A 3 x 3 grid of vertices in the plane z = 0 (normals +z), edges along rows, columns and one
// diagonal per cell.
struct Grid {
    std::vector<float> positions, normals;
    std::vector<int32_t> edges;
    Grid() {
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 3; ++x) {
                positions.insert(positions.end(), {float(x), float(y), 0.0f});
                normals.insert(normals.end(), {0.0f, 0.0f, 1.0f});
            }
        auto id = [](int x, int y) { return y * 3 + x; };
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 3; ++x) {
                if (x < 2) edges.insert(edges.end(), {id(x, y), id(x + 1, y)});
                if (y < 2) edges.insert(edges.end(), {id(x, y), id(x, y + 1)});
                if (x < 2 && y < 2) edges.insert(edges.end(), {id(x, y), id(x + 1, y + 1)});
            }
    }
};

TEST(MeshAttributes, PointinessIsOneHalfOnAFlatInterior) {
    Grid g;
    std::vector<float> p = mesh_pointiness(g.positions.data(), g.normals.data(), 9, g.edges.data(), g.edges.size() / 2);
    // The centre's edges balance out: the mean edge direction is 0 and acos(0) / pi = 0.5; its
    // neighbours on the border are also perpendicular to their normals on average.
    EXPECT_NEAR(p[4], 0.5f, 1e-6f);
    for (float v : p) EXPECT_NEAR(v, 0.5f, 1e-6f);
}

TEST(MeshAttributes, PointinessOfACubesCornersIsTheirAngle) {
    // Every corner of a cube: the mean edge direction points into the cube, 180 - 54.7 degrees from
    // the corner's normal; all corners alike, so the blur keeps the value. Normals turned inwards
    // (a cavity) give the supplement.
    std::vector<float> positions, normals;
    for (int k = 0; k < 8; ++k) {
        const float x = (k & 1) ? 1.0f : -1.0f, y = (k & 2) ? 1.0f : -1.0f, z = (k & 4) ? 1.0f : -1.0f;
        positions.insert(positions.end(), {x, y, z});
        const float s = 1.0f / std::sqrt(3.0f);
        normals.insert(normals.end(), {x * s, y * s, z * s});
    }
    std::vector<int32_t> edges;
    for (int k = 0; k < 8; ++k)
        for (int bit : {1, 2, 4})
            if (!(k & bit)) edges.insert(edges.end(), {k, k | bit});
    ASSERT_EQ(edges.size(), 24u);
    const float convex = std::acos(-1.0f / std::sqrt(3.0f)) / 3.14159265f;
    for (float v : mesh_pointiness(positions.data(), normals.data(), 8, edges.data(), 12)) EXPECT_NEAR(v, convex, 1e-5f);
    for (float& n : normals) n = -n;
    for (float v : mesh_pointiness(positions.data(), normals.data(), 8, edges.data(), 12))
        EXPECT_NEAR(v, 1.0f - convex, 1e-5f);
}

TEST(MeshAttributes, PointinessWeldsCopiesAtOnePosition) {
    // The tent again, its tip duplicated: the copy takes two of the tip's edges. Cycles welds the
    // copies, so both get the value the unsplit mesh gives the tip.
    Grid g;
    g.positions[4 * 3 + 2] = 1.0f;
    std::vector<float> whole = mesh_pointiness(g.positions.data(), g.normals.data(), 9, g.edges.data(), g.edges.size() / 2);
    Grid s;
    s.positions[4 * 3 + 2] = 1.0f;
    s.positions.insert(s.positions.end(), {1.0f, 1.0f, 1.0f});
    s.normals.insert(s.normals.end(), {0.0f, 0.0f, 1.0f});
    int moved = 0;
    for (size_t e = 0; e < s.edges.size() && moved < 2; e += 2)
        if (s.edges[e] == 4) s.edges[e] = 9, ++moved;
    std::vector<float> split = mesh_pointiness(s.positions.data(), s.normals.data(), 10, s.edges.data(), s.edges.size() / 2);
    EXPECT_NEAR(split[4], whole[4], 1e-6f);
    EXPECT_NEAR(split[9], whole[4], 1e-6f);
}

TEST(MeshAttributes, RandomPerIslandIsTheHashOfTheUnionByRankRoot) {
    // Two islands: a triangle (0, 1, 2) and an edge chain (3, 4), (4, 5). Union by rank: joining 0
    // and 1 makes 0 the root (equal ranks: the first), then 2 joins under 0; for the chain 3 is root.
    const std::vector<int32_t> edges = {0, 1, 1, 2, 2, 0, 3, 4, 4, 5};
    const std::vector<int32_t> first = {2, 5, 0};
    std::vector<float> r = mesh_random_per_island(6, edges.data(), edges.size() / 2, first.data(), first.size());
    auto expected = [](uint32_t root) { return float(shading::lookup3::hash1(root)) / float(0xFFFFFFFFu); };
    EXPECT_EQ(r[0], expected(0));
    EXPECT_EQ(r[1], expected(3));
    EXPECT_EQ(r[2], r[0]);
    EXPECT_NE(r[0], r[1]);
}

TEST(MeshAttributes, BadIndicesAreRefused) {
    const std::vector<int32_t> edges = {0, 7};
    const std::vector<int32_t> first = {0};
    EXPECT_THROW(mesh_random_per_island(3, edges.data(), 1, first.data(), 1), std::invalid_argument);
    const std::vector<float> p(9, 0.0f), n(9, 0.0f);
    EXPECT_THROW(mesh_pointiness(p.data(), n.data(), 3, edges.data(), 1), std::invalid_argument);
}

}  // namespace
}  // namespace smis
