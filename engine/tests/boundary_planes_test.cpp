// The pass-through boundaries' planes (scene/boundary_planes.h): a segment is reported clear of them
// only when both ends lie strictly on one side of every plane, with the margin.
#include <gtest/gtest.h>

#include <cmath>

#include "scene/boundary_planes.h"

using namespace smis;

namespace {

// The twelve triangles of the box [lo, hi], as add_box (test_scenes.h) makes them.
void add_box_triangles(BoundaryPlanes& planes, const Vec3& lo, const Vec3& hi) {
    const Vec3 v[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                       {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
    const int t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                     1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
    for (int i = 0; i < 36; i += 3) planes.add_triangle(v[t[i]], v[t[i + 1]], v[t[i + 2]]);
}

}  // namespace

TEST(BoundaryPlanes, ABoxIsSixPlanesThatSeparateOnlySegmentsOnOneSideOfEach) {
    BoundaryPlanes planes;
    planes.reset(4.0f);
    add_box_triangles(planes, {-3.0f, -3.0f, -0.3f}, {3.0f, 3.0f, 3.6f});
    ASSERT_TRUE(planes.usable());
    EXPECT_EQ(planes.size(), 6u);  // two triangles per face, one plane
    // Inside to inside, and outside to outside beyond the same face: clear.
    EXPECT_TRUE(planes.separated({0.0f, 0.0f, 1.0f}, {2.9f, -2.5f, 3.5f}));
    EXPECT_TRUE(planes.separated({4.0f, 0.0f, 1.0f}, {5.0f, 1.0f, 2.0f}));
    // Inside to outside, and outside to outside across the box: maybe crossing.
    EXPECT_FALSE(planes.separated({0.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 4.0f}));
    EXPECT_FALSE(planes.separated({-4.0f, 0.0f, 1.0f}, {4.0f, 0.0f, 1.0f}));
    // Outside on different sides of one plane but missing the box would cross no triangle, but
    // the test only knows planes: conservative.
    EXPECT_FALSE(planes.separated({4.0f, -4.0f, 1.0f}, {4.0f, 4.0f, 1.0f}));
    // Within the margin (1e-4 of the extent) of a face: the BVH decides.
    EXPECT_FALSE(planes.separated({0.0f, 0.0f, 1.0f}, {2.9999f, 0.0f, 1.0f}));
    EXPECT_TRUE(planes.separated({0.0f, 0.0f, 1.0f}, {2.998f, 0.0f, 1.0f}));
    // Non-finite ends are never clear.
    EXPECT_FALSE(planes.separated({0.0f, 0.0f, 1.0f}, {NAN, 0.0f, 1.0f}));
    EXPECT_FALSE(planes.separated({0.0f, 0.0f, 1.0f}, {INFINITY, 0.0f, 1.0f}));
}

TEST(BoundaryPlanes, NoBoundariesSeparateEverythingAndBadInputTurnsTheTestOff) {
    BoundaryPlanes none;
    none.reset(1.0f);
    EXPECT_TRUE(none.usable());
    EXPECT_TRUE(none.separated({0.0f, 0.0f, 0.0f}, {1.0f, 2.0f, 3.0f}));

    BoundaryPlanes degenerate;
    degenerate.reset(1.0f);
    degenerate.add_triangle({0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {2.0f, 0.0f, 0.0f});
    EXPECT_FALSE(degenerate.usable());
    EXPECT_FALSE(degenerate.separated({0.0f, 1.0f, 0.0f}, {0.0f, 2.0f, 0.0f}));

    BoundaryPlanes many;  // a finely tessellated sphere: more planes than the test is worth
    many.reset(2.0f);
    for (int i = 0; i < int(BoundaryPlanes::kMaxPlanes) + 1; ++i) {
        float a = 0.1f * float(i), c = std::cos(a), s = std::sin(a);
        many.add_triangle({c, s, 0.0f}, {c, s, 1.0f}, {c - s, s + c, 0.0f});
    }
    EXPECT_FALSE(many.usable());

    BoundaryPlanes moving;
    moving.reset(1.0f);
    moving.disable();
    EXPECT_FALSE(moving.separated({0.0f, 0.0f, 0.0f}, {0.1f, 0.0f, 0.0f}));

    BoundaryPlanes unbounded;
    unbounded.reset(INFINITY);
    EXPECT_FALSE(unbounded.usable());
}
