// Light sources with Cycles' units. Every light samples a direction from a reference point and
// reports the solid-angle density of that direction through a matching pdf(), so the path tracer
// can combine light sampling with BSDF sampling by MIS (lecture notes on MIS, "AreaLight" interface).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/math.h"
#include "core/sampling.h"
#include "scene/camera.h"
#include "scene/texture.h"
#include "shading/shader_context.h"

namespace smis {

struct LightSample {
    Vec3 wi;          // unit direction from the reference point towards the light
    float dist = 0;   // distance to the sampled point; kInf for lights at infinity
    Color L{0.0f};    // radiance arriving at the reference point along -wi (unoccluded)
    float pdf = 0;    // solid-angle density of wi (for delta lights: 1, and delta = true)
    bool delta = false;
    // Mesh lights: distance from the sampled point to the nearest edge of its triangle (the shadow
    // ray's last stretch is tested near edges, reaches_mesh_light); lamps and the world: kInf.
    float edge_distance = kInf;
    bool valid() const { return pdf > 0.0f && std::isfinite(pdf) && is_finite(L) && !is_black(L); }
};

// A rectangular area light as photon planes see it: corner + u + v spans the rectangle (u, v its
// full edges), emitting one-sided along `normal` with constant radiance.
struct LightRectangle {
    Vec3 corner, u, v, normal;
    Color radiance{0.0f};
    float area() const { return length(cross(u, v)); }
};

// A point or spot light without radius as photon planes see it: a point emitting intensity(dir)
// (W/sr) towards unit direction dir, Cycles 3.4's spot falloff included.
struct LightPoint {
    Vec3 position;
    Color intensity{0.0f};  // along the spot's axis, or in every direction of a point light
    bool spot = false;
    Vec3 axis;              // the spot's direction
    float cos_half = -1.0f; // cosine of half the spot size
    float smooth = 0.0f;    // (1 - cos_half) x spot blend
    // Cycles 3.4 spot_attenuation(): the cosine to the axis inside the cone, times a smoothstep
    // over the blend's band of cosines; 1 for a point light.
    float falloff(const Vec3& dir_from_light) const;
};

// Where a light at a finite distance is, for choosing among lights by their closeness to a ray
// segment in a medium (media_light_choice.h): a sphere around it and, for one-sided emitters, the
// normal of the emitting side (points behind the plane through `centre` receive nothing).
struct LightBounds {
    Vec3 centre;
    float radius = 0.0f;
    Vec3 normal{0.0f, 0.0f, 0.0f};
    bool one_sided = false;
};

// A light struck by a ray (BSDF-sampled or camera).
struct LightHit {
    float t = kInf;
    Color L{0.0f};
    float pdf = 0;  // solid-angle density the light's sample() would have produced for this direction
};

class Light {
public:
    virtual ~Light() = default;
    virtual LightSample sample(const Vec3& ref, Point2 u) const = 0;
    // The sample for a path at shutter time `time`: a moving emitter (TriangleLight::set_motion) is
    // sampled where the path's rays see it then; every other light does not move.
    LightSample sample_at(const Vec3& ref, Point2 u, float time) const {
        return __builtin_expect(moves_, 0) ? sample_moving(ref, u, time) : sample(ref, u);
    }
    // Solid-angle density of sample() producing direction wi from ref (0 if it cannot).
    virtual float pdf(const Vec3& ref, const Vec3& wi) const = 0;
    // Intersection by a ray for lights that are not scene geometry (area, point/spot disks, sun, world).
    // Lights at infinity report t = kInf and are only struck by rays that escape the scene.
    virtual bool intersect(const Ray& ray, LightHit* hit) const { return false; }
    // The same for a ray of a known kind (camera, diffuse, ...: the Light Path node of a World
    // program, see EnvironmentLight); lights that do not depend on it ignore the kind.
    virtual bool intersect_as(const Ray& ray, const ShaderRay& kind, LightHit* hit) const { return intersect(ray, hit); }
    virtual bool at_infinity() const { return false; }
    // The World (uniform or a node tree): what Film Transparent takes out of the camera's view.
    virtual bool is_background() const { return false; }
    virtual bool is_delta() const { return false; }
    // True when sample(ref, u) picks the same light point for every ref (uniform area sampling, a
    // point without radius): single scattering then aims equiangular sampling at that very point.
    virtual bool point_independent_of_reference() const { return false; }
    // Rectangular area lights (Blender's SQUARE/RECTANGLE shapes) describe themselves for photon
    // planes; every other light returns false.
    virtual bool rectangle(LightRectangle* out) const { return false; }
    // Point and spot lights without radius (delta lights) describe themselves for photon planes
    // too; every other light returns false.
    virtual bool point(LightPoint* out) const { return false; }
    // Lights at a finite distance describe their bounds (where they are at the frame for moving
    // ones); lights at infinity return false.
    virtual bool bounds(LightBounds* out) const { return false; }
    // Emitted power (luminance-weighted), used for light selection proportional to power. Lights at
    // infinity deliver power in proportion to the scene's cross-section, hence the radius.
    virtual float power(float scene_radius) const = 0;
    bool visible_to_camera = true;
    // Cycles' per-light toggles. cast_shadow = false: light samples are not tested for occlusion
    // (the light shines through everything). use_mis = false: only light samples find the light,
    // unweighted; rays that meet it (camera rays aside) see nothing.
    bool cast_shadow = true;
    bool use_mis = true;
    // Cycles' Ray Visibility of the light object (or of a mesh light's object): bounce rays of a
    // type it is hidden from do not see it and light samples leave out the lobes of that type
    // (light_hidden_from, lobe_ray_types); kRayVolumeScatter off: it does not light media.
    uint32_t visibility = kRayAllVisibility;

protected:
    virtual LightSample sample_moving(const Vec3& ref, Point2 u, float time) const { return sample(ref, u); }
    bool moves_ = false;
};

// Blender light description, in Blender's units (converted as Cycles converts them).
struct LightDesc {
    std::string type;   // AREA, POINT, SPOT, SUN
    Transform to_world;
    Color color{1.0f};
    float power = 0;     // W (AREA/POINT/SPOT)
    float strength = 0;  // W/m^2 (SUN)
    std::string shape = "SQUARE";
    float size = 1, size_y = 1, radius = 0, spot_size = 0.785398f, spot_blend = 0.15f, angle = 0;
    float spread = kPi;  // AREA: the emission cone's full angle (radians; pi = Lambertian, no cone)
    bool visible_to_camera = true;
    bool cast_shadow = true, use_mis = true;  // Light > Cast Shadow, Multiple Importance (Cycles)
    uint32_t visibility = kRayAllVisibility;  // Object > Visibility > Ray Visibility (Light::visibility)
    // Spectral rendering only: the emitted spectrum (RGB = the colour upsampled, BLACKBODY at
    // `temperature` K, or a CIE illuminant D65, A, F2, F10, F11), see spectral/spectra.h.
    std::string spectrum = "RGB";
    float temperature = 6500.0f;
};

// Throws std::invalid_argument with a clear message for lights that cannot emit (negative power,
// zero size, non-finite values).
std::unique_ptr<Light> make_light(const LightDesc& desc);

// Emissive triangle of a mesh (world space), two-sided like Cycles' mesh emission.
// Emission evaluated at a point of a triangle (a material's shader program), implemented by Scene.
class SurfaceEmission {
public:
    virtual ~SurfaceEmission() = default;
    virtual Color emission(uint32_t instance, uint32_t prim, uint32_t material, float bu, float bv,
                           const Vec3& wo) const = 0;
};

// Where an emissive triangle of a moving or deforming object is at a shutter time (world space),
// implemented by Scene as its rays see the triangle then.
class MovingTriangles {
public:
    virtual ~MovingTriangles() = default;
    virtual void triangle_at(uint32_t instance, uint32_t prim, float time, Vec3 v[3]) const = 0;
};

class TriangleLight : public Light {
public:
    TriangleLight(const Vec3& a, const Vec3& b, const Vec3& c, const Color& radiance);
    // Textured emission: the radiance at a point is radiance x the texture at the point's UV,
    // interpolated from the corners' (uv[3]); selection power uses the texture's mean colour.
    void set_texture(const Texture* texture, const Point2* uv);
    // Emission from a shader program: radiance x shader->emission() at the sampled point; `power`
    // is the selection power to use (the emission at the centroid).
    void set_shader(const SurfaceEmission* shader, uint32_t instance, uint32_t prim, uint32_t material,
                    const Color& centroid_emission);
    LightSample sample(const Vec3& ref, Point2 u) const override;
    float pdf(const Vec3& ref, const Vec3& wi) const override;
    // Motion blur: the triangle moves over the shutter (its constructor's corners: where it is at
    // the frame, for the selection power); sample_at and the timed pdf_at place it at their time.
    void set_motion(const MovingTriangles* motion, uint32_t instance, uint32_t prim);
    // Density of hitting point p (normal n) from ref, already known from a BVH hit.
    float pdf_at(const Vec3& ref, const Vec3& p) const;
    // The same on a path at shutter time `time` (the hit's).
    float pdf_at(const Vec3& ref, const Vec3& p, float time) const {
        return __builtin_expect(moves_, 0) ? at_time(time).pdf_at(ref, p) : pdf_at(ref, p);
    }
    bool point_independent_of_reference() const override { return true; }
    float power(float scene_radius) const override;
    bool bounds(LightBounds* out) const override;
    const Color& radiance() const { return radiance_; }
    float area() const { return area_; }

protected:
    LightSample sample_moving(const Vec3& ref, Point2 u, float time) const override {
        return at_time(time).sample(ref, u);
    }

private:
    void set_corners(const Vec3& a, const Vec3& b, const Vec3& c);
    // This light with its corners where the triangle is at `time` (not moving itself).
    TriangleLight at_time(float time) const;
    Vec3 a_, e1_, e2_, n_;
    float area_;
    // The triangle's heights over the edges opposite a, b and c (2 area / edge length): a point's
    // distance to an edge is its barycentric of the opposite corner times that height.
    float height_[3];
    Color radiance_;
    const Texture* texture_ = nullptr;  // owned by the scene's material
    Point2 uv_[3];
    const SurfaceEmission* shader_ = nullptr;
    uint32_t instance_ = 0, prim_ = 0, material_ = 0;
    Color centroid_emission_{0.0f};
    const MovingTriangles* motion_ = nullptr;
};

// Uniform world background (Blender World "Background" colour x strength): radiance at infinity.
class WorldLight : public Light {
public:
    explicit WorldLight(const Color& radiance);
    LightSample sample(const Vec3& ref, Point2 u) const override;
    float pdf(const Vec3& ref, const Vec3& wi) const override;
    bool intersect(const Ray& ray, LightHit* hit) const override;
    bool at_infinity() const override { return true; }
    bool is_background() const override { return true; }
    float power(float scene_radius) const override;
    const Color& radiance() const { return radiance_; }

private:
    Color radiance_;
};

}  // namespace smis
