#include "scene/motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace smis {
namespace {

// The unit quaternion of a proper rotation matrix given by its columns (Shoemake's method: the
// largest of w, x, y, z is computed first, for precision).
void quaternion_from_rotation(const Vec3& c0, const Vec3& c1, const Vec3& c2, float q[4]) {
    const float m00 = c0.x, m11 = c1.y, m22 = c2.z;
    const float trace = m00 + m11 + m22;
    if (trace > 0.0f) {
        float s = 2.0f * std::sqrt(trace + 1.0f);
        q[3] = 0.25f * s;
        q[0] = (c1.z - c2.y) / s;
        q[1] = (c2.x - c0.z) / s;
        q[2] = (c0.y - c1.x) / s;
    } else if (m00 > m11 && m00 > m22) {
        float s = 2.0f * std::sqrt(1.0f + m00 - m11 - m22);
        q[3] = (c1.z - c2.y) / s;
        q[0] = 0.25f * s;
        q[1] = (c1.x + c0.y) / s;
        q[2] = (c2.x + c0.z) / s;
    } else if (m11 > m22) {
        float s = 2.0f * std::sqrt(1.0f + m11 - m00 - m22);
        q[3] = (c2.x - c0.z) / s;
        q[0] = (c1.x + c0.y) / s;
        q[1] = 0.25f * s;
        q[2] = (c2.y + c1.z) / s;
    } else {
        float s = 2.0f * std::sqrt(1.0f + m22 - m00 - m11);
        q[3] = (c0.y - c1.x) / s;
        q[0] = (c2.x + c0.z) / s;
        q[1] = (c2.y + c1.z) / s;
        q[2] = 0.25f * s;
    }
    float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; ++i) q[i] /= n;
}

// Columns of the rotation of a unit quaternion.
void rotation_columns(const float q[4], Vec3* c0, Vec3* c1, Vec3* c2) {
    const float x = q[0], y = q[1], z = q[2], w = q[3];
    *c0 = {1.0f - 2.0f * (y * y + z * z), 2.0f * (x * y + w * z), 2.0f * (x * z - w * y)};
    *c1 = {2.0f * (x * y - w * z), 1.0f - 2.0f * (x * x + z * z), 2.0f * (y * z + w * x)};
    *c2 = {2.0f * (x * z + w * y), 2.0f * (y * z - w * x), 1.0f - 2.0f * (x * x + y * y)};
}

// Cycles' quat_interpolate: slerp, or a normalised lerp when the two are nearly equal.
void slerp(const float a[4], const float b[4], float t, float out[4]) {
    float cos_theta = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    if (cos_theta > 0.9995f) {
        float n = 0.0f;
        for (int i = 0; i < 4; ++i) {
            out[i] = (1.0f - t) * a[i] + t * b[i];
            n += out[i] * out[i];
        }
        n = std::sqrt(n);
        for (int i = 0; i < 4; ++i) out[i] /= n;
        return;
    }
    float theta = std::acos(std::clamp(cos_theta, -1.0f, 1.0f));
    float perp[4], n = 0.0f;
    for (int i = 0; i < 4; ++i) {
        perp[i] = b[i] - a[i] * cos_theta;
        n += perp[i] * perp[i];
    }
    n = std::sqrt(n);
    float c = std::cos(theta * t), s = std::sin(theta * t);
    for (int i = 0; i < 4; ++i) out[i] = a[i] * c + perp[i] / n * s;
}

}  // namespace

DecomposedTransform decompose(const Transform& t) {
    DecomposedTransform d;
    d.translation = t.column(3);
    Vec3 a0 = t.column(0), a1 = t.column(1), a2 = t.column(2);
    // Gram-Schmidt: q0 along a0, q1 the part of a1 orthogonal to q0, q2 the rest; S holds the
    // projections (its upper triangle) and the remaining lengths (its diagonal).
    d.sx = length(a0);
    Vec3 q0 = a0 / d.sx;
    d.kxy = dot(q0, a1);
    Vec3 r1 = a1 - q0 * d.kxy;
    d.sy = length(r1);
    Vec3 q1 = r1 / d.sy;
    d.kxz = dot(q0, a2);
    d.kyz = dot(q1, a2);
    Vec3 r2 = a2 - q0 * d.kxz - q1 * d.kyz;
    Vec3 q2 = cross(q0, q1);
    // A mirroring transform keeps a proper rotation: the mirror goes into the last scale.
    d.sz = dot(q2, r2);
    quaternion_from_rotation(q0, q1, q2, d.quat);
    return d;
}

Transform compose(const DecomposedTransform& d) {
    Vec3 q0, q1, q2;
    rotation_columns(d.quat, &q0, &q1, &q2);
    const Vec3 cols[4] = {q0 * d.sx, q0 * d.kxy + q1 * d.sy, q0 * d.kxz + q1 * d.kyz + q2 * d.sz, d.translation};
    Transform t;
    for (int c = 0; c < 4; ++c) t.m[0][c] = cols[c].x, t.m[1][c] = cols[c].y, t.m[2][c] = cols[c].z;
    return t;
}

std::vector<DecomposedTransform> decompose_motion(const std::vector<Transform>& steps) {
    std::vector<DecomposedTransform> out;
    out.reserve(steps.size());
    for (const Transform& t : steps) {
        DecomposedTransform d = decompose(t);
        if (!out.empty()) {
            const float* p = out.back().quat;
            if (p[0] * d.quat[0] + p[1] * d.quat[1] + p[2] * d.quat[2] + p[3] * d.quat[3] < 0.0f)
                for (float& q : d.quat) q = -q;
        }
        out.push_back(d);
    }
    return out;
}

Transform interpolate_motion(const std::vector<DecomposedTransform>& steps, float time) {
    const int last = static_cast<int>(steps.size()) - 1;
    const float x = std::clamp(time, 0.0f, 1.0f) * last;
    const int step = std::min(static_cast<int>(x), last - 1);
    const float t = x - step;
    const DecomposedTransform& a = steps[step];
    const DecomposedTransform& b = steps[step + 1];
    auto lerp = [t](float u, float v) { return (1.0f - t) * u + t * v; };
    DecomposedTransform d;
    slerp(a.quat, b.quat, t, d.quat);
    d.translation = a.translation * (1.0f - t) + b.translation * t;
    d.sx = lerp(a.sx, b.sx), d.sy = lerp(a.sy, b.sy), d.sz = lerp(a.sz, b.sz);
    d.kxy = lerp(a.kxy, b.kxy), d.kxz = lerp(a.kxz, b.kxz), d.kyz = lerp(a.kyz, b.kyz);
    return compose(d);
}

RTCQuaternionDecomposition embree_decomposition(const DecomposedTransform& d) {
    RTCQuaternionDecomposition q;
    rtcInitQuaternionDecomposition(&q);
    rtcQuaternionDecompositionSetScale(&q, d.sx, d.sy, d.sz);
    rtcQuaternionDecompositionSetSkew(&q, d.kxy, d.kxz, d.kyz);
    rtcQuaternionDecompositionSetQuaternion(&q, d.quat[3], d.quat[0], d.quat[1], d.quat[2]);
    rtcQuaternionDecompositionSetTranslation(&q, d.translation.x, d.translation.y, d.translation.z);
    return q;
}

ShutterCurve::ShutterCurve(const std::vector<float>& values) {
    if (values.size() < 2) throw std::invalid_argument("shutter curve needs at least two values");
    const size_t n = values.size() - 1;  // segments, density linear within each
    std::vector<double> cdf(n + 1, 0.0);
    bool flat = true;
    for (size_t i = 0; i < n; ++i) {
        float a = values[i], b = values[i + 1];
        if (!(a >= 0.0f) || !(b >= 0.0f) || !std::isfinite(a) || !std::isfinite(b))
            throw std::invalid_argument("shutter curve values must be finite and non-negative");
        flat = flat && a == values[0] && b == values[0];
        cdf[i + 1] = cdf[i] + 0.5 * (a + b);
    }
    if (!(cdf[n] > 0.0)) throw std::invalid_argument("shutter curve is zero everywhere");
    if (flat) return;
    // The inverse at 1024 evenly spaced fractions, each found on the piecewise-linear density:
    // within a segment the CDF is quadratic in the time, solved exactly.
    constexpr int kTable = 1024;
    inverse_.resize(kTable + 1);
    size_t seg = 0;
    for (int k = 0; k <= kTable; ++k) {
        double target = cdf[n] * k / kTable;
        while (seg + 1 < n && cdf[seg + 1] < target) ++seg;
        double a = values[seg], b = values[seg + 1], rest = target - cdf[seg];
        // a s + (b - a) s^2 / 2 = rest, s in [0, 1] of the segment
        double s;
        if (std::fabs(b - a) < 1e-9 * std::max(a, b)) s = a > 0.0 ? rest / a : 0.0;
        else s = (-a + std::sqrt(std::max(0.0, a * a + 2.0 * (b - a) * rest))) / (b - a);
        inverse_[k] = static_cast<float>((seg + std::clamp(s, 0.0, 1.0)) / n);
    }
}

float ShutterCurve::sample(float u) const {
    if (inverse_.empty()) return u;
    float x = std::clamp(u, 0.0f, 1.0f) * (inverse_.size() - 1);
    size_t i = std::min(static_cast<size_t>(x), inverse_.size() - 2);
    float f = x - i;
    return inverse_[i] * (1.0f - f) + inverse_[i + 1] * f;
}

}  // namespace smis
