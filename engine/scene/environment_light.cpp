#include "scene/environment_light.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace smis {

Point2 direction_to_equirectangular(const Vec3& d) {
    float len = length(d);
    if (!(len > 0.0f)) return {0.0f, 0.0f};
    float u = 0.5f - std::atan2(d.y, d.x) * (0.5f * kInvPi);
    float v = 1.0f - std::acos(clampf(d.z / len, -1.0f, 1.0f)) * kInvPi;
    return {u, v};
}

Vec3 equirectangular_to_direction(float u, float v) {
    float phi = kPi * (1.0f - 2.0f * u), theta = kPi * (1.0f - v);
    float s = std::sin(theta);
    return {s * std::cos(phi), s * std::sin(phi), std::cos(theta)};
}

Point2 direction_to_mirrorball(const Vec3& d_in) {
    // The ball's normal halves d and the view direction back to the camera (0, -1, 0).
    Vec3 d = d_in;
    d.y -= 1.0f;
    float div = 2.0f * std::sqrt(std::max(-0.5f * d.y, 0.0f));
    if (div > 0.0f) d = d / div;
    return {0.5f * (d.x + 1.0f), 0.5f * (d.z + 1.0f)};
}

ShaderRay EnvironmentLight::light_sample_kind() {
    ShaderRay k;
    k.camera = false;
    return k;
}

EnvironmentLight::EnvironmentLight(std::shared_ptr<const ShaderProgram> program, const Scene* scene, int width,
                                   int height, bool sample_sun)
    : program_(std::move(program)), scene_(scene) {
    if (width <= 0 || height <= 0) width = 1024, height = 512;
    width_ = std::clamp(width, 1, 8192);
    height_ = std::clamp(height, 1, 4096);
    const int w = width_, h = height_;
    if (const NishitaSky* sun = sample_sun ? program_->sampled_sun() : nullptr) {
        sun_dir_ = normalize(sun->sun_direction());
        sun_frame_ = Frame(sun_dir_);
        sun_one_minus_cos_ = 2.0f * sqr(std::sin(0.5f * sun->sun_half_angle()));  // 1 - cos, without cancellation
    }
    row_cdf_.assign(size_t(w + 1) * h, 0.0f);
    std::vector<double> row_sum(h, 0.0), row_color[3];
    for (auto& c : row_color) c.assign(h, 0.0);
    const ShaderRay kind = light_sample_kind();
    // The program at every cell centre (Cycles' shade_background_pixels), luminance x sin(theta):
    // the solid angle of a cell is proportional to sin(theta) of its latitude.
    tbb::parallel_for(tbb::blocked_range<int>(0, h), [&](const tbb::blocked_range<int>& rows) {
        std::vector<double> f(w);
        for (int y = rows.begin(); y < rows.end(); ++y) {
            const float v = (y + 0.5f) / h;
            const float sin_theta = std::sin(kPi * v);
            double sum = 0.0, rgb[3] = {0.0, 0.0, 0.0};
            for (int x = 0; x < w; ++x) {
                const Vec3 dir = equirectangular_to_direction((x + 0.5f) / w, v);
                Color L = radiance(dir, kind);
                f[x] = double(std::max(luminance(L), 0.0f)) * sin_theta;
                sum += f[x];
                // A sampled sun's light is integrated on its own below, not by the cells it covers.
                if (sun_one_minus_cos_ > 0.0f && sun_pdf(dir) > 0.0f) continue;
                for (int c = 0; c < 3; ++c) rgb[c] += double(L[c]) * sin_theta;
            }
            float* cdf = &row_cdf_[size_t(y) * (w + 1)];
            double acc = 0.0;
            cdf[0] = 0.0f;
            for (int x = 0; x < w; ++x) {
                acc += f[x];
                cdf[x + 1] = sum > 0.0 ? float(acc / sum) : float(x + 1) / w;
            }
            cdf[w] = 1.0f;
            row_sum[y] = sum;
            for (int c = 0; c < 3; ++c) row_color[c][y] = rgb[c];
        }
    });
    marginal_cdf_.assign(h + 1, 0.0);
    double total = 0.0, weights = 0.0, rgb[3] = {0.0, 0.0, 0.0};
    for (int y = 0; y < h; ++y) {
        total += row_sum[y];
        marginal_cdf_[y + 1] = total;
        weights += double(w) * std::sin(kPi * (y + 0.5f) / h);
        for (int c = 0; c < 3; ++c) rgb[c] += row_color[c][y];
    }
    empty_ = !(total > 0.0) || !std::isfinite(total);
    for (double& c : marginal_cdf_) c = empty_ ? 0.0 : c / total;
    marginal_cdf_[h] = 1.0;
    average_ = weights > 0.0 ? vmax(Color(float(rgb[0] / weights), float(rgb[1] / weights), float(rgb[2] / weights)),
                                    Color(0.0f))
                             : Color(0.0f);
    if (!is_finite(average_)) average_ = Color(0.0f);

    if (sun_one_minus_cos_ > 0.0f) {
        constexpr float kSunWeight = 4.0f, kMapWeight = 1.0f;  // Cycles' background sun_weight and map_weight
        sun_probability_ = empty_ ? 1.0f : kSunWeight / (kSunWeight + kMapWeight);
        // The disc's share of the mean radiance (light selection, the spectral emitter's colour):
        // its mean radiance from stratified points of the cone, times its solid angle over 4 pi.
        constexpr int kStrata = 16;
        Color disc(0.0f);
        for (int i = 0; i < kStrata; ++i)
            for (int j = 0; j < kStrata; ++j)
                disc += radiance(sun_frame_.to_world(sample_uniform_cone({(i + 0.5f) / kStrata, (j + 0.5f) / kStrata},
                                                                         sun_one_minus_cos_)),
                                 kind);
        const Color share = disc * (sun_one_minus_cos_ / (2.0f * kStrata * kStrata));
        if (is_finite(share)) average_ += share;
    }
}

ShaderContext EnvironmentLight::context(const Vec3& dir, const ShaderRay& kind) const {
    ShaderContext c;
    c.scene = scene_;
    c.ray = kind;
    c.background = true;
    c.P = dir;
    c.N = c.Ng = c.I = -dir;
    return c;
}

Color EnvironmentLight::radiance(const Vec3& dir, const ShaderRay& kind) const {
    ShaderResult res;
    program_->eval(context(dir, kind), &res);
    return is_finite(res.emission) ? vmax(res.emission, Color(0.0f)) : Color(0.0f);
}

float EnvironmentLight::cell_pdf(int x, int y) const {
    const float* cdf = &row_cdf_[size_t(y) * (width_ + 1)];
    return float(marginal_cdf_[y + 1] - marginal_cdf_[y]) * (cdf[x + 1] - cdf[x]);
}

// Density over (u, v) is cell_pdf x width x height; a solid angle dw = 2 pi^2 sin(theta) du dv.
LightSample EnvironmentLight::sample(const Vec3& ref, Point2 u) const {
    LightSample s;
    s.dist = kInf;
    if (sun_probability_ > 0.0f) {
        // Choose the strategy with u.x and reuse what is left of it for the strategy's own sample.
        if (u.x < sun_probability_) {
            u.x = std::min(u.x / sun_probability_, 1.0f - 1e-7f);
            s.wi = sun_frame_.to_world(sample_uniform_cone(u, sun_one_minus_cos_));
            s.pdf = pdf(s.wi);
            if (s.pdf > 0.0f) s.L = radiance(s.wi, light_sample_kind());
            return s;
        }
        u.x = std::min((u.x - sun_probability_) / (1.0f - sun_probability_), 1.0f - 1e-7f);
    }
    if (empty_) return s;
    // Row: the first whose cdf passes u.y (rows of zero probability are never chosen).
    const double uy = u.y;
    int y = int(std::upper_bound(marginal_cdf_.begin(), marginal_cdf_.end(), uy) - marginal_cdf_.begin()) - 1;
    y = std::clamp(y, 0, height_ - 1);
    while (y > 0 && !(marginal_cdf_[y + 1] > marginal_cdf_[y])) --y;
    const double row_p = marginal_cdf_[y + 1] - marginal_cdf_[y];
    if (!(row_p > 0.0)) return s;
    const float dv = float(std::clamp((uy - marginal_cdf_[y]) / row_p, 0.0, 1.0));
    const float* cdf = &row_cdf_[size_t(y) * (width_ + 1)];
    int x = int(std::upper_bound(cdf, cdf + width_ + 1, u.x) - cdf) - 1;
    x = std::clamp(x, 0, width_ - 1);
    while (x > 0 && !(cdf[x + 1] > cdf[x])) --x;
    const float cell_w = cdf[x + 1] - cdf[x];
    if (!(cell_w > 0.0f)) return s;
    const float du = clampf((u.x - cdf[x]) / cell_w, 0.0f, 1.0f);
    const float uu = (x + du) / width_, vv = std::min((y + dv) / height_, 1.0f);
    s.wi = equirectangular_to_direction(uu, vv);
    // The pdf from the cell the direction falls in, as pdf() finds it (a direction on a cell border
    // may round into the neighbour: both then agree).
    s.pdf = pdf(s.wi);
    if (s.pdf > 0.0f) s.L = radiance(s.wi, light_sample_kind());
    return s;
}

float EnvironmentLight::pdf(const Vec3& wi) const {
    if (sun_probability_ <= 0.0f) return map_pdf(wi);
    return sun_probability_ * sun_pdf(wi) + (1.0f - sun_probability_) * map_pdf(wi);
}

float EnvironmentLight::sun_pdf(const Vec3& wi) const {
    // 1 - cos of the angle to the axis as |wi - axis|^2 / 2: exact for the disc's tiny angles.
    Vec3 d = normalize(wi) - sun_dir_;
    return 0.5f * dot(d, d) <= sun_one_minus_cos_ ? uniform_cone_pdf(sun_one_minus_cos_) : 0.0f;
}

float EnvironmentLight::map_pdf(const Vec3& wi) const {
    if (empty_) return 0.0f;
    float sin_theta = std::sqrt(std::max(0.0f, 1.0f - sqr(clampf(wi.z, -1.0f, 1.0f))));
    if (!(sin_theta > 0.0f)) return 0.0f;
    Point2 uv = direction_to_equirectangular(wi);
    int x = std::clamp(int(uv.x * width_), 0, width_ - 1);
    int y = std::clamp(int(uv.y * height_), 0, height_ - 1);
    return cell_pdf(x, y) * float(width_) * float(height_) / (2.0f * kPi * kPi * sin_theta);
}

bool EnvironmentLight::intersect(const Ray& ray, LightHit* hit) const {
    return intersect_as(ray, light_sample_kind(), hit);
}

bool EnvironmentLight::intersect_as(const Ray& ray, const ShaderRay& kind, LightHit* hit) const {
    if (ray.tmax < kInf) return false;
    Vec3 d = normalize(ray.d);
    hit->t = kInf;
    hit->L = radiance(d, kind);
    hit->pdf = pdf(d);
    return true;
}

float EnvironmentLight::power(float scene_radius) const {
    // As WorldLight: the mean radiance through the scene's cross-section, from every direction.
    return luminance(average_) * kPi * sqr(scene_radius) * 4.0f;
}

}  // namespace smis
