#include "scene/spherical_rectangle.h"

#include <cmath>

namespace smis {

namespace {

struct D3 {
    double x, y, z;
};
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 normalized(const D3& a) {
    double l = std::sqrt(dot(a, a));
    return l > 0.0 ? D3{a.x / l, a.y / l, a.z / l} : D3{0.0, 0.0, 0.0};
}
double clamp_unit(double c) { return c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c); }

}  // namespace

SphericalRectangle::SphericalRectangle(const Vec3& ref, const Vec3& corner, const Vec3& u, const Vec3& v) {
    D3 eu{u.x, u.y, u.z}, ev{v.x, v.y, v.z};
    double lu = std::sqrt(dot(eu, eu)), lv = std::sqrt(dot(ev, ev));
    if (!(lu > 0.0 && lv > 0.0) || !std::isfinite(lu * lv)) return;
    D3 x{eu.x / lu, eu.y / lu, eu.z / lu}, y{ev.x / lv, ev.y / lv, ev.z / lv};
    D3 z = cross(x, y);
    D3 d{double(corner.x) - ref.x, double(corner.y) - ref.y, double(corner.z) - ref.z};
    x0_ = dot(d, x);
    y0_ = dot(d, y);
    z0_ = dot(d, z);
    // The paper's frame has the rectangle below the reference point (z0 <= 0).
    if (z0_ > 0.0) {
        z0_ = -z0_;
        z = {-z.x, -z.y, -z.z};
    }
    x1_ = x0_ + lu;
    y1_ = y0_ + lv;
    if (!(z0_ < 0.0)) return;  // on the plane: the rectangle is seen edge-on
    // Normals of the four planes through o and an edge, and the interior angles between them.
    D3 v00{x0_, y0_, z0_}, v01{x0_, y1_, z0_}, v10{x1_, y0_, z0_}, v11{x1_, y1_, z0_};
    D3 n0 = normalized(cross(v00, v10)), n1 = normalized(cross(v10, v11));
    D3 n2 = normalized(cross(v11, v01)), n3 = normalized(cross(v01, v00));
    double g0 = std::acos(clamp_unit(-dot(n0, n1))), g1 = std::acos(clamp_unit(-dot(n1, n2)));
    double g2 = std::acos(clamp_unit(-dot(n2, n3))), g3 = std::acos(clamp_unit(-dot(n3, n0)));
    b0_ = n0.z;
    b1_ = n2.z;
    k_ = 2.0 * M_PI - g2 - g3;
    double s = g0 + g1 - k_;  // the spherical quadrilateral's area (paper, eq. 1)
    if (!(s > 0.0) || !std::isfinite(s)) return;
    solid_angle_ = s;
    const D3* axes[3] = {&x, &y, &z};
    double* dst[3] = {x_, y_, z_};
    for (int a = 0; a < 3; ++a) dst[a][0] = axes[a]->x, dst[a][1] = axes[a]->y, dst[a][2] = axes[a]->z;
    o_[0] = ref.x, o_[1] = ref.y, o_[2] = ref.z;
}

Vec3 SphericalRectangle::sample(Point2 u) const {
    // Paper, Algorithm 1: the first coordinate from the sub-area up to angle au (its inverse in
    // closed form), then the second uniformly in the sine of the elevation along that column.
    double au = u.x * solid_angle_ + k_;
    double fu = (std::cos(au) * b0_ - b1_) / std::sin(au);
    double cu = clamp_unit((fu > 0.0 ? 1.0 : -1.0) / std::sqrt(fu * fu + b0_ * b0_));
    double xu = -(cu * z0_) / std::sqrt(std::fmax(1e-300, 1.0 - cu * cu));
    xu = std::fmin(std::fmax(xu, x0_), x1_);
    double dist = std::sqrt(xu * xu + z0_ * z0_);
    double h0 = y0_ / std::sqrt(dist * dist + y0_ * y0_), h1 = y1_ / std::sqrt(dist * dist + y1_ * y1_);
    double hv = h0 + u.y * (h1 - h0), hv2 = hv * hv;
    double yv = hv2 < 1.0 - 1e-12 ? hv * dist / std::sqrt(1.0 - hv2) : y1_;
    yv = std::fmin(std::fmax(yv, y0_), y1_);
    double p[3];
    for (int a = 0; a < 3; ++a) p[a] = o_[a] + xu * x_[a] + yv * y_[a] + z0_ * z_[a];
    return {float(p[0]), float(p[1]), float(p[2])};
}

}  // namespace smis
