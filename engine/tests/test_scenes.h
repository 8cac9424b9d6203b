// Small analytic scenes built directly through the Scene API, shared by the engine tests.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "render/session.h"
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

// Mean and standard error of one channel over the pixels of an image (pixels independent).
struct MeanErr {
    double mean, stderr_;
};
inline MeanErr channel_mean(const std::vector<float>& rgba, int c) {
    double s = 0, s2 = 0;
    size_t n = rgba.size() / 4;
    for (size_t i = 0; i < n; ++i) {
        s += rgba[4 * i + c];
        s2 += double(rgba[4 * i + c]) * rgba[4 * i + c];
    }
    double m = s / n, var = std::max(0.0, s2 / n - m * m);
    return {m, std::sqrt(var / n)};
}

}  // namespace smis::testing
