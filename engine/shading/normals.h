// Shading-normal repair shared by the node evaluator's normal outputs (Bump, Normal Map) and the
// closures' normals, as Cycles 3.4 applies it (kernel/closure/bsdf_util.h).
#pragma once
#include "core/math.h"

namespace smis::shading {

// A bent shading normal N can mirror the incoming direction I below the geometric surface (Ng),
// which no light path could take. If the reflection R = 2 (N.I) N - I is below a small threshold
// above the surface, N is turned towards Ng, within the plane of N and Ng, just far enough that the
// reflection sits on the threshold: dot(R', Ng) = min(0.9 Ng.I, 0.01). Solving for N'.z in that
// frame gives N'.z^2 = (c +- b) / (2a) with a = Ix^2 + Iz^2, b = sqrt(Ix^2 (a - t^2)), c = Iz t + a;
// of the valid roots the shallower reflection is kept; with none, Ng.
// Out of line: the check below runs at every hit, the turn itself rarely.
[[gnu::noinline]] inline Vec3 turn_normal_for_valid_reflection(const Vec3& Ng, const Vec3& I, const Vec3& N,
                                                                float threshold) {
    float n_ng = dot(N, Ng);
    Vec3 x = N - Ng * n_ng;
    float xl = length(x);
    if (!(xl > 0.0f)) return Ng;
    x = x / xl;
    float ix = dot(I, x), iz = dot(I, Ng);
    float ix2 = ix * ix, iz2 = iz * iz;
    float a = ix2 + iz2;
    if (!(a > 0.0f)) return Ng;
    float b = safe_sqrt(ix2 * (a - threshold * threshold));
    float c = iz * threshold + a;
    float fac = 0.5f / a;
    float n1_z2 = fac * (b + c), n2_z2 = fac * (-b + c);
    bool valid1 = n1_z2 > 1e-5f && n1_z2 <= 1.0f + 1e-5f;
    bool valid2 = n2_z2 > 1e-5f && n2_z2 <= 1.0f + 1e-5f;
    float nx, nz;
    if (valid1 && valid2) {
        float n1x = safe_sqrt(1.0f - n1_z2), n1z = safe_sqrt(n1_z2);
        float n2x = safe_sqrt(1.0f - n2_z2), n2z = safe_sqrt(n2_z2);
        float r1 = 2.0f * (n1x * ix + n1z * iz) * n1z - iz;
        float r2 = 2.0f * (n2x * ix + n2z * iz) * n2z - iz;
        bool ok1 = r1 >= 1e-5f, ok2 = r2 >= 1e-5f;
        bool first = (ok1 && ok2) ? r1 < r2 : r1 > r2;
        nx = first ? n1x : n2x;
        nz = first ? n1z : n2z;
    } else if (valid1 || valid2) {
        float z2 = valid1 ? n1_z2 : n2_z2;
        nx = safe_sqrt(1.0f - z2);
        nz = safe_sqrt(z2);
    } else {
        return Ng;
    }
    return x * nx + Ng * nz;
}

inline Vec3 ensure_valid_reflection(const Vec3& Ng, const Vec3& I, const Vec3& N) {
    Vec3 R = N * (2.0f * dot(N, I)) - I;
    float threshold = std::min(0.9f * dot(Ng, I), 0.01f);
    if (dot(Ng, R) >= threshold) return N;
    return turn_normal_for_valid_reflection(Ng, I, N, threshold);
}

// A closure's shading normal as every closure gets it (Cycles' svm_node_closure_bsdf): N turned by
// ensure_valid_reflection, or `fallback` (the interpolated normal) where the turn gives a non-finite
// normal or one below the surface. One function for the shader program's closures and the lowered
// image closure (scene/image_closure.h), which must repair the normal bit for bit as the program does.
inline Vec3 closure_normal(const Vec3& Ng, const Vec3& I, const Vec3& N, const Vec3& fallback) {
    Vec3 ns = ensure_valid_reflection(Ng, I, N);
    if (!is_finite(ns) || !(dot(ns, Ng) > 0.0f)) ns = fallback;
    return ns;
}

}  // namespace smis::shading
