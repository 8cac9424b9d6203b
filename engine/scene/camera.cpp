#include "scene/camera.h"

#include <cstring>
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

    if (desc.fstop != 0.0f) {
        require_feature(kWithDepthOfField, "depth of field", "depth_of_field");
        // Cycles' thin lens: aperture radius = focal length / (2 f-stop), the focal length in metres
        // (lens is in mm); an orthographic camera takes 1 / (2 f-stop) world units.
        if (!(desc.fstop > 0.0f) || !std::isfinite(desc.fstop)) throw std::invalid_argument("camera f-stop invalid");
        if (!(desc.focus_distance > 0.0f) || !std::isfinite(desc.focus_distance))
            throw std::invalid_argument("camera focus distance invalid");
        if (!(desc.aperture_ratio > 0.0f) || !std::isfinite(desc.aperture_ratio) ||
            !std::isfinite(desc.aperture_rotation))
            throw std::invalid_argument("camera aperture ratio/rotation invalid");
        aperture_radius_ = desc.orthographic ? 0.5f / desc.fstop : desc.lens * 1e-3f / (2.0f * desc.fstop);
        if (!std::isfinite(aperture_radius_)) aperture_radius_ = 0.0f;
    }

    if (desc.motion.size() == 1) throw std::invalid_argument("camera motion needs at least two steps");
    bool moves = false;
    for (const Transform& t : desc.motion) {
        if (!t.is_finite() || !(std::fabs(t.determinant3()) > 0.0f))
            throw std::invalid_argument("camera motion matrix is not finite or is singular");
        moves = moves || std::memcmp(&t, &desc.motion[0], sizeof(Transform)) != 0;
    }
    if (moves) motion_ = decompose_motion(desc.motion);
    if (!desc.shutter_curve.empty()) shutter_ = ShutterCurve(desc.shutter_curve);

    const int* b = desc.border;
    bool has_border = b[2] > b[0] && b[3] > b[1];
    window_[0] = has_border ? std::max(0, b[0]) : 0;
    window_[1] = has_border ? std::max(0, b[1]) : 0;
    window_[2] = has_border ? std::min(desc.width, b[2]) : desc.width;
    window_[3] = has_border ? std::min(desc.height, b[3]) : desc.height;
    if (window_[2] <= window_[0] || window_[3] <= window_[1]) throw std::invalid_argument("empty render border");
}

Point2 Camera::sample_aperture(Point2 u) const {
    Point2 p = desc_.aperture_blades >= 3 ? sample_regular_polygon(desc_.aperture_blades, desc_.aperture_rotation, u)
                                          : sample_uniform_disk_concentric(u);
    return {p.x * aperture_radius_ / desc_.aperture_ratio, p.y * aperture_radius_};
}

Ray Camera::generate_ray(float fx, float fy, Point2 u_lens, float time) const {
    float sx = -half_w_ + 2.0f * half_w_ * (fx / desc_.width) + shift_x_;
    float sy = -half_h_ + 2.0f * half_h_ * (fy / desc_.height) + shift_y_;
    // Camera space: x right, y up, z along the view axis. A pinhole ray starts at `o` in direction d;
    // a thin lens moves the start to a point on the aperture and aims it at the point the pinhole ray
    // reaches on the plane of focus (Cycles' camera_sample_perspective/orthographic), so everything
    // at the focus distance stays sharp.
    Vec3 o = desc_.orthographic ? Vec3(sx, sy, 0.0f) : Vec3(0.0f);
    Vec3 d = desc_.orthographic ? Vec3(0.0f, 0.0f, 1.0f) : Vec3(sx, sy, 1.0f);
    if (has_aperture()) {
        Vec3 focus = o + d * (desc_.focus_distance / d.z);
        Point2 lens = sample_aperture(u_lens);
        o += Vec3(lens.x, lens.y, 0.0f);
        d = focus - o;
    }
    d = normalize(d);
    Ray ray;
    ray.time = time;
    if (!motion_.empty()) {
        // Cycles interpolates the camera-to-world transform of its motion steps the same way.
        Transform m = interpolate_motion(motion_, time);
        Vec3 right = normalize(m.column(0)), up = normalize(m.column(1)), forward = -normalize(m.column(2));
        ray.o = m.column(3) + right * o.x + up * o.y;
        ray.d = right * d.x + up * d.y + forward * d.z;
    } else {
        ray.o = origin_ + right_ * o.x + up_ * o.y;
        ray.d = right_ * d.x + up_ * d.y + forward_ * d.z;
    }
    // Blender clips planes perpendicular to the view axis, so ray distances grow with the obliqueness.
    ray.tmin = desc_.clip_start / d.z;
    ray.tmax = desc_.clip_end / d.z;
    ray.visibility = kRayCamera;
    return ray;
}

float Camera::pixel_footprint(float dist) const {
    float extent = 2.0f * half_w_ / desc_.width;
    return desc_.orthographic ? extent : extent * dist;
}

Vec3 Camera::window_coordinates(const Vec3& p) const {
    Vec3 d = p - origin_;
    float x = dot(d, right_), y = dot(d, up_), z = dot(d, forward_);
    if (!desc_.orthographic) {
        if (!(z > 0.0f)) return Vec3(0.0f);
        x /= z, y /= z;
    }
    return {(x - shift_x_ + half_w_) / (2.0f * half_w_), (y - shift_y_ + half_h_) / (2.0f * half_h_), 0.0f};
}

}  // namespace smis
