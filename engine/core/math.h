// Small vector math shared by the whole engine: Vec3, Color (linear RGB), Frame, 4x4 affine transforms.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <cstring>

namespace smis {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;
constexpr float kInv4Pi = 1.0f / (4.0f * kPi);
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Vec3 {
    float x = 0, y = 0, z = 0;
    Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
    explicit constexpr Vec3(float v) : x(v), y(v), z(v) {}
    float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator*(const Vec3& o) const { return {x * o.x, y * o.y, z * o.z}; }
    Vec3 operator/(const Vec3& o) const { return {x / o.x, y / o.y, z / o.z}; }
    Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(float s) const { float r = 1.0f / s; return {x * r, y * r, z * r}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
    Vec3& operator*=(const Vec3& o) { x *= o.x; y *= o.y; z *= o.z; return *this; }
    Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
    bool operator==(const Vec3& o) const { return x == o.x && y == o.y && z == o.z; }
};
inline Vec3 operator*(float s, const Vec3& v) { return v * s; }

// Linear RGB in Blender's scene-linear space (Rec.709 primaries).
using Color = Vec3;

inline float dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float absdot(const Vec3& a, const Vec3& b) { return std::fabs(dot(a, b)); }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length_sq(const Vec3& v) { return dot(v, v); }
inline float length(const Vec3& v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(const Vec3& v) { return v / length(v); }
inline Vec3 vmin(const Vec3& a, const Vec3& b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 vmax(const Vec3& a, const Vec3& b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float max_component(const Vec3& v) { return std::max(v.x, std::max(v.y, v.z)); }
inline float min_component(const Vec3& v) { return std::min(v.x, std::min(v.y, v.z)); }
inline float average(const Vec3& v) { return (v.x + v.y + v.z) * (1.0f / 3.0f); }
inline float luminance(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }
inline bool is_black(const Color& c) { return c.x == 0.0f && c.y == 0.0f && c.z == 0.0f; }
inline bool is_finite(float v) { return std::isfinite(v); }
inline bool is_finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline Vec3 lerp(float t, const Vec3& a, const Vec3& b) { return a * (1.0f - t) + b * t; }
inline float clampf(float v, float lo, float hi) { return std::min(hi, std::max(lo, v)); }
inline float sqr(float v) { return v * v; }
inline float safe_sqrt(float v) { return std::sqrt(std::max(0.0f, v)); }
inline Vec3 reflect(const Vec3& wo, const Vec3& n) { return n * (2.0f * dot(wo, n)) - wo; }
inline Vec3 face_forward(const Vec3& n, const Vec3& v) { return dot(n, v) < 0.0f ? -n : n; }

// Orthonormal basis around a unit normal (Duff et al. 2017, branchless).
struct Frame {
    Vec3 s, t, n;
    Frame() : s(1, 0, 0), t(0, 1, 0), n(0, 0, 1) {}
    explicit Frame(const Vec3& normal) : n(normal) {
        float sign = std::copysign(1.0f, n.z);
        float a = -1.0f / (sign + n.z);
        float b = n.x * n.y * a;
        s = Vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
        t = Vec3(b, sign + n.y * n.y * a, -n.y);
    }
    Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
    Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

// Row-major 4x4 affine transform (last row 0 0 0 1), as Blender's matrix_world.
struct Transform {
    float m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};
    Vec3 point(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    Vec3 column(int c) const { return {m[0][c], m[1][c], m[2][c]}; }
    float determinant3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    // Inverse transpose of the 3x3 part, for normals (unnormalised).
    Vec3 normal(const Vec3& n) const {
        Vec3 c0 = column(0), c1 = column(1), c2 = column(2);
        Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
        return r0 * n.x + r1 * n.y + r2 * n.z;
    }
    // A world-space normal in the object space of this object-to-world transform (M^T n, unnormalised).
    Vec3 normal_to_object(const Vec3& n) const {
        return {m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z, m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z,
                m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z};
    }
    bool is_finite() const {
        for (auto& r : m)
            for (float v : r)
                if (!std::isfinite(v)) return false;
        return true;
    }
};

// Ray-origin offset that is robust at every scale (Waechter & Binder, Ray Tracing Gems ch. 6):
// moves the point a few ULPs along the geometric normal instead of a fixed epsilon.
inline Vec3 offset_ray_origin(const Vec3& p, const Vec3& n) {
    constexpr float origin = 1.0f / 32.0f, float_scale = 1.0f / 65536.0f, int_scale = 256.0f;
    Vec3 out;
    for (int i = 0; i < 3; ++i) {
        int32_t of = static_cast<int32_t>(int_scale * n[i]);
        float pi = p[i];
        int32_t bits;
        std::memcpy(&bits, &pi, 4);
        bits += (pi < 0) ? -of : of;
        float moved;
        std::memcpy(&moved, &bits, 4);
        out[i] = std::fabs(pi) < origin ? pi + float_scale * n[i] : moved;
    }
    return out;
}

}  // namespace smis
