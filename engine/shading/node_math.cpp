// Cycles 3.4 colour / converter node maths. See node_math.h for the contract of each function.
//
// The float expressions keep Cycles' evaluation order (e.g. interp is a + t * (b - a) while the Mix
// node's Float/Vector modes use a * (1 - t) + b * t), so results match the CPU kernel to the last
// bit or so; comments call out the places where the "obvious" formula would differ.
#include "shading/node_math.h"

#include <cfloat>
#include <cmath>
#include <cstring>

namespace smis::shading {
namespace {

// Cycles' scalar min/max/clamp are plain comparisons; their NaN behaviour (a NaN first argument is
// dropped by max(a, lo)) is what makes clamp(NaN, 0, 1) return 0, which ramp lookups rely on.
inline float cmin(float a, float b) { return a < b ? a : b; }
inline float cmax(float a, float b) { return a > b ? a : b; }
inline float cclamp(float a, float lo, float hi) { return cmin(cmax(a, lo), hi); }
inline float saturate(float a) { return cclamp(a, 0.0f, 1.0f); }

// (int)f as the x86 CPU kernel computes it: cvttss2si returns INT_MIN for NaN and out-of-range
// values. Matters for safe_pow's "is the exponent an integer" test with huge exponents.
inline int float_to_int_x86(float f) {
    if (!(f > -2147483904.0f && f < 2147483648.0f)) return INT32_MIN;
    return static_cast<int>(f);
}

inline float safe_divide(float a, float b) { return b != 0.0f ? a / b : 0.0f; }
inline float safe_modulo(float a, float b) { return b != 0.0f ? std::fmod(a, b) : 0.0f; }
inline float fractf(float a) { return a - std::floor(a); }

// Negative base with a non-integer exponent has no real result: 0. Otherwise plain powf (the CPU
// kernel does not special-case 0^0 or negative bases with integer exponents; powf handles them).
float safe_powf(float a, float b) {
    if (a < 0.0f && b != static_cast<float>(float_to_int_x86(b))) return 0.0f;
    return std::pow(a, b);
}

float safe_logf(float a, float b) {
    if (a <= 0.0f || b <= 0.0f) return 0.0f;
    return safe_divide(std::log(a), std::log(b));
}

// Godot-style wrap into [min, max): max and min may come in either order.
float wrapf(float value, float max, float min) {
    float range = max - min;
    return range != 0.0f ? value - range * std::floor((value - min) / range) : min;
}

float pingpongf(float a, float b) {
    return b != 0.0f ? std::fabs(fractf((a - b) / (b * 2.0f)) * b * 2.0f - b) : 0.0f;
}

// Polynomial smooth minimum (cubic, blend distance k).
float smoothminf(float a, float b, float k) {
    if (k != 0.0f) {
        float h = std::fmax(k - std::fabs(a - b), 0.0f) / k;
        return std::fmin(a, b) - h * h * h * k * (1.0f / 6.0f);
    }
    return std::fmin(a, b);
}

float compatible_signf(float f) {
    if (f == 0.0f) return 0.0f;
    return f < 0.0f ? -1.0f : 1.0f;
}

inline Vec3 v3(float x, float y, float z) { return Vec3(x, y, z); }
inline float vdot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline float vlen(const Vec3& a) { return std::sqrt(vdot(a, a)); }
// True division per component (smis::Vec3 / float multiplies by the reciprocal, which can differ in
// the last bit from Cycles).
inline Vec3 vdiv(const Vec3& a, float s) { return v3(a.x / s, a.y / s, a.z / s); }
inline Vec3 vfloor(const Vec3& a) { return v3(std::floor(a.x), std::floor(a.y), std::floor(a.z)); }
inline Vec3 interp(const Vec3& a, const Vec3& b, float t) {
    return v3(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z));
}
inline Vec3 safe_divide3(const Vec3& a, const Vec3& b) {
    return v3(safe_divide(a.x, b.x), safe_divide(a.y, b.y), safe_divide(a.z, b.z));
}

}  // namespace

// -------------------------------------------------------------------------------------------------
float math_op(MathOp op, float a, float b, float c) {
    switch (op) {
        case MathOp::Add: return a + b;
        case MathOp::Subtract: return a - b;
        case MathOp::Multiply: return a * b;
        case MathOp::Divide: return safe_divide(a, b);
        case MathOp::MultiplyAdd: return a * b + c;
        case MathOp::Power: return safe_powf(a, b);
        case MathOp::Logarithm: return safe_logf(a, b);
        case MathOp::Sqrt: return std::sqrt(cmax(a, 0.0f));
        case MathOp::InverseSqrt: return a > 0.0f ? 1.0f / std::sqrt(a) : 0.0f;
        case MathOp::Absolute: return std::fabs(a);
        case MathOp::Exponent: return std::exp(a);
        case MathOp::Minimum: return std::fmin(a, b);
        case MathOp::Maximum: return std::fmax(a, b);
        case MathOp::LessThan: return a < b ? 1.0f : 0.0f;
        case MathOp::GreaterThan: return a > b ? 1.0f : 0.0f;
        case MathOp::Sign: return compatible_signf(a);
        case MathOp::Compare:
            return (a == b || std::fabs(a - b) <= std::fmax(c, FLT_EPSILON)) ? 1.0f : 0.0f;
        case MathOp::SmoothMin: return smoothminf(a, b, c);
        case MathOp::SmoothMax: return -smoothminf(-a, -b, c);
        case MathOp::Round: return std::floor(a + 0.5f);  // halves round up, also for negatives
        case MathOp::Floor: return std::floor(a);
        case MathOp::Ceil: return std::ceil(a);
        case MathOp::Trunc: return a >= 0.0f ? std::floor(a) : std::ceil(a);
        case MathOp::Fract: return fractf(a);
        case MathOp::Modulo: return safe_modulo(a, b);  // fmod: takes the sign of a
        case MathOp::Wrap: return wrapf(a, b, c);
        case MathOp::Snap: return std::floor(safe_divide(a, b)) * b;
        case MathOp::PingPong: return pingpongf(a, b);
        case MathOp::Sine: return std::sin(a);
        case MathOp::Cosine: return std::cos(a);
        case MathOp::Tangent: return std::tan(a);
        case MathOp::Arcsine: return std::asin(cclamp(a, -1.0f, 1.0f));
        case MathOp::Arccosine: return std::acos(cclamp(a, -1.0f, 1.0f));
        case MathOp::Arctangent: return std::atan(a);
        case MathOp::Arctan2: return std::atan2(a, b);
        case MathOp::Sinh: return std::sinh(a);
        case MathOp::Cosh: return std::cosh(a);
        case MathOp::Tanh: return std::tanh(a);
        case MathOp::Radians: return a * (kPi / 180.0f);
        case MathOp::Degrees: return a * (180.0f / kPi);
        case MathOp::Count: break;
    }
    return 0.0f;
}

// -------------------------------------------------------------------------------------------------
bool vector_math_outputs_value(VectorMathOp op) {
    return op == VectorMathOp::DotProduct || op == VectorMathOp::Distance || op == VectorMathOp::Length;
}

void vector_math_op(VectorMathOp op, const Vec3& a, const Vec3& b, const Vec3& c, float scale,
                    Vec3* vector_out, float* value_out) {
    Vec3 v(0.0f);
    float value = 0.0f;
    switch (op) {
        case VectorMathOp::Add: v = a + b; break;
        case VectorMathOp::Subtract: v = a - b; break;
        case VectorMathOp::Multiply: v = a * b; break;
        case VectorMathOp::Divide: v = safe_divide3(a, b); break;
        case VectorMathOp::MultiplyAdd: v = a * b + c; break;
        case VectorMathOp::CrossProduct: v = cross(a, b); break;
        case VectorMathOp::Project: {
            float len_sq = vdot(b, b);
            v = len_sq != 0.0f ? b * (vdot(a, b) / len_sq) : Vec3(0.0f);
            break;
        }
        case VectorMathOp::Reflect: {
            // Plain normalize: a zero normal gives NaN, as in Cycles.
            Vec3 n = vdiv(b, vlen(b));
            v = a - n * (2.0f * vdot(a, n));
            break;
        }
        case VectorMathOp::Refract: {
            Vec3 n = vdiv(b, vlen(b));
            float cos_i = vdot(n, a);
            float k = 1.0f - scale * scale * (1.0f - cos_i * cos_i);
            v = k < 0.0f ? Vec3(0.0f) : a * scale - n * (scale * cos_i + std::sqrt(k));
            break;
        }
        case VectorMathOp::Faceforward: v = vdot(c, b) < 0.0f ? a : -a; break;
        case VectorMathOp::DotProduct: value = vdot(a, b); break;
        case VectorMathOp::Distance: value = vlen(a - b); break;
        case VectorMathOp::Length: value = vlen(a); break;
        case VectorMathOp::Scale: v = a * scale; break;
        case VectorMathOp::Normalize: {
            float len = vlen(a);
            v = len != 0.0f ? a * (1.0f / len) : a;  // zero stays zero
            break;
        }
        case VectorMathOp::Absolute: v = v3(std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)); break;
        // SSE min/max: return the second operand when the first comparison fails (also for NaN).
        case VectorMathOp::Minimum: v = v3(cmin(a.x, b.x), cmin(a.y, b.y), cmin(a.z, b.z)); break;
        case VectorMathOp::Maximum: v = v3(cmax(a.x, b.x), cmax(a.y, b.y), cmax(a.z, b.z)); break;
        case VectorMathOp::Floor: v = vfloor(a); break;
        case VectorMathOp::Ceil: v = v3(std::ceil(a.x), std::ceil(a.y), std::ceil(a.z)); break;
        case VectorMathOp::Fraction: v = a - vfloor(a); break;
        case VectorMathOp::Modulo:
            v = v3(safe_modulo(a.x, b.x), safe_modulo(a.y, b.y), safe_modulo(a.z, b.z));
            break;
        case VectorMathOp::Wrap:
            v = v3(wrapf(a.x, b.x, c.x), wrapf(a.y, b.y, c.y), wrapf(a.z, b.z, c.z));
            break;
        case VectorMathOp::Snap: v = vfloor(safe_divide3(a, b)) * b; break;
        case VectorMathOp::Sine: v = v3(std::sin(a.x), std::sin(a.y), std::sin(a.z)); break;
        case VectorMathOp::Cosine: v = v3(std::cos(a.x), std::cos(a.y), std::cos(a.z)); break;
        case VectorMathOp::Tangent: v = v3(std::tan(a.x), std::tan(a.y), std::tan(a.z)); break;
        case VectorMathOp::Count: break;
    }
    if (vector_out) *vector_out = v;
    if (value_out) *value_out = value;
}

// -------------------------------------------------------------------------------------------------
// Colour models.
Color rgb_to_hsv(const Color& rgb) {
    float cmax_ = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
    float cmin_ = cmin(rgb.x, cmin(rgb.y, rgb.z));
    float cdelta = cmax_ - cmin_;
    float v = cmax_;
    float s = cmax_ != 0.0f ? cdelta / cmax_ : 0.0f;
    float h = 0.0f;
    if (s != 0.0f) {
        float cr = (cmax_ - rgb.x) / cdelta, cg = (cmax_ - rgb.y) / cdelta, cb = (cmax_ - rgb.z) / cdelta;
        if (rgb.x == cmax_)
            h = cb - cg;
        else if (rgb.y == cmax_)
            h = 2.0f + cr - cb;
        else
            h = 4.0f + cg - cr;
        h /= 6.0f;
        if (h < 0.0f) h += 1.0f;
    }
    return {h, s, v};
}

Color hsv_to_rgb(const Color& hsv) {
    float h = hsv.x, s = hsv.y, v = hsv.z;
    if (s == 0.0f) return {v, v, v};
    if (h == 1.0f) h = 0.0f;
    h *= 6.0f;
    float i = std::floor(h);
    float f = h - i;
    float p = v * (1.0f - s);
    float q = v * (1.0f - s * f);
    float t = v * (1.0f - s * (1.0f - f));
    // Any sector outside 0..4 (including negative hues) falls into the last one, as in Cycles.
    if (i == 0.0f) return {v, t, p};
    if (i == 1.0f) return {q, v, p};
    if (i == 2.0f) return {p, v, t};
    if (i == 3.0f) return {p, q, v};
    if (i == 4.0f) return {t, p, v};
    return {v, p, q};
}

Color rgb_to_hsl(const Color& rgb) {
    float cmax_ = std::fmax(rgb.x, std::fmax(rgb.y, rgb.z));
    float cmin_ = cmin(rgb.x, cmin(rgb.y, rgb.z));
    float l = cmin(1.0f, (cmax_ + cmin_) / 2.0f);
    float h = 0.0f, s = 0.0f;
    if (cmax_ != cmin_) {
        float cdelta = cmax_ - cmin_;
        s = l > 0.5f ? cdelta / (2.0f - cmax_ - cmin_) : cdelta / (cmax_ + cmin_);
        if (cmax_ == rgb.x)
            h = (rgb.y - rgb.z) / cdelta + (rgb.y < rgb.z ? 6.0f : 0.0f);
        else if (cmax_ == rgb.y)
            h = (rgb.z - rgb.x) / cdelta + 2.0f;
        else
            h = (rgb.x - rgb.y) / cdelta + 4.0f;
    }
    return {h / 6.0f, s, l};
}

Color hsl_to_rgb(const Color& hsl) {
    float h = hsl.x, s = hsl.y, l = hsl.z;
    float nr = saturate(std::fabs(h * 6.0f - 3.0f) - 1.0f);
    float ng = saturate(2.0f - std::fabs(h * 6.0f - 2.0f));
    float nb = saturate(2.0f - std::fabs(h * 6.0f - 4.0f));
    float chroma = (1.0f - std::fabs(2.0f * l - 1.0f)) * s;
    return {(nr - 0.5f) * chroma + l, (ng - 0.5f) * chroma + l, (nb - 0.5f) * chroma + l};
}

// -------------------------------------------------------------------------------------------------
// Mix blend modes (Cycles' svm_mix_*). Per-channel helpers keep the branches of the C originals.
namespace {

float overlay1(float t, float a, float b) {
    float tm = 1.0f - t;
    return a < 0.5f ? a * (tm + 2.0f * t * b) : 1.0f - (tm + 2.0f * t * (1.0f - b)) * (1.0f - a);
}

float divide1(float t, float a, float b) {
    return b != 0.0f ? (1.0f - t) * a + t * a / b : a;  // channel kept where b is 0
}

float dodge1(float t, float a, float b) {
    if (a == 0.0f) return a;
    float tmp = 1.0f - t * b;
    if (tmp <= 0.0f) return 1.0f;
    tmp = a / tmp;
    return tmp > 1.0f ? 1.0f : tmp;
}

float burn1(float t, float a, float b) {
    float tmp = (1.0f - t) + t * b;
    if (tmp <= 0.0f) return 0.0f;
    tmp = 1.0f - (1.0f - a) / tmp;
    if (tmp < 0.0f) return 0.0f;
    return tmp > 1.0f ? 1.0f : tmp;
}

}  // namespace

Color mix_blend(MixBlend blend, float t, const Color& a, const Color& b) {
    switch (blend) {
        case MixBlend::Mix: return interp(a, b, t);
        case MixBlend::Darken: return interp(a, v3(cmin(a.x, b.x), cmin(a.y, b.y), cmin(a.z, b.z)), t);
        case MixBlend::Multiply: return interp(a, a * b, t);
        case MixBlend::Burn: return v3(burn1(t, a.x, b.x), burn1(t, a.y, b.y), burn1(t, a.z, b.z));
        case MixBlend::Lighten: return interp(a, v3(cmax(a.x, b.x), cmax(a.y, b.y), cmax(a.z, b.z)), t);
        case MixBlend::Screen: {
            float tm = 1.0f - t;
            auto s = [&](float x, float y) { return 1.0f - (tm + t * (1.0f - y)) * (1.0f - x); };
            return v3(s(a.x, b.x), s(a.y, b.y), s(a.z, b.z));
        }
        case MixBlend::Dodge: return v3(dodge1(t, a.x, b.x), dodge1(t, a.y, b.y), dodge1(t, a.z, b.z));
        case MixBlend::Add: return interp(a, a + b, t);
        case MixBlend::Overlay:
            return v3(overlay1(t, a.x, b.x), overlay1(t, a.y, b.y), overlay1(t, a.z, b.z));
        case MixBlend::SoftLight: {
            // (1 - t) a + t ((1 - a) b a + a screen(a, b)), Cycles' variant of soft light.
            float tm = 1.0f - t;
            auto s = [&](float x, float y) {
                float scr = 1.0f - (1.0f - y) * (1.0f - x);
                return tm * x + t * ((1.0f - x) * y * x + x * scr);
            };
            return v3(s(a.x, b.x), s(a.y, b.y), s(a.z, b.z));
        }
        case MixBlend::LinearLight: {
            auto l = [&](float x, float y) { return x + t * (2.0f * y + -1.0f); };
            return v3(l(a.x, b.x), l(a.y, b.y), l(a.z, b.z));
        }
        case MixBlend::Difference:
            return interp(a, v3(std::fabs(a.x - b.x), std::fabs(a.y - b.y), std::fabs(a.z - b.z)), t);
        case MixBlend::Subtract: return interp(a, a - b, t);
        case MixBlend::Divide: return v3(divide1(t, a.x, b.x), divide1(t, a.y, b.y), divide1(t, a.z, b.z));
        case MixBlend::Hue: {
            Color hsv2 = rgb_to_hsv(b);
            if (hsv2.y == 0.0f) return a;  // grey B has no hue to give
            Color hsv = rgb_to_hsv(a);
            hsv.x = hsv2.x;
            return interp(a, hsv_to_rgb(hsv), t);
        }
        case MixBlend::Saturation: {
            Color hsv = rgb_to_hsv(a);
            if (hsv.y == 0.0f) return a;  // grey A stays grey (no hue to saturate)
            Color hsv2 = rgb_to_hsv(b);
            hsv.y = (1.0f - t) * hsv.y + t * hsv2.y;
            return hsv_to_rgb(hsv);
        }
        case MixBlend::Color: {
            Color hsv2 = rgb_to_hsv(b);
            if (hsv2.y == 0.0f) return a;
            Color hsv = rgb_to_hsv(a);
            hsv.x = hsv2.x;
            hsv.y = hsv2.y;
            return interp(a, hsv_to_rgb(hsv), t);
        }
        case MixBlend::Value: {
            Color hsv = rgb_to_hsv(a);
            Color hsv2 = rgb_to_hsv(b);
            hsv.z = (1.0f - t) * hsv.z + t * hsv2.z;
            return hsv_to_rgb(hsv);
        }
        case MixBlend::Count: break;
    }
    return Color(0.0f);
}

float mix_float(float fac, float a, float b) { return a * (1.0f - fac) + b * fac; }

Vec3 mix_vector(const Vec3& fac, const Vec3& a, const Vec3& b) {
    return v3(a.x * (1.0f - fac.x) + b.x * fac.x, a.y * (1.0f - fac.y) + b.y * fac.y,
              a.z * (1.0f - fac.z) + b.z * fac.z);
}

// -------------------------------------------------------------------------------------------------
Color hue_saturation_value(float hue, float saturation, float value, float fac, const Color& color) {
    Color hsv = rgb_to_hsv(color);
    // fmod keeps the sign, so a negative shifted hue stays negative and hsv_to_rgb maps it to its
    // last sector, exactly like Cycles (Blender's UI range keeps hue in [0, 1] so this is rare).
    hsv.x = std::fmod(hsv.x + hue + 0.5f, 1.0f);
    hsv.y = saturate(hsv.y * saturation);
    hsv.z *= value;
    Color rgb = hsv_to_rgb(hsv);
    auto blend = [&](float x, float in) { return std::fmax(fac * x + (1.0f - fac) * in, 0.0f); };
    return {blend(rgb.x, color.x), blend(rgb.y, color.y), blend(rgb.z, color.z)};
}

Color bright_contrast(const Color& color, float bright, float contrast) {
    float a = 1.0f + contrast;
    float b = bright - contrast * 0.5f;
    return {cmax(a * color.x + b, 0.0f), cmax(a * color.y + b, 0.0f), cmax(a * color.z + b, 0.0f)};
}

Color gamma_node(const Color& color, float gamma) {
    if (gamma == 0.0f) return Color(1.0f);
    auto g = [&](float x) { return x > 0.0f ? std::pow(x, gamma) : x; };
    return {g(color.x), g(color.y), g(color.z)};
}

Color invert_node(float fac, const Color& color) {
    auto inv = [&](float x) { return fac * (1.0f - x) + (1.0f - fac) * x; };
    return {inv(color.x), inv(color.y), inv(color.z)};
}

float rgb_to_bw(const Color& c) {
    // Row Y of the inverse of kXyzToRgb as Cycles computes it in float (measured: RGB to BW of pure
    // red / green / blue in Blender 3.4.1); they sum to 1.00000095.
    return c.x * 0.212672979f + c.y * 0.715152621f + c.z * 0.0721754432f;
}

// -------------------------------------------------------------------------------------------------
namespace {

// Blackbody fit of Cycles 3.4 (kernel/tables.h): per temperature band, R and G are
// a / T + b T + c and B is ((a T + b) T + c) T + d, in Rec.709. Band edges in kelvin below.
constexpr float kBlackbodyEdges[6] = {965.0f, 1167.0f, 1449.0f, 1902.0f, 3315.0f, 6365.0f};
constexpr float kBlackbodyR[7][3] = {
    {1.61919106e+03f, -2.05010916e-03f, 5.02995757e+00f},
    {2.48845471e+03f, -1.11330907e-03f, 3.22621544e+00f},
    {3.34143193e+03f, -4.86551192e-04f, 1.76486769e+00f},
    {4.09461742e+03f, -1.27446582e-04f, 7.25731635e-01f},
    {4.67028036e+03f, 2.91258199e-05f, 1.26703442e-01f},
    {4.59509185e+03f, 2.87495649e-05f, 1.50345020e-01f},
    {3.78717450e+03f, 9.35907826e-06f, 3.99075871e-01f}};
constexpr float kBlackbodyG[7][3] = {
    {-4.88999748e+02f, 6.04330754e-04f, -7.55807526e-02f},
    {-7.55994277e+02f, 3.16730098e-04f, 4.78306139e-01f},
    {-1.02363977e+03f, 1.20223470e-04f, 9.36662319e-01f},
    {-1.26571316e+03f, 4.87340896e-06f, 1.27054498e+00f},
    {-1.42529332e+03f, -4.01150431e-05f, 1.43972784e+00f},
    {-1.17554822e+03f, -2.16378048e-05f, 1.30408023e+00f},
    {-5.00799571e+02f, -4.59832026e-06f, 1.09098763e+00f}};
constexpr float kBlackbodyB[7][4] = {
    {5.96945309e-11f, -4.85742887e-08f, -9.70622247e-05f, -4.07936148e-03f},
    {2.40430366e-11f, 5.55021075e-08f, -1.98503712e-04f, 2.89312858e-02f},
    {-1.40949732e-11f, 1.89878968e-07f, -3.56632824e-04f, 9.10767778e-02f},
    {-3.61460868e-11f, 2.84822009e-07f, -4.93211319e-04f, 1.56723440e-01f},
    {-1.97075738e-11f, 1.75359352e-07f, -2.50542825e-04f, -2.22783266e-02f},
    {-1.61997957e-13f, -1.64216008e-08f, 3.86216271e-04f, -7.38077418e-01f},
    {6.72650283e-13f, -2.73078809e-08f, 4.24098264e-04f, -7.52335691e-01f}};

// CIE 1931 2-degree colour matching functions x, y, z, 380..780 nm in 5 nm steps (81 rows).
constexpr float kCie[81][3] = {
    {0.0014f, 0.0000f, 0.0065f}, {0.0022f, 0.0001f, 0.0105f}, {0.0042f, 0.0001f, 0.0201f},
    {0.0076f, 0.0002f, 0.0362f}, {0.0143f, 0.0004f, 0.0679f}, {0.0232f, 0.0006f, 0.1102f},
    {0.0435f, 0.0012f, 0.2074f}, {0.0776f, 0.0022f, 0.3713f}, {0.1344f, 0.0040f, 0.6456f},
    {0.2148f, 0.0073f, 1.0391f}, {0.2839f, 0.0116f, 1.3856f}, {0.3285f, 0.0168f, 1.6230f},
    {0.3483f, 0.0230f, 1.7471f}, {0.3481f, 0.0298f, 1.7826f}, {0.3362f, 0.0380f, 1.7721f},
    {0.3187f, 0.0480f, 1.7441f}, {0.2908f, 0.0600f, 1.6692f}, {0.2511f, 0.0739f, 1.5281f},
    {0.1954f, 0.0910f, 1.2876f}, {0.1421f, 0.1126f, 1.0419f}, {0.0956f, 0.1390f, 0.8130f},
    {0.0580f, 0.1693f, 0.6162f}, {0.0320f, 0.2080f, 0.4652f}, {0.0147f, 0.2586f, 0.3533f},
    {0.0049f, 0.3230f, 0.2720f}, {0.0024f, 0.4073f, 0.2123f}, {0.0093f, 0.5030f, 0.1582f},
    {0.0291f, 0.6082f, 0.1117f}, {0.0633f, 0.7100f, 0.0782f}, {0.1096f, 0.7932f, 0.0573f},
    {0.1655f, 0.8620f, 0.0422f}, {0.2257f, 0.9149f, 0.0298f}, {0.2904f, 0.9540f, 0.0203f},
    {0.3597f, 0.9803f, 0.0134f}, {0.4334f, 0.9950f, 0.0087f}, {0.5121f, 1.0000f, 0.0057f},
    {0.5945f, 0.9950f, 0.0039f}, {0.6784f, 0.9786f, 0.0027f}, {0.7621f, 0.9520f, 0.0021f},
    {0.8425f, 0.9154f, 0.0018f}, {0.9163f, 0.8700f, 0.0017f}, {0.9786f, 0.8163f, 0.0014f},
    {1.0263f, 0.7570f, 0.0011f}, {1.0567f, 0.6949f, 0.0010f}, {1.0622f, 0.6310f, 0.0008f},
    {1.0456f, 0.5668f, 0.0006f}, {1.0026f, 0.5030f, 0.0003f}, {0.9384f, 0.4412f, 0.0002f},
    {0.8544f, 0.3810f, 0.0002f}, {0.7514f, 0.3210f, 0.0001f}, {0.6424f, 0.2650f, 0.0000f},
    {0.5419f, 0.2170f, 0.0000f}, {0.4479f, 0.1750f, 0.0000f}, {0.3608f, 0.1382f, 0.0000f},
    {0.2835f, 0.1070f, 0.0000f}, {0.2187f, 0.0816f, 0.0000f}, {0.1649f, 0.0610f, 0.0000f},
    {0.1212f, 0.0446f, 0.0000f}, {0.0874f, 0.0320f, 0.0000f}, {0.0636f, 0.0232f, 0.0000f},
    {0.0468f, 0.0170f, 0.0000f}, {0.0329f, 0.0119f, 0.0000f}, {0.0227f, 0.0082f, 0.0000f},
    {0.0158f, 0.0057f, 0.0000f}, {0.0114f, 0.0041f, 0.0000f}, {0.0081f, 0.0029f, 0.0000f},
    {0.0058f, 0.0021f, 0.0000f}, {0.0041f, 0.0015f, 0.0000f}, {0.0029f, 0.0010f, 0.0000f},
    {0.0020f, 0.0007f, 0.0000f}, {0.0014f, 0.0005f, 0.0000f}, {0.0010f, 0.0004f, 0.0000f},
    {0.0007f, 0.0002f, 0.0000f}, {0.0005f, 0.0002f, 0.0000f}, {0.0003f, 0.0001f, 0.0000f},
    {0.0002f, 0.0001f, 0.0000f}, {0.0002f, 0.0001f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f},
    {0.0001f, 0.0000f, 0.0000f}, {0.0001f, 0.0000f, 0.0000f}, {0.0000f, 0.0000f, 0.0000f}};

// XYZ (D65) -> scene linear (Rec.709) as Cycles 3.4 builds it from Blender's OCIO config: the
// aces_interchange role gives (srgb_to_xyz^-1 * AP0_to_XYZ_D65[OCIO, exact]) * AP0_to_XYZ_D65[Cycles'
// 6-digit copy]^-1, i.e. the inverse srgb_to_xyz matrix up to ~1e-6 (computed in double here).
constexpr float kXyzToRgb[3][3] = {{3.24045491f, -1.53714013f, -0.498532176f},
                                   {-0.969266295f, 1.87601042f, 0.0415556692f},
                                   {0.0556431971f, -0.204025343f, 1.05722475f}};

}  // namespace

Color blackbody(float t) {
    Color c;
    if (t >= 12000.0f) {
        c = Color(0.8262954810464208f, 0.9945080501520986f, 1.566307710274283f);
    } else if (t < 800.0f) {
        // Arbitrary dim lower limit, shared with OSL.
        c = Color(5.413294490189271f, -0.20319390035873933f, -0.0822535242887164f);
    } else {
        int i = 0;
        while (i < 6 && t >= kBlackbodyEdges[i]) ++i;
        const float* r = kBlackbodyR[i];
        const float* g = kBlackbodyG[i];
        const float* b = kBlackbodyB[i];
        float t_inv = 1.0f / t;
        c = Color(r[0] * t_inv + r[1] * t + r[2], g[0] * t_inv + g[1] * t + g[2],
                  ((b[0] * t + b[1]) * t + b[2]) * t + b[3]);
    }
    // Cycles converts Rec.709 to the scene-linear space, which is Rec.709 itself in Blender's
    // config (its is_rec709 short cut), and drops the negative out-of-gamut parts.
    return {std::fmax(c.x, 0.0f), std::fmax(c.y, 0.0f), std::fmax(c.z, 0.0f)};
}

Color wavelength_to_rgb(float nm) {
    float ii = (nm - 380.0f) * (1.0f / 5.0f);
    // Truncation towards zero, so ii in (-1, 0) still uses row 0 (extrapolated); NaN or huge values
    // give INT_MIN (x86 cvttss2si), i.e. black.
    int i = float_to_int_x86(ii);
    Vec3 xyz(0.0f);
    if (i >= 0 && i < 80) {
        float f = ii - static_cast<float>(i);
        const float* c0 = kCie[i];
        const float* c1 = kCie[i + 1];
        xyz = interp(Vec3(c0[0], c0[1], c0[2]), Vec3(c1[0], c1[1], c1[2]), f);
    }
    Color rgb;
    for (int k = 0; k < 3; ++k)
        rgb[k] = kXyzToRgb[k][0] * xyz.x + kXyzToRgb[k][1] * xyz.y + kXyzToRgb[k][2] * xyz.z;
    rgb *= 1.0f / 2.52f;  // Cycles' empirical scale to keep the components <= 1
    return {std::fmax(rgb.x, 0.0f), std::fmax(rgb.y, 0.0f), std::fmax(rgb.z, 0.0f)};
}

// -------------------------------------------------------------------------------------------------
namespace {

float smoothstep(float edge0, float edge1, float x) {
    if (x < edge0) return 0.0f;
    if (x >= edge1) return 1.0f;
    float t = (x - edge0) / (edge1 - edge0);
    return (3.0f - 2.0f * t) * (t * t);
}

float smootherstep(float edge0, float edge1, float x) {
    x = cclamp(safe_divide(x - edge0, edge1 - edge0), 0.0f, 1.0f);
    return x * x * x * (x * (x * 6.0f - 15.0f) + 10.0f);
}

float clamp_to_range(float v, float lo, float hi) {
    return lo > hi ? cclamp(v, hi, lo) : cclamp(v, lo, hi);
}

}  // namespace

float map_range(MapRangeType type, float value, float from_min, float from_max, float to_min,
                 float to_max, float steps, bool clamp) {
    float result = 0.0f;
    if (from_max != from_min) {
        float factor = value;
        switch (type) {
            case MapRangeType::Stepped:
                factor = (value - from_min) / (from_max - from_min);
                factor = steps > 0.0f ? std::floor(factor * (steps + 1.0f)) / steps : 0.0f;
                break;
            case MapRangeType::SmoothStep:
                factor = from_min > from_max ? 1.0f - smoothstep(from_max, from_min, factor)
                                             : smoothstep(from_min, from_max, factor);
                break;
            case MapRangeType::SmootherStep:
                factor = from_min > from_max ? 1.0f - smootherstep(from_max, from_min, factor)
                                             : smootherstep(from_min, from_max, factor);
                break;
            default:
                factor = (value - from_min) / (from_max - from_min);
                break;
        }
        result = to_min + factor * (to_max - to_min);
    }
    // Cycles expands the float node's clamp into a Clamp node in RANGE mode after it.
    return clamp ? clamp_to_range(result, to_min, to_max) : result;
}

Vec3 map_range_vector(MapRangeType type, const Vec3& value, const Vec3& from_min, const Vec3& from_max,
                      const Vec3& to_min, const Vec3& to_max, const Vec3& steps, bool clamp) {
    Vec3 result;
    for (int k = 0; k < 3; ++k) {
        float f = safe_divide(value[k] - from_min[k], from_max[k] - from_min[k]);
        switch (type) {
            case MapRangeType::Stepped:
                f = steps[k] > 0.0f ? std::floor(f * (steps[k] + 1.0f)) / steps[k] : 0.0f;
                break;
            case MapRangeType::SmoothStep:
                f = cclamp(f, 0.0f, 1.0f);
                f = (3.0f - 2.0f * f) * (f * f);
                break;
            case MapRangeType::SmootherStep:
                f = cclamp(f, 0.0f, 1.0f);
                f = f * f * f * (f * (f * 6.0f - 15.0f) + 10.0f);
                break;
            default: break;
        }
        result[k] = to_min[k] + f * (to_max[k] - to_min[k]);
    }
    bool use_clamp = clamp && type != MapRangeType::SmoothStep && type != MapRangeType::SmootherStep;
    if (use_clamp)
        for (int k = 0; k < 3; ++k) result[k] = clamp_to_range(result[k], to_min[k], to_max[k]);
    return result;
}

float clamp_node(bool range, float value, float min, float max) {
    if (range && min > max) return cclamp(value, max, min);
    return cclamp(value, min, max);
}

// -------------------------------------------------------------------------------------------------
namespace {

// Cycles' rgb_ramp_lookup over float4 entries; channel k (0..3, 3 = alpha) or all.
inline float entry(const Rgba& e, int k) { return k < 3 ? e.rgb[k] : e.a; }

float ramp_channel(const Rgba* table, int n, float f, bool interpolate, bool extrapolate, int k) {
    if ((f < 0.0f || f > 1.0f) && extrapolate) {
        float t0, dy;
        if (f < 0.0f) {
            t0 = entry(table[0], k);
            dy = t0 - entry(table[1], k);
            f = -f;
        } else {
            t0 = entry(table[n - 1], k);
            dy = t0 - entry(table[n - 2], k);
            f = f - 1.0f;
        }
        return t0 + dy * f * static_cast<float>(n - 1);
    }
    f = saturate(f) * static_cast<float>(n - 1);
    int i = static_cast<int>(f);
    i = i < 0 ? 0 : (i > n - 1 ? n - 1 : i);
    float t = f - static_cast<float>(i);
    float a = entry(table[i], k);
    if (interpolate && t > 0.0f) a = (1.0f - t) * a + t * entry(table[i + 1], k);
    return a;
}

Vec3 curves_lookup(const Rgba* table, int n, float min_x, float max_x, float fac, const Vec3& in,
                   bool extrapolate) {
    float range = max_x - min_x;
    Vec3 out;
    for (int k = 0; k < 3; ++k) {
        float rel = (in[k] - min_x) / range;
        out[k] = ramp_channel(table, n, rel, true, extrapolate, k);
    }
    return v3((1.0f - fac) * in.x + fac * out.x, (1.0f - fac) * in.y + fac * out.y,
              (1.0f - fac) * in.z + fac * out.z);
}

}  // namespace

Rgba ramp_lookup(const Rgba* table, int n, float f, bool interpolate, bool extrapolate) {
    Rgba out;
    if (n <= 0) return Rgba{Color(0.0f), 0.0f};
    if (n == 1) return table[0];
    for (int k = 0; k < 3; ++k) out.rgb[k] = ramp_channel(table, n, f, interpolate, extrapolate, k);
    out.a = ramp_channel(table, n, f, interpolate, extrapolate, 3);
    return out;
}

Color rgb_curves(const Rgba* table, int n, float min_x, float max_x, float fac, const Color& in,
                 bool extrapolate) {
    if (n < 2) return in;
    return curves_lookup(table, n, min_x, max_x, fac, in, extrapolate);
}

Vec3 vector_curves(const Rgba* table, int n, float min_x, float max_x, float fac, const Vec3& in,
                   bool extrapolate) {
    if (n < 2) return in;
    return curves_lookup(table, n, min_x, max_x, fac, in, extrapolate);
}

// -------------------------------------------------------------------------------------------------
namespace {

constexpr const char* kMathNames[] = {
    "ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "POWER", "LOGARITHM", "SQRT",
    "INVERSE_SQRT", "ABSOLUTE", "EXPONENT", "MINIMUM", "MAXIMUM", "LESS_THAN", "GREATER_THAN", "SIGN",
    "COMPARE", "SMOOTH_MIN", "SMOOTH_MAX", "ROUND", "FLOOR", "CEIL", "TRUNC", "FRACT", "MODULO", "WRAP",
    "SNAP", "PINGPONG", "SINE", "COSINE", "TANGENT", "ARCSINE", "ARCCOSINE", "ARCTANGENT", "ARCTAN2",
    "SINH", "COSH", "TANH", "RADIANS", "DEGREES"};
constexpr const char* kVectorMathNames[] = {
    "ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "CROSS_PRODUCT", "PROJECT", "REFLECT",
    "REFRACT", "FACEFORWARD", "DOT_PRODUCT", "DISTANCE", "LENGTH", "SCALE", "NORMALIZE", "ABSOLUTE",
    "MINIMUM", "MAXIMUM", "FLOOR", "CEIL", "FRACTION", "MODULO", "WRAP", "SNAP", "SINE", "COSINE",
    "TANGENT"};
constexpr const char* kBlendNames[] = {
    "MIX", "DARKEN", "MULTIPLY", "BURN", "LIGHTEN", "SCREEN", "DODGE", "ADD", "OVERLAY", "SOFT_LIGHT",
    "LINEAR_LIGHT", "DIFFERENCE", "SUBTRACT", "DIVIDE", "HUE", "SATURATION", "COLOR", "VALUE"};
constexpr const char* kMapRangeNames[] = {"LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP"};

static_assert(sizeof(kMathNames) / sizeof(kMathNames[0]) == size_t(MathOp::Count), "math names");
static_assert(sizeof(kVectorMathNames) / sizeof(kVectorMathNames[0]) == size_t(VectorMathOp::Count),
              "vector math names");
static_assert(sizeof(kBlendNames) / sizeof(kBlendNames[0]) == size_t(MixBlend::Count), "blend names");
static_assert(sizeof(kMapRangeNames) / sizeof(kMapRangeNames[0]) == size_t(MapRangeType::Count),
              "map range names");

template <typename E, size_t N>
bool lookup(const char* const (&names)[N], const char* id, E* out) {
    if (!id) return false;
    for (size_t i = 0; i < N; ++i)
        if (std::strcmp(names[i], id) == 0) {
            *out = static_cast<E>(i);
            return true;
        }
    return false;
}

template <size_t N>
const char* name_of(const char* const (&names)[N], size_t i) { return i < N ? names[i] : ""; }

}  // namespace

const char* math_op_name(MathOp op) { return name_of(kMathNames, size_t(op)); }
const char* vector_math_op_name(VectorMathOp op) { return name_of(kVectorMathNames, size_t(op)); }
const char* mix_blend_name(MixBlend blend) { return name_of(kBlendNames, size_t(blend)); }
const char* map_range_type_name(MapRangeType type) { return name_of(kMapRangeNames, size_t(type)); }
bool math_op_from_name(const char* id, MathOp* out) { return lookup(kMathNames, id, out); }
bool vector_math_op_from_name(const char* id, VectorMathOp* out) { return lookup(kVectorMathNames, id, out); }
bool mix_blend_from_name(const char* id, MixBlend* out) { return lookup(kBlendNames, id, out); }
bool map_range_type_from_name(const char* id, MapRangeType* out) { return lookup(kMapRangeNames, id, out); }

}  // namespace smis::shading
