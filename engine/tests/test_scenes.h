// Small analytic scenes built directly through the Scene API, shared by the engine tests.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "render/session.h"
#include "stats.h"
#include "scene/scene.h"

namespace smis::testing {

// UV sphere of radius r centred at the origin, outward winding; smooth corner normals when asked.
inline uint32_t add_sphere(Scene& s, float r, int rings, int segments, uint32_t material, bool smooth = true) {
    std::vector<float> v;
    std::vector<int32_t> t;
    std::vector<float> n;
    auto vid = [&](int i, int j) { return i * (segments + 1) + j; };
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            float th = kPi * i / rings, ph = 2 * kPi * j / segments;
            v.insert(v.end(), {r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
        }
    auto normal_of = [&](int id) { return normalize(Vec3(v[3 * id], v[3 * id + 1], v[3 * id + 2])); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            int a = vid(i, j), b = vid(i + 1, j), c = vid(i + 1, j + 1), d = vid(i, j + 1);
            for (auto tri : {std::array<int, 3>{a, b, c}, std::array<int, 3>{a, c, d}}) {
                t.insert(t.end(), tri.begin(), tri.end());
                for (int k : tri) {
                    Vec3 nn = normal_of(k);
                    n.insert(n.end(), {nn.x, nn.y, nn.z});
                }
            }
        }
    // The poles produce zero-area triangles: the scene drops them, as it must.
    uint32_t mesh = s.add_mesh(v.data(), v.size() / 3, t.data(), t.size() / 3, smooth ? n.data() : nullptr, nullptr,
                               {material});
    s.add_instance(mesh, Transform());
    return mesh;
}

inline CameraDesc camera_at(const Vec3& pos, int w, int h) {
    CameraDesc c;
    c.width = w;
    c.height = h;
    c.to_world.m[0][3] = pos.x, c.to_world.m[1][3] = pos.y, c.to_world.m[2][3] = pos.z;
    c.clip_start = 1e-3f;
    return c;
}

inline Material diffuse(const Color& albedo, const Color& emission = Color(0.0f)) {
    Material m;
    Lobe l;
    l.weight = albedo;
    m.lobes.push_back(l);
    m.emission = emission;
    return m;
}

inline std::vector<float> render(const std::shared_ptr<Scene>& scene, RenderSettings settings) {
    RenderSession session(scene, settings);
    session.run();
    return session.pixels();
}

// Mean (with its standard error) of one channel over the pixels of an image (pixels independent).
inline stats::MeanEstimator channel_mean(const std::vector<float>& rgba, int c) {
    stats::MeanEstimator m;
    for (size_t i = 0; i < rgba.size() / 4; ++i) m.add(rgba[4 * i + c]);
    return m;
}

}  // namespace smis::testing

namespace smis::testing {

// Axis-aligned box [lo, hi] as 12 triangles with outward winding (Blender's convention).
inline void add_box(Scene& s, const Vec3& lo, const Vec3& hi, uint32_t material) {
    const float v[] = {lo.x, lo.y, lo.z, hi.x, lo.y, lo.z, hi.x, hi.y, lo.z, lo.x, hi.y, lo.z,
                       lo.x, lo.y, hi.z, hi.x, lo.y, hi.z, hi.x, hi.y, hi.z, lo.x, hi.y, hi.z};
    const int32_t t[] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                         2, 3, 7, 2, 7, 6, 1, 2, 6, 1, 6, 5, 3, 0, 4, 3, 4, 7};
    uint32_t mesh = s.add_mesh(v, 8, t, 12, nullptr, nullptr, {material});
    s.add_instance(mesh, Transform());
}

// A camera at pos looking along +Y: its -Z rotated onto +Y (rotation of +90 degrees about X).
inline CameraDesc camera_along_y(const Vec3& pos, int w, int h, float lens) {
    CameraDesc c = camera_at(pos, w, h);
    c.to_world.m[1][1] = 0.0f, c.to_world.m[1][2] = -1.0f;
    c.to_world.m[2][1] = 1.0f, c.to_world.m[2][2] = 0.0f;
    c.lens = lens;
    return c;
}

inline Material glossy(const Color& color, float roughness) {
    Material m;
    Lobe l;
    l.kind = LobeKind::Microfacet;
    l.weight = color;
    l.alpha = roughness * roughness;
    m.lobes.push_back(l);
    return m;
}

// A small closed room (the camera looks in through the open... closed front wall behind it), a
// diffuse occluder box and a glossy box under a ceiling area light: occlusion, glossy reflection and
// indirect light, everything path-space filtering must get right.
inline std::shared_ptr<Scene> small_room(int w, int h) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    uint32_t red = s->add_material(diffuse(Color(0.7f, 0.15f, 0.1f)));
    uint32_t shiny = s->add_material(glossy(Color(0.8f, 0.7f, 0.5f), 0.3f));
    // Room interior x, y in [-1, 1], z in [0, 2]: walls are thin boxes.
    add_box(*s, {-1.1f, -1.1f, -0.1f}, {1.1f, 1.1f, 0.0f}, white);   // floor
    add_box(*s, {-1.1f, -1.1f, 2.0f}, {1.1f, 1.1f, 2.1f}, white);    // ceiling
    add_box(*s, {-1.1f, 1.0f, 0.0f}, {1.1f, 1.1f, 2.0f}, white);     // back
    add_box(*s, {-1.1f, -1.1f, 0.0f}, {-1.0f, 1.1f, 2.0f}, red);     // left
    add_box(*s, {1.0f, -1.1f, 0.0f}, {1.1f, 1.1f, 2.0f}, white);     // right
    add_box(*s, {-1.1f, -3.1f, 0.0f}, {1.1f, -3.0f, 2.0f}, white);   // front, behind the camera
    add_box(*s, {-0.6f, -0.2f, 0.0f}, {-0.1f, 0.4f, 0.9f}, white);   // occluder
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.7f, 0.0f, 0.5f}, shiny);     // glossy box
    LightDesc light;
    light.type = "AREA";
    light.shape = "SQUARE";
    light.size = 0.6f;
    light.power = 60.0f;
    light.to_world.m[2][3] = 1.98f;  // facing down (-Z), as Blender's default
    s->add_light(light);
    CameraDesc c = camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f);
    s->set_camera(c);
    s->commit();
    return s;
}

}  // namespace smis::testing
