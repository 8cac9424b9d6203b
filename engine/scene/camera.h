// Blender's camera model (perspective and orthographic), framed exactly as Cycles frames it
// (intern/cycles/blender/camera.cpp: sensor fit, shift in units of the fitted dimension).
#pragma once
#include <string>
#include <vector>
#include "core/features.h"
#include "core/math.h"
#include "core/sampling.h"
#include "scene/motion.h"
#include "scene/ray_visibility.h"

namespace smis {

struct Ray {
    Vec3 o, d;
    float tmin = 0.0f, tmax = kInf;
    float time = kShutterCentre;  // in the shutter interval, 0 = open, 1 = close (motion blur)
    // The Embree mask: which objects the ray sees (ray_visibility.h; camera rays kRayCamera, bounce
    // rays ray_mask() of their path flags). Queries that are no ray of a path see everything.
    uint32_t visibility = kRayAllVisibility;
};

struct CameraDesc {
    bool orthographic = false;
    Transform to_world;          // Blender matrix_world (scale is removed)
    std::string sensor_fit = "AUTO";
    float sensor_width = 36.0f, sensor_height = 24.0f, lens = 50.0f;
    float ortho_scale = 7.0f;
    float shift_x = 0.0f, shift_y = 0.0f;
    float clip_start = 0.1f, clip_end = 1000.0f;
    int width = 64, height = 64;  // full frame after resolution percentage
    float pixel_aspect_x = 1.0f, pixel_aspect_y = 1.0f;
    int border[4] = {0, 0, 0, 0};  // [x0, y0, x1, y1) window, y from the bottom; all zero = full frame
    // Depth of field (Blender's camera.dof, Cycles' thin lens); fstop 0 = pinhole.
    float fstop = 0.0f;
    float focus_distance = 10.0f;   // along the view axis (planar), from the distance or focus object
    int aperture_blades = 0;        // < 3: round aperture
    float aperture_rotation = 0.0f; // radians
    float aperture_ratio = 1.0f;    // anamorphic: the aperture's x extent is divided by it
    // Motion blur: the camera's matrices at evenly spaced times over the shutter (none or at least
    // two; all equal counts as none), and the shutter curve (values over the shutter; empty = flat).
    std::vector<Transform> motion;
    std::vector<float> shutter_curve;
};

class Camera {
public:
    Camera() = default;
    explicit Camera(const CameraDesc& desc);
    // (fx, fy): continuous coordinates on the full frame in pixels, y from the bottom row; u_lens
    // picks the point on the aperture (ignored by a pinhole camera); time in the shutter moves a
    // camera that has motion (and is the ray's time).
    Ray generate_ray(float fx, float fy, Point2 u_lens = {0.5f, 0.5f}, float time = kShutterCentre) const;
    bool has_motion() const { return !motion_.empty(); }
    // A ray's time in the shutter from a uniform number (the shutter curve's distribution).
    float sample_time(float u) const { return shutter_.sample(u); }
    bool has_aperture() const { return kWithDepthOfField && aperture_radius_ > 0.0f; }
    float aperture_radius() const { return aperture_radius_; }  // world units
    int width() const { return desc_.width; }
    int height() const { return desc_.height; }
    int window_x0() const { return window_[0]; }
    int window_y0() const { return window_[1]; }
    int window_width() const { return window_[2] - window_[0]; }
    int window_height() const { return window_[3] - window_[1]; }
    // Distance of p along the view axis: Cycles' Z pass (planar camera-space depth).
    float view_depth(const Vec3& p) const { return dot(p - origin_, forward_); }
    // World-space size of one pixel at distance `dist` along the view axis (used by path-space filtering).
    float pixel_footprint(float dist) const;
    // The camera's frame (x right, y up, z forward: the camera space of Cycles' shaders).
    const Vec3& origin() const { return origin_; }
    const Vec3& right_axis() const { return right_; }
    const Vec3& up_axis() const { return up_; }
    const Vec3& forward_axis() const { return forward_; }
    // Texture Coordinate's Window output: p projected to the full frame, (0, 0) bottom left, (1, 1)
    // top right, z 0.
    Vec3 window_coordinates(const Vec3& p) const;

private:
    CameraDesc desc_;
    int window_[4] = {0, 0, 0, 0};
    Vec3 origin_, right_, up_, forward_;
    float half_w_ = 1.0f, half_h_ = 1.0f;  // image-plane half extents (at distance 1, or world units)
    float shift_x_ = 0.0f, shift_y_ = 0.0f;
    float aperture_radius_ = 0.0f;
    std::vector<DecomposedTransform> motion_;  // empty: a camera that does not move
    ShutterCurve shutter_;
    // Point on the aperture in the camera's (right, up) plane, world units.
    Point2 sample_aperture(Point2 u) const;
};

}  // namespace smis
