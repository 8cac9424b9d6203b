// Hair curves (curves.cpp): a ray leaving a strand ignores the whole strand, every segment of it, as
// Cycles 3.4's Embree filter does (it compares the hit segment's curve, curve_segments[prim].prim,
// with the ray's own); other strands still block it.
#include <gtest/gtest.h>

#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

// A hairpin (up at x = 0, over, down at x = 0.2: its first and last segments face each other across
// 0.16 m) and a straight strand at x = 0.5, radius 0.02.
TEST(Curves, RaysLeavingAStrandIgnoreAllOfItsSegments) {
    Scene s;
    uint32_t m = s.add_material(diffuse(Color(0.5f)));
    const float r = 0.02f;
    const float points[] = {0.0f, 0.0f, 0.0f, r,   0.0f, 0.0f, 1.0f, r,   0.1f, 0.0f, 1.1f, r,
                            0.2f, 0.0f, 1.0f, r,   0.2f, 0.0f, 0.0f, r,   0.5f, 0.0f, 0.0f, r,
                            0.5f, 0.0f, 1.0f, r};
    const int32_t offsets[] = {0, 5, 7};
    s.add_instance(s.add_curves(points, 7, offsets, 2, m), Transform());
    s.set_camera(camera_at(Vec3(0.0f, -5.0f, 0.5f), 4, 4));
    s.commit();
    auto hit_x = [&](const Vec3& o, float dx) {
        SurfaceHit h;
        return s.intersect(Ray{o, Vec3(dx, 0.0f, 0.0f)}, &h) ? h.p.x : -1.0f;
    };
    // From outside, the hairpin's first arm is hit (its centre line bows towards -x, away from the
    // next control point: Catmull-Rom).
    const float arm = hit_x(Vec3(-1.0f, 0.0f, 0.5f), 1.0f);
    EXPECT_NEAR(arm, -r, 0.01f);
    // From there through the fibre (a transmission's ray, starting on segment 0): the hairpin's
    // other arm (segment 3) is ignored, the straight strand is not, as in Cycles.
    EXPECT_NEAR(hit_x(Vec3(arm, 0.0f, 0.5f), 1.0f), 0.5f - r, 1e-4f);
    // From the straight strand's surface the hairpin is another strand: its second arm, the mirror
    // image of the first about x = 0.1, is hit.
    EXPECT_NEAR(hit_x(Vec3(0.5f - r, 0.0f, 0.5f), -1.0f), 0.2f - arm, 1e-4f);
}
