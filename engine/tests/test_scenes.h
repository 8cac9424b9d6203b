// Small analytic scenes built directly through the Scene API, shared by the engine tests.
#pragma once
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "render/session.h"
#include "stats.h"
#include "scene/scene.h"

namespace smis::testing {

// UV sphere of radius r centred at `centre`, outward winding; smooth corner normals when asked.
inline uint32_t add_sphere(Scene& s, float r, int rings, int segments, uint32_t material, bool smooth = true,
                           const Vec3& centre = Vec3(0.0f)) {
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
// The material of a medium's boundary ("fog"): index-matched surfaces that a ray passes through into
// `medium` (added to the scene here).
inline uint32_t add_medium_boundary(Scene& s, const Medium& medium) {
    Material boundary;
    boundary.name = "fog";
    boundary.pass_through = true;
    boundary.medium = s.add_medium(medium);
    return s.add_material(boundary);
}

inline std::vector<float> render(const std::shared_ptr<Scene>& scene, RenderSettings settings) {
    RenderSession session(scene, settings);
    session.run();
    return session.pixels();
}

// Determinism: `st` (with its seed) renders the same image on 1 thread and on `threads`, and another
// image with the next seed. `what` names the case in failure messages.
inline void expect_same_image_whatever_the_thread_count(const std::shared_ptr<Scene>& scene, RenderSettings st,
                                                        int threads, const std::string& what) {
    st.threads = 1;
    auto one = render(scene, st);
    st.threads = threads;
    EXPECT_EQ(one, render(scene, st)) << what;
    st.seed += 1;
    EXPECT_NE(one, render(scene, st)) << what;
}

// The integrators of the stress, fuzz and motion suites: every name of the settings table's INTEGRATOR
// enum (so a new integrator is in them without an edit here), plus the path tracer's many-light
// direct-light strategies, named PATH+RIS and PATH+RESTIR_<mis> (unbiased, visibility reuse).
inline const std::vector<std::string>& all_integrators() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> out;
        for (const auto& item : SettingNames<IntegratorKind>::items) out.push_back(item.first);
        for (const char* variant : {"PATH+RIS", "PATH+RESTIR_SEED", "PATH+RESTIR_TALBOT", "PATH+RESTIR_NONE"})
            out.push_back(variant);
        return out;
    }();
    return names;
}
inline void select_integrator(RenderSettings& rs, const std::string& name) {
    rs.integrator = setting_value<IntegratorKind>(name.substr(0, name.find('+')));
    if (name == "PATH+RIS") rs.direct_light = DirectLightStrategy::Ris;
    if (name.rfind("PATH+RESTIR_", 0) == 0) {
        rs.direct_light = DirectLightStrategy::Restir;
        const std::string mis = name.substr(12);
        rs.restir_mis = mis == "TALBOT" ? RestirMis::Talbot : mis == "NONE" ? RestirMis::None : RestirMis::Seed;
    }
}

// Mean (with its standard error) of one channel over the pixels of an image (pixels independent).
inline stats::MeanEstimator channel_mean(const std::vector<float>& rgba, int c) {
    stats::MeanEstimator m;
    for (size_t i = 0; i < rgba.size() / 4; ++i) m.add(rgba[4 * i + c]);
    return m;
}

// Per-pixel statistics over independent renders (different seeds), of the green channel or of all
// three. Estimators that reuse samples across pixels (or across the iterations of one render)
// correlate the pixels of one render, but not renders: per-pixel statistics must come from across
// renders.
struct PixelStats {
    std::vector<double> mean, var;  // per pixel (and channel): mean over renders and the variance of that mean
    stats::MeanEstimator image;     // the image mean of the green channel, one value per render
    stats::MeanEstimator channel_image[3];  // the image mean of each channel, one value per render
};
inline PixelStats across_renders(const std::shared_ptr<Scene>& scene, RenderSettings st, int renders, uint32_t spp,
                                 uint32_t seed0, bool all_channels = false) {
    const size_t n = size_t(scene->camera().window_width()) * scene->camera().window_height();
    const int c0 = all_channels ? 0 : 1, c1 = all_channels ? 3 : 2;
    std::vector<stats::MeanEstimator> est(n * size_t(c1 - c0));
    PixelStats ps;
    st.samples = spp;
    for (int r = 0; r < renders; ++r) {
        st.seed = seed0 + r;
        auto img = render(scene, st);
        for (size_t i = 0; i < n; ++i)
            for (int c = c0; c < c1; ++c) est[i * size_t(c1 - c0) + size_t(c - c0)].add(img[4 * i + c]);
        for (int c = 0; c < 3; ++c) ps.channel_image[c].add(channel_mean(img, c).mean());
        ps.image.add(channel_mean(img, 1).mean());
    }
    for (auto& e : est) {
        ps.mean.push_back(e.mean());
        ps.var.push_back(e.variance() / e.count());
    }
    return ps;
}
// Fraction of pixels (and channels) whose mean agrees with the reference's at the Šidák-corrected 5% level.
inline double accepted_fraction(const PixelStats& a, const PixelStats& ref) {
    const int n = static_cast<int>(a.mean.size());
    const double alpha = stats::sidak_significance(0.05, n);
    int ok = 0;
    for (int i = 0; i < n; ++i)
        ok += stats::z_test(a.mean[i], ref.mean[i], std::sqrt(a.var[i] + ref.var[i]), 1e-6).p_value >= alpha;
    return double(ok) / n;
}
// The image-mean z-test of each channel; `worst` receives the largest |z| (signed).
inline double smallest_channel_p_value(const PixelStats& a, const PixelStats& ref, double* worst = nullptr) {
    double p = 1.0, z = 0.0;
    for (int c = 0; c < 3; ++c) {
        stats::ZTest t = stats::z_test_difference(a.channel_image[c], ref.channel_image[c]);
        if (t.p_value < p) p = t.p_value, z = t.z;
    }
    if (worst) *worst = z;
    return p;
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

// Smooth glass of index eta (one Dielectric lobe).
inline Material smooth_glass(float eta) {
    Material m;
    Lobe g;
    g.kind = LobeKind::Dielectric;
    g.alpha = 0.0f;
    g.eta = eta;
    m.lobes.push_back(g);
    return m;
}

// The test scenes' lights, each built in one expression, e.g.
//   s->add_light(point_light(5.0f, 0.05f, {0.5f, 0.4f, 0.6f}).spectrum("D65").hidden_from_camera());
struct TestLight {
    LightDesc desc;
    TestLight& spectrum(const char* name) {
        desc.spectrum = name;
        return *this;
    }
    // Hidden from camera rays: a light's randomly covered edge pixels would dominate a test's noise.
    TestLight& hidden_from_camera() {
        desc.visible_to_camera = false;
        return *this;
    }
    operator const LightDesc&() const { return desc; }
};
inline TestLight light_at(const char* type, float power, const Vec3& at) {
    TestLight light;
    light.desc.type = type;
    light.desc.power = power;
    light.desc.to_world.m[0][3] = at.x, light.desc.to_world.m[1][3] = at.y, light.desc.to_world.m[2][3] = at.z;
    return light;
}
// A square area light of side `size`, centred at `at`, facing down (-Z, as Blender's default).
inline TestLight area_light(float size, float power, const Vec3& at) {
    TestLight light = light_at("AREA", power, at);
    light.desc.shape = "SQUARE";
    light.desc.size = size;
    return light;
}
// A point light (a sphere of `radius`) at `at`.
inline TestLight point_light(float power, float radius, const Vec3& at) {
    TestLight light = light_at("POINT", power, at);
    light.desc.radius = radius;
    return light;
}
inline void add_square_light(Scene& s, float size, float power, const Vec3& at) { s.add_light(area_light(size, power, at)); }

// A closed room, interior x, y in [-1, 1], z in [0, 2], of thin boxes: `floor`, the `left` wall, and
// `walls` for the rest (the front one behind a camera at y = -2.9).
inline void add_room(Scene& s, uint32_t floor, uint32_t walls, uint32_t left) {
    add_box(s, {-1.1f, -1.1f, -0.1f}, {1.1f, 1.1f, 0.0f}, floor);    // floor
    add_box(s, {-1.1f, -1.1f, 2.0f}, {1.1f, 1.1f, 2.1f}, walls);     // ceiling
    add_box(s, {-1.1f, 1.0f, 0.0f}, {1.1f, 1.1f, 2.0f}, walls);      // back
    add_box(s, {-1.1f, -1.1f, 0.0f}, {-1.0f, 1.1f, 2.0f}, left);     // left
    add_box(s, {1.0f, -1.1f, 0.0f}, {1.1f, 1.1f, 2.0f}, walls);      // right
    add_box(s, {-1.1f, -3.1f, 0.0f}, {1.1f, -3.0f, 2.0f}, walls);    // front, behind the camera
}

// A small closed room (the camera looks in through the open... closed front wall behind it), a
// diffuse occluder box and a glossy box under a ceiling area light: occlusion, glossy reflection and
// indirect light, everything path-space filtering must get right.
inline std::shared_ptr<Scene> small_room(int w, int h) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    uint32_t red = s->add_material(diffuse(Color(0.7f, 0.15f, 0.1f)));
    uint32_t shiny = s->add_material(glossy(Color(0.8f, 0.7f, 0.5f), 0.3f));
    add_room(*s, white, white, red);
    add_box(*s, {-0.6f, -0.2f, 0.0f}, {-0.1f, 0.4f, 0.9f}, white);   // occluder
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.7f, 0.0f, 0.5f}, shiny);     // glossy box
    add_square_light(*s, 0.6f, 60.0f, {0.0f, 0.0f, 1.98f});
    CameraDesc c = camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f);
    s->set_camera(c);
    s->commit();
    return s;
}

}  // namespace smis::testing

namespace smis::testing {

// Many small emitters over a floor with occluders, seen from above: a grid of small area lights
// (one-sided, facing down) and a grid of emissive quads (two-sided mesh emission), of varied colours
// and powers, above boxes and bars that cast many shadows; a glossy strip so that light sampling is
// MIS-combined with BSDF sampling. The many-light direct-illumination case of ReSTIR.
inline std::shared_ptr<Scene> many_lights(int w, int h, int grid = 10) {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.7f)));
    uint32_t shiny = s->add_material(glossy(Color(0.8f, 0.8f, 0.8f), 0.25f));
    add_box(*s, {-3.0f, -3.0f, -0.1f}, {3.0f, 3.0f, 0.0f}, white);       // floor
    add_box(*s, {-3.0f, 0.8f, 0.0f}, {3.0f, 1.3f, 0.002f}, shiny);       // glossy strip on it
    add_box(*s, {-1.2f, -1.0f, 0.0f}, {-0.6f, -0.4f, 0.6f}, white);      // occluder boxes
    add_box(*s, {0.4f, -0.3f, 0.0f}, {1.1f, 0.2f, 0.4f}, white);
    for (int b = 0; b < 4; ++b) {                                        // bars casting thin shadows
        float y = -1.5f + 0.9f * b;
        add_box(*s, {-2.0f, y, 0.9f}, {2.0f, y + 0.12f, 0.98f}, white);
    }
    auto colour = [](int i) {
        return Color(0.4f + 0.6f * ((i * 37) % 11) / 10.0f, 0.4f + 0.6f * ((i * 53) % 7) / 6.0f,
                     0.4f + 0.6f * ((i * 29) % 5) / 4.0f);
    };
    const float extent = 2.2f;
    for (int i = 0; i < grid * grid; ++i) {
        float fx = -extent + 2.0f * extent * (i % grid + 0.5f) / grid, fy = -extent + 2.0f * extent * (i / grid + 0.5f) / grid;
        LightDesc light;
        light.type = "AREA";
        light.shape = "SQUARE";
        light.size = 0.06f;
        light.color = colour(i);
        light.power = 0.5f + 2.5f * float((i * 7919) % 13) / 12.0f;
        light.to_world.m[0][3] = fx, light.to_world.m[1][3] = fy, light.to_world.m[2][3] = 1.6f + 0.2f * float(i % 3);
        s->add_light(light);
        // An emissive quad halfway between each pair of lights, lower (between the bars and the floor).
        uint32_t emitter = s->add_material(diffuse(Color(0.0f), colour(i + 5) * (2.0f + float(i % 4))));
        float ex = fx + extent / grid, ey = fy + extent / grid, r = 0.04f;
        if (ex > extent || ey > extent) continue;
        add_box(*s, {ex - r, ey - r, 0.7f}, {ex + r, ey + r, 0.7f + 0.02f}, emitter);
    }
    s->set_world(Color(0.3f, 0.35f, 0.4f));
    s->set_camera(camera_at({0.0f, 0.0f, 6.0f}, w, h));
    s->commit();
    return s;
}

inline Medium medium_of(const Color& sigma_a, const Color& sigma_s, float g) {
    Medium m;
    m.sigma_a = sigma_a;
    m.sigma_s = sigma_s;
    m.phase = HenyeyGreenstein(g);
    return m;
}

// Fog (an index-matched box) around a white floor, a mirror and a glass block that holds a medium of
// its own, lit by a rectangle above and a point light inside the fog; the camera looks in from outside.
// `spectral_light`: the point light has a D65 spectrum (spectral content). w x h pixels.
inline std::shared_ptr<Scene> foggy_mirror_and_glass(const Medium& fog, const Medium& inside_glass,
                                                     bool spectral_light = false, int w = 16, int h = 16) {
    auto s = std::make_shared<Scene>();
    add_box(*s, {-1.5f, -1.5f, -0.2f}, {1.5f, 1.5f, 2.5f}, add_medium_boundary(*s, fog));
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_box(*s, {-1.1f, 0.8f, 0.0f}, {0.1f, 0.9f, 1.3f}, s->add_material(glossy(Color(0.9f), 0.0f)));
    Material glass = smooth_glass(1.5f);
    glass.medium = s->add_medium(inside_glass);
    add_box(*s, {0.2f, -0.5f, 0.0f}, {0.8f, 0.1f, 0.7f}, s->add_material(glass));
    s->add_light(area_light(1.5f, 60.0f, {0.0f, 0.0f, 2.2f}).hidden_from_camera());
    s->add_light(point_light(15.0f, 0.15f, {-0.7f, -0.6f, 0.9f}).spectrum(spectral_light ? "D65" : "RGB"));
    s->set_camera(camera_along_y({0.0f, -3.2f, 0.6f}, w, h, 30.0f));
    s->commit();
    return s;
}

}  // namespace smis::testing
