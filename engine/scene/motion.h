// Transform motion blur: an object's or the camera's transforms at evenly spaced times over the
// shutter (time 0 = shutter open, 1 = close), interpolated as Cycles 3.4 interpolates them
// (util/transform.h, transform_motion_array_interpolate): each step decomposed into translation,
// rotation and an upper-triangular scale/skew; the rotation slerped, the rest interpolated linearly.
// Embree's quaternion motion instances take the same decomposition, so the BVH, the hit's transform
// and the camera all see one motion.
#pragma once
#include <embree3/rtcore.h>

#include <vector>

#include "core/math.h"

namespace smis {

// Rays that carry no time of their own see the scene at the middle of the shutter (Cycles' ray
// time without motion blur is 0.5 as well).
constexpr float kShutterCentre = 0.5f;

struct DecomposedTransform {
    Vec3 translation{0.0f};
    float quat[4] = {0.0f, 0.0f, 0.0f, 1.0f};  // x, y, z, w
    // The 3x3 part is rotation(quat) x S with S upper triangular: [sx kxy kxz; 0 sy kyz; 0 0 sz].
    float sx = 1.0f, sy = 1.0f, sz = 1.0f, kxy = 0.0f, kxz = 0.0f, kyz = 0.0f;
};

// M = T R S by Gram-Schmidt on M's columns (a QR decomposition with a proper rotation R).
DecomposedTransform decompose(const Transform& t);
Transform compose(const DecomposedTransform& d);
// Every step decomposed, each quaternion on the same hemisphere as the one before (so the slerp
// between two steps takes the short way round, as Cycles' transform_motion_decompose ensures).
std::vector<DecomposedTransform> decompose_motion(const std::vector<Transform>& steps);
// The transform at `time` in [0, 1] between evenly spaced steps (at least two).
Transform interpolate_motion(const std::vector<DecomposedTransform>& steps, float time);
RTCQuaternionDecomposition embree_decomposition(const DecomposedTransform& d);

// Cycles' shutter curve: a ray's time drawn from the curve's shape over the shutter by its inverse
// cumulative distribution. An empty or flat curve is the uniform shutter.
class ShutterCurve {
public:
    ShutterCurve() = default;
    // values: the curve at evenly spaced times over [0, 1] (at least two, non-negative, some > 0).
    explicit ShutterCurve(const std::vector<float>& values);
    float sample(float u) const;
    bool uniform() const { return inverse_.empty(); }

private:
    std::vector<float> inverse_;  // time at evenly spaced cumulative fractions 0..1
};

}  // namespace smis
