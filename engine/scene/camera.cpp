#include "scene/camera.h"

#include <stdexcept>

namespace smis {

Camera::Camera(const CameraDesc& desc) : desc_(desc) {
    if (desc.width <= 0 || desc.height <= 0) throw std::invalid_argument("camera resolution must be positive");
    if (!desc.to_world.is_finite()) throw std::invalid_argument("camera matrix is not finite");
    // The clip range becomes every camera ray's [tnear, tfar]: a NaN or negative clip_start reached
    // Embree as tnear < 0, which aborts the process on Embree's `ray.tnear() >= 0` assertion (found
    // by fuzz_test). Shift and pixel aspect feed the ray direction, so they must be finite too.
    if (!(desc.clip_start >= 0.0f) || !std::isfinite(desc.clip_start) || !(desc.clip_end > desc.clip_start))
        throw std::invalid_argument("camera clip range invalid");
    if (!std::isfinite(desc.shift_x) || !std::isfinite(desc.shift_y))
        throw std::invalid_argument("camera shift is not finite");
    if (!(desc.pixel_aspect_x > 0.0f) || !(desc.pixel_aspect_y > 0.0f) || !std::isfinite(desc.pixel_aspect_x) ||
        !std::isfinite(desc.pixel_aspect_y))
        throw std::invalid_argument("camera pixel aspect invalid");
    const Transform& m = desc.to_world;
    origin_ = Vec3(m.m[0][3], m.m[1][3], m.m[2][3]);
    right_ = normalize(m.column(0));
    up_ = normalize(m.column(1));
    forward_ = -normalize(m.column(2));  // Blender cameras look down their local -Z
    if (!is_finite(right_) || !is_finite(up_) || !is_finite(forward_))
        throw std::invalid_argument("camera matrix is degenerate");

    // Cycles' blender_camera_viewplane(): choose the fitted axis, then the other one follows the aspect.
    float xratio = desc.width * desc.pixel_aspect_x, yratio = desc.height * desc.pixel_aspect_y;
    bool horizontal;
    float sensor;
    if (desc.sensor_fit == "HORIZONTAL") {
        horizontal = true;
        sensor = desc.sensor_width;
    } else if (desc.sensor_fit == "VERTICAL") {
        horizontal = false;
        sensor = desc.sensor_height;
    } else {
        horizontal = xratio > yratio;
        sensor = desc.sensor_width;
    }
    // Half extent of the fitted axis: at distance 1 for perspective, in world units for ortho.
    float fitted_half = desc.orthographic ? 0.5f * desc.ortho_scale : 0.5f * sensor / desc.lens;
    if (!(fitted_half > 0.0f) || !std::isfinite(fitted_half)) throw std::invalid_argument("camera lens/sensor invalid");
    if (horizontal) {
        half_w_ = fitted_half;
        half_h_ = fitted_half * yratio / xratio;
    } else {
        half_h_ = fitted_half;
        half_w_ = fitted_half * xratio / yratio;
    }
    // Shift is measured in units of the fitted dimension's full extent, on both axes.
    shift_x_ = desc.shift_x * 2.0f * fitted_half;
    shift_y_ = desc.shift_y * 2.0f * fitted_half;

    const int* b = desc.border;
    bool has_border = b[2] > b[0] && b[3] > b[1];
    window_[0] = has_border ? std::max(0, b[0]) : 0;
    window_[1] = has_border ? std::max(0, b[1]) : 0;
    window_[2] = has_border ? std::min(desc.width, b[2]) : desc.width;
    window_[3] = has_border ? std::min(desc.height, b[3]) : desc.height;
    if (window_[2] <= window_[0] || window_[3] <= window_[1]) throw std::invalid_argument("empty render border");
}

Ray Camera::generate_ray(float fx, float fy) const {
    float sx = -half_w_ + 2.0f * half_w_ * (fx / desc_.width) + shift_x_;
    float sy = -half_h_ + 2.0f * half_h_ * (fy / desc_.height) + shift_y_;
    Ray ray;
    if (desc_.orthographic) {
        ray.o = origin_ + right_ * sx + up_ * sy;
        ray.d = forward_;
        ray.tmin = desc_.clip_start;
        ray.tmax = desc_.clip_end;
    } else {
        Vec3 d = right_ * sx + up_ * sy + forward_;
        float inv_len = 1.0f / length(d);
        ray.o = origin_;
        ray.d = d * inv_len;
        // Blender clips planes perpendicular to the view axis, so the ray distances grow off-axis.
        ray.tmin = desc_.clip_start / inv_len;
        ray.tmax = desc_.clip_end / inv_len;
    }
    return ray;
}

float Camera::pixel_footprint(float dist) const {
    float extent = 2.0f * half_w_ / desc_.width;
    return desc_.orthographic ? extent : extent * dist;
}

}  // namespace smis
