#include "scene/medium.h"

namespace smis {

PhaseSample HenyeyGreenstein::sample(const Vec3& wo, Point2 u) const {
    // Inverse CDF of HG in cos_theta = dot(-wo, wi) (pbrt-v3, 11.3.1, with the sign of its
    // convention folded into the frame around -wo).
    float cos_theta;
    if (std::fabs(g_) < 1e-3f) {
        cos_theta = 1.0f - 2.0f * u.x;
    } else {
        float s = (1.0f - g_ * g_) / (1.0f - g_ + 2.0f * g_ * u.x);
        cos_theta = clampf((1.0f + g_ * g_ - s * s) / (2.0f * g_), -1.0f, 1.0f);
    }
    float sin_theta = safe_sqrt(1.0f - cos_theta * cos_theta);
    float phi = 2.0f * kPi * u.y;
    PhaseSample ps;
    ps.wi = Frame(-wo).to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
    ps.pdf = density(cos_theta);
    return ps;
}

namespace {

// Below this optical depth the truncated exponential is indistinguishable from uniform in float.
constexpr float kThinSegment = 1e-6f;

}  // namespace

float truncated_exponential_pdf(float sigma, float len, float t) {
    if (!(t >= 0.0f && t < len)) return 0.0f;
    if (sigma * len < kThinSegment) return std::isfinite(len) ? 1.0f / len : 0.0f;
    return sigma * std::exp(-sigma * t) / -std::expm1(-sigma * len);
}

bool sample_truncated_exponential(float sigma, float len, float u, float* t) {
    if (sigma * len < kThinSegment) {
        if (!std::isfinite(len)) return false;  // no extinction on an infinite segment: nothing to sample
        *t = u * len;
    } else {
        *t = -std::log1p(u * std::expm1(-sigma * len)) / sigma;
    }
    *t = std::min(*t, std::nextafter(len, 0.0f));
    return true;
}

DistanceSample sample_segment_distance(const Color& sigma_t, float len, float u_channel, float u) {
    DistanceSample ds;
    if (!(len > 0.0f)) return ds;
    int c = std::min(2, static_cast<int>(u_channel * 3.0f));
    if (!sample_truncated_exponential(sigma_t[c], len, u, &ds.t)) return ds;
    ds.pdf = segment_distance_pdf(sigma_t, len, ds.t);
    return ds;
}

float segment_distance_pdf(const Color& sigma_t, float len, float t) {
    return (truncated_exponential_pdf(sigma_t.x, len, t) + truncated_exponential_pdf(sigma_t.y, len, t) +
            truncated_exponential_pdf(sigma_t.z, len, t)) *
           (1.0f / 3.0f);
}

EquiangularFrame equiangular_frame(const Vec3& o, const Vec3& d, float len, const Vec3& p) {
    EquiangularFrame f;
    f.delta = dot(p - o, d);
    f.h = length(p - (o + d * f.delta));
    if (!(f.h > 1e-7f * std::max(1.0f, std::fabs(f.delta))) || !std::isfinite(f.h)) return f;
    f.theta_a = std::atan2(-f.delta, f.h);
    f.theta_b = std::isinf(len) ? 0.5f * kPi : std::atan2(len - f.delta, f.h);
    f.valid = f.theta_b > f.theta_a;
    return f;
}

DistanceSample sample_equiangular(const EquiangularFrame& f, float u) {
    DistanceSample ds;
    if (!f.valid) return ds;
    float theta = f.theta_a + u * (f.theta_b - f.theta_a);
    ds.t = std::max(0.0f, f.delta + f.h * std::tan(theta));
    ds.pdf = equiangular_pdf(f, ds.t);
    return ds;
}

float equiangular_pdf(const EquiangularFrame& f, float t) {
    if (!f.valid) return 0.0f;
    float x = t - f.delta;
    return f.h / ((f.theta_b - f.theta_a) * (f.h * f.h + x * x));
}

}  // namespace smis
