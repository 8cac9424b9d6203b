#include "scene/lights.h"

#include <algorithm>
#include <stdexcept>

#include "scene/area_spread.h"

namespace smis {
namespace {

// Cycles converts Blender's Watts to radiance with these factors (scene/light.cpp, 3.4):
// point/spot: P / (4 pi) intensity spread over a disk of area pi r^2; area: P / (4 A).
constexpr float kAreaLightFactor = 0.25f;
constexpr float kPointLightFactor = 0.25f * kInvPi;

// Solid-angle density of uniformly sampling a point on a surface of `area`, seen from distance d
// under the cosine cos_light at the light.
inline float area_to_solid_angle(float area_pdf, float dist_sq, float cos_light) {
    if (!(cos_light > 1e-7f)) return 0.0f;
    return area_pdf * dist_sq / cos_light;
}

inline float smoothstep01(float x) {
    x = clampf(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

}  // namespace

float LightPoint::falloff(const Vec3& dir_from_light) const {
    if (!spot) return 1.0f;
    float c = dot(dir_from_light, axis);
    if (c <= cos_half) return 0.0f;
    float t = c - cos_half;
    if (smooth > 0.0f && t < smooth) c *= smoothstep01(t / smooth);
    return c;
}

namespace {

// Rectangle or ellipse, one-sided, emitting along -Z of the light object (Blender area light).
// With a spread below 180 degrees the emission is confined to a cone (AreaSpread); a rectangle then
// samples only the part of it that can reach the reference point, as Cycles does
// (light_spread_clamp_area_light): the rectangle around the disk of AreaSpread::reach() at the
// point's foot, clipped to the light; the pdf is that part's.
class AreaLight : public Light {
public:
    AreaLight(const Vec3& center, const Vec3& axis_u, const Vec3& axis_v, bool ellipse, const Color& radiance,
              AreaSpread spread)
        : center_(center), u_(axis_u), v_(axis_v), ellipse_(ellipse), radiance_(radiance), spread_(spread) {
        Vec3 n = cross(u_, v_);
        float len = length(n);
        area_ = 4.0f * len * (ellipse ? kPi / 4.0f : 1.0f);  // u_, v_ are half axes
        n_ = -(n / len);
        inv_u_sq_ = 1.0f / length_sq(u_);
        inv_v_sq_ = 1.0f / length_sq(v_);
        // The reachable part is a rectangle in the light's own axes: they must be orthogonal
        // (a sheared light samples all of itself, which is unbiased too).
        clip_ = spread_.active() && !ellipse_ && std::fabs(dot(u_, v_)) <= 1e-4f * length(u_) * length(v_);
    }
    LightSample sample(const Vec3& ref, Point2 u) const override {
        if (spread_.active()) return sample_with_spread(ref, u);
        Point2 ab = position(u);
        return sample_point(ref, ab.x, ab.y, area_);
    }
    // Out of line, so lights without a spread keep their short path: a rectangle samples the part
    // of itself that reaches ref, and the radiance falls off within the cone.
    [[gnu::noinline]] LightSample sample_with_spread(const Vec3& ref, Point2 u) const {
        Part part{-1.0f, 1.0f, -1.0f, 1.0f};
        if (clip_ && !reachable_part(ref, &part)) return LightSample{};
        Point2 ab = clip_ ? Point2{part.a0 + (part.a1 - part.a0) * u.x, part.b0 + (part.b1 - part.b0) * u.y}
                          : position(u);
        LightSample s = sample_point(ref, ab.x, ab.y, part.area(area_));
        if (s.pdf > 0.0f) s.L *= spread_.attenuation(-dot(s.wi, n_));
        return s;
    }
    // The point of the whole light at u, in half-axis coordinates.
    Point2 position(Point2 u) const {
        return ellipse_ ? sample_uniform_disk_concentric(u) : Point2{2.0f * u.x - 1.0f, 2.0f * u.y - 1.0f};
    }
    // The sample at (a, b) of a part of the light of `area` sampled uniformly.
    LightSample sample_point(const Vec3& ref, float a, float b, float area) const {
        LightSample s;
        Vec3 p = center_ + u_ * a + v_ * b;
        Vec3 d = p - ref;
        float dist_sq = length_sq(d);
        if (!(dist_sq > 0.0f)) return s;
        s.dist = std::sqrt(dist_sq);
        s.wi = d / s.dist;
        float cos_l = -dot(s.wi, n_);
        s.pdf = area_to_solid_angle(1.0f / area, dist_sq, cos_l);
        if (s.pdf > 0.0f) s.L = radiance_;
        return s;
    }
    float pdf(const Vec3& ref, const Vec3& wi) const override {
        Ray r{ref, wi, 0.0f, kInf};
        LightHit h;
        return intersect(r, &h) ? h.pdf : 0.0f;
    }
    bool intersect(const Ray& ray, LightHit* hit) const override {
        float denom = dot(ray.d, n_);
        if (!(denom < 0.0f)) return false;  // one-sided: only rays arriving against the emitting side
        float t = dot(center_ - ray.o, n_) / denom;
        if (!(t > ray.tmin && t < ray.tmax)) return false;
        Vec3 q = ray.o + ray.d * t - center_;
        float a = dot(q, u_) * inv_u_sq_, b = dot(q, v_) * inv_v_sq_;
        bool inside = ellipse_ ? (a * a + b * b <= 1.0f) : (std::fabs(a) <= 1.0f && std::fabs(b) <= 1.0f);
        if (!inside) return false;
        hit->t = t;
        if (spread_.active()) return spread_hit(ray.o, a, b, -denom, hit);
        hit->L = radiance_;
        hit->pdf = area_to_solid_angle(1.0f / area_, t * t, -denom);
        return true;
    }
    float power(float) const override { return luminance(radiance_) * area_ * kPi; }  // spread keeps it
    bool point_independent_of_reference() const override { return !clip_; }
    bool rectangle(LightRectangle* out) const override {
        // Photon planes need an orthogonal frame on the light (a sheared light falls back to NEE)
        // and constant radiance (a light with a spread too).
        if (ellipse_ || spread_.active() || std::fabs(dot(u_, v_)) > 1e-4f * length(u_) * length(v_)) return false;
        if (out) *out = {center_ - u_ - v_, u_ * 2.0f, v_ * 2.0f, n_, radiance_};
        return true;
    }
    bool bounds(LightBounds* out) const override {
        *out = {center_, std::max(length(u_ + v_), length(u_ - v_)), n_, true};
        return true;
    }

private:
    // A part of the rectangle in its half-axis coordinates, [a0, a1] x [b0, b1] within [-1, 1]^2.
    struct Part {
        float a0, a1, b0, b1;
        float area(float full) const { return full * 0.25f * (a1 - a0) * (b1 - b0); }
        bool contains(float a, float b) const { return a >= a0 && a <= a1 && b >= b0 && b <= b1; }
    };
    // The radiance and pdf of a hit at (a, b) seen under cos_light from `ref` (hit->t set), for a
    // light with a spread; false when the hit lies outside the cone or the part sampled from ref.
    [[gnu::noinline]] bool spread_hit(const Vec3& ref, float a, float b, float cos_light, LightHit* hit) const {
        const float falloff = spread_.attenuation(cos_light);
        if (!(falloff > 0.0f)) return false;
        float area = area_;
        if (clip_) {
            Part part;
            if (!reachable_part(ref, &part) || !part.contains(a, b)) return false;
            area = part.area(area_);
        }
        hit->L = radiance_ * falloff;
        hit->pdf = area_to_solid_angle(1.0f / area, hit->t * hit->t, cos_light);
        return true;
    }
    // The part of the rectangle that can light `ref`; false when none can.
    bool reachable_part(const Vec3& ref, Part* part) const {
        const Vec3 rel = ref - center_;
        const float reach = spread_.reach(std::fabs(dot(rel, n_)));
        const float len_u = std::sqrt(1.0f / inv_u_sq_), len_v = std::sqrt(1.0f / inv_v_sq_);
        const float cu = dot(rel, u_) / len_u, cv = dot(rel, v_) / len_v;  // the foot, in lengths
        part->a0 = std::max((cu - reach) / len_u, -1.0f);
        part->a1 = std::min((cu + reach) / len_u, 1.0f);
        part->b0 = std::max((cv - reach) / len_v, -1.0f);
        part->b1 = std::min((cv + reach) / len_v, 1.0f);
        return part->a0 < part->a1 && part->b0 < part->b1;
    }

    Vec3 center_, u_, v_, n_;
    bool ellipse_;
    Color radiance_;
    AreaSpread spread_;
    bool clip_ = false;
    float area_, inv_u_sq_, inv_v_sq_;
};

// Point and spot lights. With a radius they are a disk of that radius that always faces the shading
// point (Cycles 3.4 samples them this way), otherwise a delta light.
class PointLight : public Light {
public:
    PointLight(const Vec3& pos, float radius, const Color& intensity, bool spot, const Vec3& axis, float cos_half,
               float smooth)
        : pos_(pos), radius_(radius), intensity_(intensity), emitter_{pos, intensity, spot, axis, cos_half, smooth} {
        area_ = kPi * radius * radius;
    }
    bool is_delta() const override { return radius_ <= 0.0f; }
    LightSample sample(const Vec3& ref, Point2 u) const override {
        LightSample s;
        Vec3 to_center = pos_ - ref;
        float dc_sq = length_sq(to_center);
        if (!(dc_sq > 0.0f)) return s;
        if (radius_ <= 0.0f) {
            s.dist = std::sqrt(dc_sq);
            s.wi = to_center / s.dist;
            s.L = intensity_ * attenuation(-s.wi) / dc_sq;
            s.pdf = 1.0f;
            s.delta = true;
            return s;
        }
        Vec3 n = -to_center / std::sqrt(dc_sq);  // disk faces the reference point
        Frame f(n);
        Point2 d = sample_uniform_disk_concentric(u);
        Vec3 p = pos_ + (f.s * d.x + f.t * d.y) * radius_;
        Vec3 dir = p - ref;
        float dist_sq = length_sq(dir);
        s.dist = std::sqrt(dist_sq);
        s.wi = dir / s.dist;
        s.pdf = area_to_solid_angle(1.0f / area_, dist_sq, -dot(s.wi, n));
        if (s.pdf > 0.0f) s.L = intensity_ * (attenuation(-s.wi) / area_);
        return s;
    }
    float pdf(const Vec3& ref, const Vec3& wi) const override {
        Ray r{ref, wi, 0.0f, kInf};
        LightHit h;
        return intersect(r, &h) ? h.pdf : 0.0f;
    }
    bool intersect(const Ray& ray, LightHit* hit) const override {
        if (radius_ <= 0.0f) return false;
        if (misses_by_far(ray)) return false;
        Vec3 n = ray.o - pos_;
        float dn = length(n);
        if (!(dn > 0.0f)) return false;
        n = n / dn;
        float denom = dot(ray.d, n);
        if (!(denom < 0.0f)) return false;
        float t = dot(pos_ - ray.o, n) / denom;
        if (!(t > ray.tmin && t < ray.tmax)) return false;
        Vec3 q = ray.o + ray.d * t - pos_;
        if (length_sq(q) > radius_ * radius_) return false;
        hit->t = t;
        hit->L = intensity_ * (attenuation(-ray.d) / area_);
        hit->pdf = area_to_solid_angle(1.0f / area_, t * t, -denom);
        return true;
    }
    float power(float) const override {
        return luminance(intensity_) * 4.0f * kPi * (emitter_.spot ? 0.5f * (1.0f - emitter_.cos_half) : 1.0f);
    }
    bool point(LightPoint* out) const override {
        if (radius_ > 0.0f) return false;  // a disk facing each shading point: no fixed emitter
        if (out) *out = emitter_;
        return true;
    }
    bool bounds(LightBounds* out) const override {
        *out = {pos_, radius_, Vec3(0.0f, 0.0f, 0.0f), false};
        return true;
    }

private:
    // Whether the ray's line passes so far from the centre that the test below cannot find the disk,
    // with no square root or division (most rays: the light is small). Every point of the disk lies
    // within radius_ of pos_, so a hit needs the line's distance p from pos_ to be at most radius_ plus
    // the test's rounding, which is far below 1e-3 of |o - pos_| + |pos_|. The squared distance
    // p^2 |d|^2 = |v|^2 |d|^2 - (v.d)^2 (v = o - pos_) is rounded by a few ulps of |v|^2 |d|^2; the
    // margin below is (2 radius_)^2 plus 1e-4 (|v|^2 + |pos_|^2), so where it says "far" the test
    // rejects the ray too and the image does not change (NaN and Inf compare false: the test runs).
    bool misses_by_far(const Ray& ray) const {
        const Vec3 v = ray.o - pos_;
        const float vv = length_sq(v), dd = length_sq(ray.d), b = dot(v, ray.d);
        return vv * dd - b * b > dd * (4.0f * radius_ * radius_ + 1e-4f * (vv + pos_sq_));
    }
    float attenuation(const Vec3& dir_from_light) const { return emitter_.falloff(dir_from_light); }
    Vec3 pos_;
    float pos_sq_ = length_sq(pos_);
    float radius_, area_;
    Color intensity_;
    LightPoint emitter_;
};

// Sun: strength S (W/m^2) from a cone of angular diameter `angle` (a delta direction when 0).
class SunLight : public Light {
public:
    SunLight(const Vec3& to_sun, float angle, const Color& irradiance) : dir_(to_sun), frame_(to_sun) {
        float half = 0.5f * std::min(angle, kPi);
        cos_max_ = std::cos(half);
        one_minus_cos_ = 2.0f * sqr(std::sin(0.5f * half));
        delta_ = half < 1e-4f;
        irradiance_ = irradiance;
        // Cycles 3.4 spreads the strength uniformly over the disc's solid angle (measured: a surface
        // facing the sun receives S (1 + cos(angle/2)) / 2, not S), so radiance = S / solid angle.
        radiance_ = delta_ ? irradiance : irradiance / (2.0f * kPi * one_minus_cos_);
    }
    bool is_delta() const override { return delta_; }
    bool at_infinity() const override { return true; }
    LightSample sample(const Vec3& ref, Point2 u) const override {
        LightSample s;
        s.dist = kInf;
        if (delta_) {
            s.wi = dir_;
            s.L = irradiance_;
            s.pdf = 1.0f;
            s.delta = true;
            return s;
        }
        s.wi = frame_.to_world(sample_uniform_cone(u, one_minus_cos_));
        s.pdf = uniform_cone_pdf(one_minus_cos_);
        s.L = radiance_;
        return s;
    }
    float pdf(const Vec3& ref, const Vec3& wi) const override {
        return (!delta_ && dot(wi, dir_) >= cos_max_) ? uniform_cone_pdf(one_minus_cos_) : 0.0f;
    }
    bool intersect(const Ray& ray, LightHit* hit) const override {
        if (delta_ || dot(ray.d, dir_) < cos_max_ || ray.tmax < kInf) return false;
        hit->t = kInf;
        hit->L = radiance_;
        hit->pdf = uniform_cone_pdf(one_minus_cos_);
        return true;
    }
    float power(float scene_radius) const override { return luminance(irradiance_) * kPi * sqr(scene_radius); }

private:
    Vec3 dir_;
    Frame frame_;
    float cos_max_, one_minus_cos_;
    bool delta_;
    Color irradiance_, radiance_;
};

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

}  // namespace

std::unique_ptr<Light> make_light(const LightDesc& d) {
    require(d.to_world.is_finite(), "light matrix is not finite");
    require(is_finite(d.color) && min_component(d.color) >= 0.0f, "light colour must be finite and non-negative");
    Vec3 pos(d.to_world.m[0][3], d.to_world.m[1][3], d.to_world.m[2][3]);
    std::unique_ptr<Light> light;
    if (d.type == "SUN") {
        require(std::isfinite(d.strength) && d.strength >= 0.0f, "sun strength must be finite and non-negative");
        require(std::isfinite(d.angle) && d.angle >= 0.0f, "sun angle must be finite and non-negative");
        Vec3 to_sun = normalize(d.to_world.column(2));  // sun shines along its local -Z
        require(is_finite(to_sun), "sun direction is degenerate");
        light = std::make_unique<SunLight>(to_sun, d.angle, d.color * d.strength);
    } else {
        require(std::isfinite(d.power), "light power is not finite");
        require(d.power >= 0.0f, "light power is negative");
        if (d.type == "AREA") {
            bool ellipse = d.shape == "DISK" || d.shape == "ELLIPSE";
            bool square = d.shape == "SQUARE" || d.shape == "DISK";
            float sx = d.size, sy = square ? d.size : d.size_y;
            require(std::isfinite(sx) && std::isfinite(sy), "area light size is not finite");
            Vec3 u = d.to_world.column(0) * (0.5f * sx), v = d.to_world.column(1) * (0.5f * sy);
            float area = length(cross(u, v)) * 4.0f * (ellipse ? kPi / 4.0f : 1.0f);
            require(area > 1e-12f && std::isfinite(area), "area light has zero size");
            require(std::isfinite(d.spread) && d.spread >= 0.0f, "area light spread must be finite and non-negative");
            light = std::make_unique<AreaLight>(pos, u, v, ellipse, d.color * (d.power * kAreaLightFactor / area),
                                                AreaSpread::from_angle(d.spread));
        } else if (d.type == "POINT" || d.type == "SPOT") {
            require(std::isfinite(d.radius) && d.radius >= 0.0f, "light radius must be finite and non-negative");
            bool spot = d.type == "SPOT";
            Vec3 axis = -normalize(d.to_world.column(2));
            float cos_half = std::cos(0.5f * clampf(d.spot_size, 0.0f, kPi));
            float smooth = (1.0f - cos_half) * clampf(d.spot_blend, 0.0f, 1.0f);
            require(!spot || is_finite(axis), "spot direction is degenerate");
            light = std::make_unique<PointLight>(pos, d.radius, d.color * (d.power * kPointLightFactor), spot, axis,
                                                 cos_half, smooth);
        } else {
            throw std::invalid_argument("unknown light type '" + d.type + "'");
        }
    }
    light->visible_to_camera = d.visible_to_camera;
    light->cast_shadow = d.cast_shadow;
    light->use_mis = d.use_mis;
    light->visibility = d.visibility;
    return light;
}

TriangleLight::TriangleLight(const Vec3& a, const Vec3& b, const Vec3& c, const Color& radiance)
    : radiance_(radiance) {
    set_corners(a, b, c);
}

void TriangleLight::set_corners(const Vec3& a, const Vec3& b, const Vec3& c) {
    a_ = a, e1_ = b - a, e2_ = c - a;
    Vec3 n = cross(e1_, e2_);
    float len = length(n);
    area_ = 0.5f * len;
    n_ = len > 0.0f ? n / len : Vec3(0, 0, 1);
    const float edge[3] = {length(e2_ - e1_), length(e2_), length(e1_)};
    for (int k = 0; k < 3; ++k) height_[k] = edge[k] > 0.0f ? len / edge[k] : 0.0f;
}

bool TriangleLight::bounds(LightBounds* out) const {
    const Vec3 centre = a_ + (e1_ + e2_) * (1.0f / 3.0f);
    const float r = std::sqrt(std::max({length_sq(a_ - centre), length_sq(a_ + e1_ - centre), length_sq(a_ + e2_ - centre)}));
    *out = {centre, r, n_, false};  // two-sided, as Cycles' mesh emission
    return true;
}

LightSample TriangleLight::sample(const Vec3& ref, Point2 u) const {
    LightSample s;
    Point2 b = sample_uniform_triangle(u);
    Vec3 p = a_ + e1_ * b.x + e2_ * b.y;
    Vec3 d = p - ref;
    float dist_sq = length_sq(d);
    if (!(dist_sq > 0.0f) || !(area_ > 0.0f)) return s;
    s.dist = std::sqrt(dist_sq);
    s.wi = d / s.dist;
    s.pdf = area_to_solid_angle(1.0f / area_, dist_sq, absdot(s.wi, n_));
    s.edge_distance = std::min({(1.0f - b.x - b.y) * height_[0], b.x * height_[1], b.y * height_[2]});
    if (s.pdf > 0.0f) s.L = radiance_;
    if (kWithTexturedEmission && texture_) {
        float w = 1.0f - b.x - b.y;
        Point2 uv{uv_[0].x * w + uv_[1].x * b.x + uv_[2].x * b.y, uv_[0].y * w + uv_[1].y * b.x + uv_[2].y * b.y};
        s.L *= texture_->lookup(uv).rgb;
    }
    if (shader_ && s.pdf > 0.0f) s.L = radiance_ * shader_->emission(instance_, prim_, material_, b.x, b.y, -s.wi);
    return s;
}

void TriangleLight::set_shader(const SurfaceEmission* shader, uint32_t instance, uint32_t prim, uint32_t material,
                               const Color& centroid_emission) {
    shader_ = shader;
    instance_ = instance, prim_ = prim, material_ = material;
    centroid_emission_ = centroid_emission;
}

void TriangleLight::set_motion(const MovingTriangles* motion, uint32_t instance, uint32_t prim) {
    motion_ = motion;
    instance_ = instance, prim_ = prim;
    moves_ = motion != nullptr;
}

TriangleLight TriangleLight::at_time(float time) const {
    Vec3 v[3];
    motion_->triangle_at(instance_, prim_, time, v);
    TriangleLight moved(*this);
    moved.set_corners(v[0], v[1], v[2]);
    moved.moves_ = false;
    return moved;
}

void TriangleLight::set_texture(const Texture* texture, const Point2* uv) {
    texture_ = texture;
    for (int k = 0; k < 3; ++k) uv_[k] = uv ? uv[k] : Point2{0.0f, 0.0f};
}

float TriangleLight::pdf_at(const Vec3& ref, const Vec3& p) const {
    Vec3 d = p - ref;
    float dist_sq = length_sq(d);
    if (!(dist_sq > 0.0f) || !(area_ > 0.0f)) return 0.0f;
    return area_to_solid_angle(1.0f / area_, dist_sq, absdot(d / std::sqrt(dist_sq), n_));
}

float TriangleLight::pdf(const Vec3& ref, const Vec3& wi) const {
    // Moeller-Trumbore, used by tests and by callers without a BVH hit.
    Vec3 pv = cross(wi, e2_);
    float det = dot(e1_, pv);
    if (std::fabs(det) < 1e-20f) return 0.0f;
    float inv = 1.0f / det;
    Vec3 tv = ref - a_;
    float b1 = dot(tv, pv) * inv;
    if (b1 < 0.0f || b1 > 1.0f) return 0.0f;
    Vec3 qv = cross(tv, e1_);
    float b2 = dot(wi, qv) * inv;
    if (b2 < 0.0f || b1 + b2 > 1.0f) return 0.0f;
    float t = dot(e2_, qv) * inv;
    if (!(t > 0.0f)) return 0.0f;
    return pdf_at(ref, ref + wi * t);
}

float TriangleLight::power(float) const {
    Color L = texture_ ? radiance_ * texture_->mean() : radiance_;
    // A program's emission varies: its value at the centroid, never quite zero (any positive power
    // keeps light selection unbiased, and a dark centroid must not hide a bright rest).
    if (shader_) L = radiance_ * vmax(centroid_emission_, Color(1e-3f));
    return luminance(L) * area_ * kPi * 2.0f;
}

WorldLight::WorldLight(const Color& radiance) : radiance_(radiance) {}

LightSample WorldLight::sample(const Vec3& ref, Point2 u) const {
    LightSample s;
    s.wi = sample_uniform_sphere(u);
    s.dist = kInf;
    s.pdf = uniform_sphere_pdf();
    s.L = radiance_;
    return s;
}

float WorldLight::pdf(const Vec3& ref, const Vec3& wi) const { return uniform_sphere_pdf(); }

bool WorldLight::intersect(const Ray& ray, LightHit* hit) const {
    if (ray.tmax < kInf) return false;
    hit->t = kInf;
    hit->L = radiance_;
    hit->pdf = uniform_sphere_pdf();
    return true;
}

float WorldLight::power(float scene_radius) const { return luminance(radiance_) * kPi * sqr(scene_radius) * 4.0f; }

}  // namespace smis
