// The World as a light: its compiled Surface (a shader program, see shading/shader_program.h)
// evaluated per direction, importance-sampled as Cycles samples its background light. The program
// is evaluated once at load at the centres of a lat-long grid; the luminance x sin(theta) of the
// cells is a piecewise-constant 2D distribution over the (u, v) square (rows by their sums, then a
// cell in the row). sample() and pdf() use that table, but the radiance they return is the program
// evaluated at the exact direction, never the tabulated value: the estimator stays unbiased at any
// map resolution, the table only steers where samples go.
//
// A Nishita sky's sun disc (about 0.5 degrees, holding most of the sky's light) is sampled on its
// own, as Cycles 3.4 does when the World has one such sun reading the plain direction
// (ShaderProgram::sampled_sun): uniformly in its cone with probability 4/5 (Cycles' sun_weight 4
// against the map's 1), the map otherwise. sample() and pdf() use the mixture of both densities
// (one-sample MIS with the balance heuristic over the two strategies), which the integrators combine
// with BSDF sampling by MIS wherever they sample lights.
#pragma once
#include <memory>
#include <vector>

#include "scene/lights.h"
#include "shading/shader_program.h"

namespace smis {

class Scene;

// Cycles 3.4's lat-long convention (kernel/camera/projection.h): u = 0.5 - atan2(y, x) / (2 pi),
// so +x is the image's centre column and +y the column at u = 0.25; v = 1 - acos(z) / pi, so +z is
// the top row (v = 1) and -z the bottom one. The zero vector maps to (0, 0).
Point2 direction_to_equirectangular(const Vec3& d);
Vec3 equirectangular_to_direction(float u, float v);
// Cycles' mirror ball: the photograph of a mirror sphere taken from -y looking along +y. A direction
// is seen at the ball's point whose normal halves it and (0, -1, 0); that normal's x and z (in
// [-1, 1]) become u and v: -y at the centre, +y all around the rim.
Point2 direction_to_mirrorball(const Vec3& d);

// Cycles' automatic importance map resolution (scene/light.cpp, device_update_background): without a
// single Nishita sun, at least 4096 x 2048, or the largest Environment Texture image when bigger.
constexpr int kEnvironmentMapAutoWidth = 4096, kEnvironmentMapAutoHeight = 2048;

class EnvironmentLight : public Light {
public:
    // program: the World's Surface (emission is the radiance); scene: where Texture Coordinate's
    // Camera and Window outputs find the camera (may be null). The map has width x height cells
    // (clamped to [1, 8192] x [1, 4096]); 0 x 0 asks for Cycles' default of 1024 x 512.
    // sample_sun = false leaves a Nishita sun to the map (comparisons only).
    EnvironmentLight(std::shared_ptr<const ShaderProgram> program, const Scene* scene, int width, int height,
                     bool sample_sun = true);

    LightSample sample(const Vec3& ref, Point2 u) const override;
    float pdf(const Vec3& ref, const Vec3& wi) const override { return pdf(wi); }
    float pdf(const Vec3& wi) const;
    // A ray that left the scene (ray.tmax infinite), of the indirect kind Cycles gives light samples
    // (no Light Path flag set), or of the given kind.
    bool intersect(const Ray& ray, LightHit* hit) const override;
    bool intersect_as(const Ray& ray, const ShaderRay& kind, LightHit* hit) const override;
    bool at_infinity() const override { return true; }
    bool is_background() const override { return true; }
    float power(float scene_radius) const override;

    // The World's radiance arriving along -dir (the program at that direction) for a ray of `kind`.
    Color radiance(const Vec3& dir, const ShaderRay& kind) const;
    // What the program reads at a direction (Cycles' shader_setup_from_background).
    ShaderContext context(const Vec3& dir, const ShaderRay& kind) const;
    // The ray kind of light samples and of the map: Cycles evaluates both with PATH_RAY_EMISSION,
    // where every Light Path output is 0.
    static ShaderRay light_sample_kind();
    // Mean radiance over the sphere, from the map (light selection, the spectral emitter's colour).
    const Color& average() const { return average_; }
    int map_width() const { return width_; }
    int map_height() const { return height_; }
    // Probability that sample() draws from the sun's cone (0: no sun sampled on its own).
    float sun_probability() const { return sun_probability_; }

private:
    float cell_pdf(int x, int y) const;  // probability of cell (x, y)
    float map_pdf(const Vec3& wi) const;  // solid-angle density of the map's samples
    float sun_pdf(const Vec3& wi) const;  // ... of the sun cone's samples

    std::shared_ptr<const ShaderProgram> program_;
    const Scene* scene_;
    int width_, height_;
    std::vector<float> row_cdf_;         // per row: width + 1 values from 0 to 1
    std::vector<double> marginal_cdf_;   // height + 1 values from 0 to 1 (rows by their sums)
    Color average_{0.0f};
    bool empty_ = true;                  // nothing to sample: the map is black everywhere
    // The sun's cone: axis, its frame, 1 - cos(half angle), and how often sample() takes it.
    Vec3 sun_dir_{0.0f, 0.0f, 1.0f};
    Frame sun_frame_{Vec3(0.0f, 0.0f, 1.0f)};
    float sun_one_minus_cos_ = 0.0f, sun_probability_ = 0.0f;
};

}  // namespace smis
