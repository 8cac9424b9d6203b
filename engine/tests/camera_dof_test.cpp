// Depth of field: Cycles' thin-lens camera. A point on the plane of focus stays sharp (every
// aperture sample sees it through the same pixel), and a defocused point spreads over the circle of
// confusion the thin-lens formula predicts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/rng.h"
#include "scene/camera.h"

using namespace smis;

namespace {

constexpr int kW = 400, kH = 300;
constexpr float kLensMm = 50.0f, kSensorMm = 36.0f, kFstop = 1.4f, kFocus = 2.0f;

CameraDesc dof_camera(int blades = 0, float ratio = 1.0f) {
    CameraDesc c;  // identity: at the origin, looking down -Z
    c.width = kW, c.height = kH;
    c.lens = kLensMm, c.sensor_width = kSensorMm;
    c.fstop = kFstop, c.focus_distance = kFocus;
    c.aperture_blades = blades, c.aperture_rotation = 0.3f, c.aperture_ratio = ratio;
    return c;
}

float distance_to_ray(const Ray& r, const Vec3& p) {
    Vec3 v = p - r.o;
    return length(v - r.d * dot(v, r.d));
}

// Pixel coordinates where the pinhole projection of camera-space point q (depth -q.z) lands.
Point2 project(const Vec3& q) {
    float half_w = 0.5f * kSensorMm / kLensMm, half_h = half_w * kH / kW;
    float sx = q.x / -q.z, sy = q.y / -q.z;
    return {(sx + half_w) / (2.0f * half_w) * kW, (sy + half_h) / (2.0f * half_h) * kH};
}

Point2 random2(Rng& rng) { return {rng.next_float(), rng.next_float()}; }

}  // namespace

TEST(CameraDof, ApertureRadiusIsFocalLengthOverTwiceTheFstop) {
    EXPECT_NEAR(Camera(dof_camera()).aperture_radius(), 0.05f / (2.0f * kFstop), 1e-7f);
    CameraDesc pinhole = dof_camera();
    pinhole.fstop = 0.0f;
    EXPECT_FALSE(Camera(pinhole).has_aperture());
    CameraDesc bad = dof_camera();
    bad.focus_distance = -1.0f;
    EXPECT_THROW(Camera{bad}, std::invalid_argument);
}

TEST(CameraDof, PointOnThePlaneOfFocusStaysSharp) {
    for (int blades : {0, 6}) {
        Camera cam(dof_camera(blades, 1.5f));
        Rng rng(3, 0);
        for (int i = 0; i < 50; ++i) {
            float fx = rng.next_float() * kW, fy = rng.next_float() * kH;
            CameraDesc pinhole_desc = dof_camera();
            pinhole_desc.fstop = 0.0f;
            Ray pinhole = Camera(pinhole_desc).generate_ray(fx, fy);
            Vec3 on_focus_plane = pinhole.o + pinhole.d * (kFocus / -pinhole.d.z);  // planar depth kFocus
            for (int j = 0; j < 20; ++j) {
                Ray r = cam.generate_ray(fx, fy, random2(rng));
                EXPECT_LT(distance_to_ray(r, on_focus_plane), 1e-5f);
                EXPECT_GT(length(r.o - pinhole.o), 0.0f);
            }
        }
    }
}

TEST(CameraDof, DefocusBlurMatchesTheThinLensCircleOfConfusion) {
    for (float depth : {0.8f, 5.0f}) {
        Camera cam(dof_camera());
        const Vec3 p(0.0f, 0.0f, -depth);  // on the optical axis, off the plane of focus
        const Point2 centre = project(p);
        // Thin lens with the sensor at the focal length F (Blender frames with F, focused at
        // infinity; the exact thin lens magnifies F/(f-F) instead of F/f, 2.6% more here):
        // CoC = A |d - f| / d * F / f on the sensor, A = F/N the aperture diameter.
        const float F = kLensMm * 1e-3f, A = F / kFstop;
        const float coc_px = A * std::fabs(depth - kFocus) / depth * (F / kFocus) / (kSensorMm * 1e-3f) * kW;
        float max_r = 0.0f;
        Rng rng(7, 0);
        for (int i = 0; i < 4000; ++i) {
            Point2 u = random2(rng);
            Vec3 lens = cam.generate_ray(centre.x, centre.y, u).o;  // the aperture point of u
            // The ray from that aperture point through p crosses the plane of focus here, and the
            // pixel whose pinhole ray goes there is the one that sees p through this aperture point.
            Vec3 q = lens + (p - lens) * (kFocus / depth);
            Point2 px = project(q);
            Ray r = cam.generate_ray(px.x, px.y, u);
            ASSERT_LT(distance_to_ray(r, p), 1e-4f);
            max_r = std::max(max_r, std::hypot(px.x - centre.x, px.y - centre.y));
        }
        EXPECT_LE(2.0f * max_r, coc_px * 1.0005f) << depth;
        EXPECT_GE(2.0f * max_r, coc_px * 0.98f) << depth;
        EXPECT_GT(coc_px, 5.0f);  // a visible blur, or the test would not test much
    }
}

TEST(CameraDof, BladesGiveAPolygonalAperture) {
    // Six blades: every aperture point lies inside the hexagon of circumradius R (rotated by the
    // blade rotation), and points reach beyond its inradius R cos(pi/6), so it is not a disk.
    Camera cam(dof_camera(6));
    const float R = cam.aperture_radius(), rotation = 0.3f, half = kPi / 6.0f;
    Rng rng(11, 0);
    float beyond_inradius = 0.0f;
    for (int i = 0; i < 4000; ++i) {
        Vec3 o = cam.generate_ray(kW / 2.0f, kH / 2.0f, random2(rng)).o;
        float angle = std::atan2(o.y, o.x) - rotation;
        // Corners at rotation + odd multiples of pi/6, edge midpoints at even ones; the distance from
        // the centre to the edge in this direction:
        float a = std::fmod(std::fmod(angle, 2.0f * half) + 2.0f * half, 2.0f * half);
        float local = a <= half ? a : a - 2.0f * half;  // from the nearest edge's midpoint direction
        float edge = R * std::cos(half) / std::cos(local);
        float r = std::hypot(o.x, o.y);
        EXPECT_LE(r, edge * 1.0001f);
        beyond_inradius = std::max(beyond_inradius, r / (R * std::cos(half)));
    }
    EXPECT_GT(beyond_inradius, 1.05f);
}
