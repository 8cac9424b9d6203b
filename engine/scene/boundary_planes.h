// The planes of the pass-through boundaries (media boundaries without a surface shader), so that a
// shadow ray in a medium can tell without a BVH query that it crosses none of them: a segment whose
// two ends lie strictly on one side of a triangle's plane cannot meet the triangle. A fog box has
// six planes, and a shadow ray from inside it to a light inside it stays on the inner side of all
// six. The test is conservative (a margin covers Embree's rounding and the planes' own), so a
// segment it passes is one the BVH would also find clear of boundaries; anything else, and scenes
// with moving or too many boundary planes, go to the BVH (volume.cpp's shadow rays).
#pragma once
#include <vector>

#include "core/math.h"

namespace smis {

class BoundaryPlanes {
public:
    static constexpr size_t kMaxPlanes = 32;  // beyond, the test costs about what a BVH query does

    // Starts over for a scene whose coordinates stay within `extent` of the origin (sets the margin).
    void reset(float extent);
    // A pass-through triangle (world space); one that is degenerate, or more than kMaxPlanes planes
    // in all, turns the test off.
    void add_triangle(const Vec3& a, const Vec3& b, const Vec3& c);
    // A boundary that moves (motion blur): the test is off.
    void disable() { usable_ = false; }
    // The test is on (no boundaries at all counts as on: every segment is clear).
    bool usable() const { return usable_; }
    // True when the segment from a to b surely crosses no boundary (a and b strictly on one side of
    // every plane); false when it may cross one, or for non-finite ends.
    bool separated(const Vec3& a, const Vec3& b) const;
    size_t size() const { return planes_.size(); }

private:
    struct Plane {
        Vec3 n;   // unit normal
        float d;  // n . p = d on the plane
    };
    std::vector<Plane> planes_;
    float margin_ = 0.0f;
    bool usable_ = true;
};

}  // namespace smis
