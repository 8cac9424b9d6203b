#include "shading/image_projection.h"

#include <cmath>

namespace smis::shading {

namespace {

// The node's remap from the [0, 1] box around 0.5 to [-1, 1].
inline Vec3 to_signed_box(const Vec3& co) { return (co - Vec3(0.5f)) * 2.0f; }

}  // namespace

Point2 project_flat(const Vec3& co) { return {co.x, co.y}; }

Point2 project_sphere(const Vec3& co) {
    Vec3 p = to_signed_box(co);
    float l2 = dot(p, p);
    if (!(l2 > 0.0f)) return {0.0f, 0.0f};
    // atan2(x, y): the angle is measured from +y; on the z axis it is undefined and Cycles uses 0.
    float u = p.x == 0.0f && p.y == 0.0f ? 0.0f : 0.5f - std::atan2(p.x, p.y) * (0.5f * kInvPi);
    float v = 1.0f - std::acos(clampf(p.z / std::sqrt(l2), -1.0f, 1.0f)) * kInvPi;
    return {u, v};
}

Point2 project_tube(const Vec3& co) {
    Vec3 p = to_signed_box(co);
    float len = std::sqrt(p.x * p.x + p.y * p.y);
    if (!(len > 0.0f)) return {0.0f, 0.0f};
    float u = (1.0f - std::atan2(p.x / len, p.y / len) * kInvPi) * 0.5f;
    float v = (p.z + 1.0f) * 0.5f;
    return {u, v};
}

BoxWeights project_box(const Vec3& co, const Vec3& n, float blend) {
    // Barycentric coordinates of the normal in the triangle whose corners are the three faces: the
    // corners (beyond `limit`) take one face, the edges blend two and, with blend, the middle three.
    Vec3 a(std::fabs(n.x), std::fabs(n.y), std::fabs(n.z));
    a = a / (a.x + a.y + a.z);
    float w[3] = {0.0f, 0.0f, 0.0f};
    const float limit = 0.5f * (1.0f + blend);
    if (a.x > limit * (a.x + a.y) && a.x > limit * (a.x + a.z)) {
        w[0] = 1.0f;
    } else if (a.y > limit * (a.x + a.y) && a.y > limit * (a.y + a.z)) {
        w[1] = 1.0f;
    } else if (a.z > limit * (a.x + a.z) && a.z > limit * (a.y + a.z)) {
        w[2] = 1.0f;
    } else if (blend > 0.0f) {
        auto ramp = [&](float t) { return clampf((t - 0.5f * (1.0f - blend)) / blend, 0.0f, 1.0f); };
        if (a.z < (1.0f - limit) * (a.y + a.x)) {
            w[0] = ramp(a.x / (a.x + a.y));
            w[1] = 1.0f - w[0];
        } else if (a.x < (1.0f - limit) * (a.y + a.z)) {
            w[1] = ramp(a.y / (a.y + a.z));
            w[2] = 1.0f - w[1];
        } else if (a.y < (1.0f - limit) * (a.x + a.z)) {
            w[0] = ramp(a.x / (a.x + a.z));
            w[2] = 1.0f - w[0];
        } else {
            for (int i = 0; i < 3; ++i) w[i] = ((2.0f - limit) * a[i] + (limit - 1.0f)) / (2.0f * limit - 1.0f);
        }
    } else {
        w[0] = 1.0f;  // no blend and no face wins (a tie): Cycles falls back to X
    }
    BoxWeights b;
    for (int i = 0; i < 3; ++i) b.w[i] = w[i] > 0.0f ? w[i] : 0.0f;  // NaN (zero normal) -> unused
    // Each face's UV, flipped on one side so that no face shows the image mirrored.
    b.uv[0] = {n.x < 0.0f ? 1.0f - co.y : co.y, co.z};
    b.uv[1] = {n.y > 0.0f ? 1.0f - co.x : co.x, co.z};
    b.uv[2] = {n.z > 0.0f ? 1.0f - co.y : co.y, co.x};
    return b;
}

}  // namespace smis::shading
