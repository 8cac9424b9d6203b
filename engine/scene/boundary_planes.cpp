#include "scene/boundary_planes.h"

#include <algorithm>
#include <cmath>

namespace smis {

namespace {

// Relative to the scene's extent: the margin a segment's ends must keep from a plane, and the
// tolerance within which two triangles count as one plane (a box's two triangles per face). Float
// rounding of a plane test at coordinates of size E is about 1e-7 E, Embree's watertight test
// resolves the same; the margin is a thousand times that, and a scattering point that close to a
// boundary simply takes the BVH query.
constexpr double kMargin = 1e-4, kSamePlane = 1e-6;

}  // namespace

void BoundaryPlanes::reset(float extent) {
    planes_.clear();
    usable_ = std::isfinite(extent);
    margin_ = float(kMargin * std::max(1.0, double(extent)));
}

void BoundaryPlanes::add_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    if (!usable_) return;
    // In double, so that the plane through the three corners holds all three to well within the margin.
    const double ax = a.x, ay = a.y, az = a.z;
    const double ux = b.x - ax, uy = b.y - ay, uz = b.z - az, vx = c.x - ax, vy = c.y - ay, vz = c.z - az;
    double nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
    const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
    const double scale = double(margin_) / kMargin;
    // Degenerate (or nearly): its plane is not defined well enough to exclude anything.
    if (!(len > 1e-12 * scale * scale) || !std::isfinite(len)) {
        usable_ = false;
        return;
    }
    nx /= len, ny /= len, nz /= len;
    // One orientation per plane (the test does not care which side is which), so that a box's two
    // triangles per face compare equal.
    const double big = std::fabs(nx) >= std::fabs(ny) && std::fabs(nx) >= std::fabs(nz) ? nx
                       : std::fabs(ny) >= std::fabs(nz)                                 ? ny
                                                                                         : nz;
    if (big < 0.0) nx = -nx, ny = -ny, nz = -nz;
    const double d = nx * ax + ny * ay + nz * az;
    for (const Vec3* p : {&b, &c})
        if (std::fabs(nx * p->x + ny * p->y + nz * p->z - d) > kSamePlane * scale) {
            usable_ = false;
            return;
        }
    for (const Plane& q : planes_)
        if (std::fabs(q.n.x - nx) < kSamePlane && std::fabs(q.n.y - ny) < kSamePlane &&
            std::fabs(q.n.z - nz) < kSamePlane && std::fabs(double(q.d) - d) < kSamePlane * scale)
            return;
    if (planes_.size() == kMaxPlanes) {
        usable_ = false;
        planes_.clear();
        return;
    }
    planes_.push_back({Vec3(float(nx), float(ny), float(nz)), float(d)});
}

bool BoundaryPlanes::separated(const Vec3& a, const Vec3& b) const {
    if (!usable_) return false;
    for (const Plane& q : planes_) {
        const float sa = dot(q.n, a) - q.d, sb = dot(q.n, b) - q.d;
        // Written so that NaN (an infinite end) fails both.
        if (!((sa > margin_ && sb > margin_) || (sa < -margin_ && sb < -margin_))) return false;
    }
    return true;
}

}  // namespace smis
