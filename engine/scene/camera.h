// Blender's camera model (perspective and orthographic), framed exactly as Cycles frames it
// (intern/cycles/blender/camera.cpp: sensor fit, shift in units of the fitted dimension).
#pragma once
#include <string>
#include "core/math.h"
#include "core/sampling.h"

namespace smis {

struct Ray {
    Vec3 o, d;
    float tmin = 0.0f, tmax = kInf;
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
};

class Camera {
public:
    Camera() = default;
    explicit Camera(const CameraDesc& desc);
    // (fx, fy): continuous coordinates on the full frame in pixels, y from the bottom row.
    Ray generate_ray(float fx, float fy) const;
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

private:
    CameraDesc desc_;
    int window_[4] = {0, 0, 0, 0};
    Vec3 origin_, right_, up_, forward_;
    float half_w_ = 1.0f, half_h_ = 1.0f;  // image-plane half extents (at distance 1, or world units)
    float shift_x_ = 0.0f, shift_y_ = 0.0f;
};

}  // namespace smis
