// Uniform sampling of the solid angle a rectangle subtends from a point (Urena, Fajardo & King 2013,
// "An Area-Preserving Parametrization for Spherical Rectangles"). Next-event estimation with it has
// the bounded weight L * solid angle wherever the reference point is, even on the light's plane,
// while uniform area sampling's weight A cos / r^2 has infinite variance for points near the light
// (what made single scattering in fog noisy around rectangle lights, see integrators/volume.cpp).
#pragma once
#include "core/math.h"
#include "core/sampling.h"

namespace smis {

class SphericalRectangle {
public:
    // The rectangle corner + a u + b v (a, b in [0, 1]; u and v orthogonal) seen from `ref`.
    // Computed in double: the solid angle is a sum of four angles minus 2 pi, which loses all of
    // float's digits for rectangles that look small.
    SphericalRectangle(const Vec3& ref, const Vec3& corner, const Vec3& u, const Vec3& v);
    // Solid angle in steradians; 0 when ref lies on the rectangle's plane or the input is degenerate.
    double solid_angle() const { return solid_angle_; }
    // A point of the rectangle whose direction from ref is uniform in the solid angle (density
    // 1 / solid_angle()). Only for solid_angle() > 0.
    Vec3 sample(Point2 u) const;

private:
    double o_[3], x_[3], y_[3], z_[3];  // reference point and the rectangle's frame (z away from o)
    double x0_, x1_, y0_, y1_, z0_;     // the rectangle in that frame, relative to o
    double b0_, b1_, k_;
    double solid_angle_ = 0.0;
};

}  // namespace smis
