// Numerical stability stress cases ("Proof of fast and accurate"): small pathological scenes rendered
// with every integrator and both MIS heuristics. Each case must not crash, must leave every pixel
// finite, and - where the scene is well posed - must not even produce a non-finite sample that the
// film guard has to catch. The counters are printed per case so CI logs show them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>

#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

const MisHeuristic kHeuristics[] = {MisHeuristic::Balance, MisHeuristic::Power};
constexpr int kRes = 16;
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kPosInf = std::numeric_limits<float>::infinity();

Transform translation(float x, float y, float z) {
    Transform t;
    t.m[0][3] = x, t.m[1][3] = y, t.m[2][3] = z;
    return t;
}

// Camera at `pos` looking along +Y (rotation of +90 degrees about X), like small_room().
CameraDesc camera_looking_y(const Vec3& pos, int w, int h) {
    CameraDesc c = camera_at(pos, w, h);
    c.to_world.m[1][1] = 0.0f, c.to_world.m[1][2] = -1.0f;
    c.to_world.m[2][1] = 1.0f, c.to_world.m[2][2] = 0.0f;
    return c;
}

// Square quad [-h, h]^2 at height z, facing +Z.
uint32_t add_quad(Scene& s, float h, float z, uint32_t material, const Transform& xf = Transform()) {
    const float v[] = {-h, -h, z, h, -h, z, h, h, z, -h, h, z};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    uint32_t mesh = s.add_mesh(v, 4, t, 2, nullptr, nullptr, {material});
    s.add_instance(mesh, xf);
    return mesh;
}

LightDesc area_light(float size, float power, float z) {
    LightDesc l;
    l.type = "AREA";
    l.size = size;
    l.power = power;
    l.to_world.m[2][3] = z;  // faces -Z
    return l;
}

LightDesc point_light(const Vec3& p, float power, float radius) {
    LightDesc l;
    l.type = "POINT";
    l.power = power;
    l.radius = radius;
    l.to_world = translation(p.x, p.y, p.z);
    return l;
}

// A floor (z = 0, [-2, 2]^2) with a diffuse and a glossy box, seen from above at a slant: the
// backdrop most cases put their pathology into.
void add_backdrop(Scene& s) {
    uint32_t white = s.add_material(diffuse(Color(0.7f)));
    uint32_t shiny = s.add_material(glossy(Color(0.8f), 0.4f));
    add_quad(s, 2.0f, 0.0f, white);
    add_box(s, {-0.8f, -0.3f, 0.0f}, {-0.2f, 0.3f, 0.6f}, shiny);
}

CameraDesc backdrop_camera() {
    CameraDesc c = camera_looking_y({0.0f, -3.0f, 1.5f}, kRes, kRes);
    // Tilt down by ~27 degrees: rotate about X by (90 - 27) instead of 90.
    float a = 63.0f * kPi / 180.0f;
    c.to_world.m[1][1] = std::cos(a), c.to_world.m[1][2] = -std::sin(a);
    c.to_world.m[2][1] = std::sin(a), c.to_world.m[2][2] = std::cos(a);
    c.lens = 25.0f;
    return c;
}

struct CaseResult {
    uint64_t nan_caught = 0, samples_rejected = 0;
    bool all_finite = true;
};

// Renders the committed scene with every integrator x heuristic (or, with `spectral`, every integrator
// in that spectral mode with the balance heuristic); prints and checks the counters.
CaseResult run_case(const char* name, const std::shared_ptr<Scene>& scene, bool expect_no_nan,
                    const char* spectral = nullptr) {
    CaseResult total;
    for (const std::string& integ : all_integrators())
        for (MisHeuristic mis : kHeuristics) {
            if (spectral && mis != MisHeuristic::Balance) continue;
            RenderSettings rs;
            if (spectral) rs.spectral = setting_value<SpectralSetting>(spectral);
            rs.samples = 4;
            rs.max_bounces = 4;
            select_integrator(rs, integ);
            rs.mis = mis;
            rs.threads = 2;
            RenderSession session(scene, rs);
            session.run();
            EXPECT_TRUE(session.error().empty()) << name << " " << integ << ": " << session.error();
            std::vector<float> px = session.pixels();
            EXPECT_EQ(px.size(), size_t(4) * session.width() * session.height());
            size_t bad = 0;
            double sum = 0.0;
            for (size_t i = 0; i < px.size(); ++i) {
                if (!std::isfinite(px[i])) ++bad;
                else if (i % 4 != 3) sum += px[i];
            }
            double mean = px.empty() ? 0.0 : sum / (0.75 * double(px.size()));
            RenderProgress p = session.progress();
            std::printf("[stress] %-28s %-18s %-7s %-16s nan_caught=%llu samples_rejected=%llu nonfinite_px=%zu mean=%.3g\n", name,
                        integ.c_str(), mis == MisHeuristic::Power ? "power" : "balance", spectral ? spectral : "",
                        static_cast<unsigned long long>(p.nan_caught),
                        static_cast<unsigned long long>(p.samples_rejected), bad, mean);
            EXPECT_EQ(bad, 0u) << name << " " << integ << ": non-finite pixels";
            if (expect_no_nan) {
                EXPECT_EQ(p.nan_caught, 0u) << name << " " << integ << ": NaN samples caught";
            }
            total.nan_caught += p.nan_caught;
            total.samples_rejected += p.samples_rejected;
            total.all_finite = total.all_finite && bad == 0;
        }
    std::fflush(stdout);
    return total;
}

using Builder = std::function<void(Scene&)>;

CaseResult build_and_run(const char* name, const Builder& build, bool expect_no_nan = true,
                         const char* spectral = nullptr) {
    auto s = std::make_shared<Scene>();
    build(*s);
    if (!s->has_camera()) s->set_camera(backdrop_camera());
    s->commit();
    return run_case(name, s, expect_no_nan, spectral);
}

Material glass(float eta, float alpha) {
    Material m;
    Lobe l;
    l.kind = LobeKind::Dielectric;
    l.weight = Color(1.0f);
    l.eta = eta;
    l.alpha = alpha;
    m.lobes.push_back(l);
    return m;
}

}  // namespace

// ---------------------------------------------------------------------------------------------------
// Geometry

TEST(Stress, NeedleAndDegenerateTriangles) {
    build_and_run("needle_triangles", [](Scene& s) {
        add_backdrop(s);
        uint32_t m = s.add_material(diffuse(Color(0.9f)));
        std::vector<float> v;
        std::vector<int32_t> t;
        // Needles 1e-7 wide and 2 long, fanned across the view; plus exactly degenerate triangles
        // (repeated vertex, collinear) that the scene must drop.
        for (int i = 0; i < 20; ++i) {
            float x = -1.0f + 0.1f * i, w = 1e-7f;
            int b = int(v.size() / 3);
            v.insert(v.end(), {x, -1.0f, 0.3f, x + w, 1.0f, 0.3f + 0.01f * i, x, 1.0f, 0.3f + w});
            t.insert(t.end(), {b, b + 1, b + 2});
        }
        int b = int(v.size() / 3);
        v.insert(v.end(), {0, 0, 0.5f, 1, 1, 0.5f, 2, 2, 0.5f});  // collinear
        t.insert(t.end(), {b, b + 1, b + 2, b, b, b + 1});       // collinear, repeated vertex
        uint32_t mesh = s.add_mesh(v.data(), v.size() / 3, t.data(), t.size() / 3, nullptr, nullptr, {m});
        EXPECT_GE(s.mesh_dropped(mesh), 2u);
        s.add_instance(mesh, Transform());
        // Emissive needles: triangle lights with (nearly) zero area.
        uint32_t glow = s.add_material(diffuse(Color(0.5f), Color(50.0f)));
        const float nv[] = {0.5f, -0.5f, 0.2f, 0.5f + 1e-7f, 0.5f, 0.2f, 0.5f, 0.5f, 0.2f + 1e-7f};
        const int32_t nt[] = {0, 1, 2};
        uint32_t needle = s.add_mesh(nv, 3, nt, 1, nullptr, nullptr, {glow});
        s.add_instance(needle, Transform());
        s.add_light(area_light(0.5f, 50.0f, 2.5f));
    });
}

TEST(Stress, CoincidentCoplanarFaces) {
    build_and_run("coincident_quads", [](Scene& s) {
        uint32_t a = s.add_material(diffuse(Color(0.8f, 0.2f, 0.2f)));
        uint32_t b = s.add_material(glossy(Color(0.2f, 0.8f, 0.2f), 0.2f));
        add_quad(s, 2.0f, 0.0f, a);
        add_quad(s, 2.0f, 0.0f, b);  // identical quad, different material
        // And a mesh instanced twice at the same place (Embree instancing path).
        const float v[] = {-0.5f, -0.5f, 0.3f, 0.5f, -0.5f, 0.3f, 0.5f, 0.5f, 0.3f, -0.5f, 0.5f, 0.3f};
        const int32_t t[] = {0, 1, 2, 0, 2, 3, 0, 1, 2};  // the first triangle duplicated inside the mesh
        uint32_t mesh = s.add_mesh(v, 4, t, 3, nullptr, nullptr, {a});
        s.add_instance(mesh, Transform());
        s.add_instance(mesh, Transform());
        s.add_light(area_light(1.0f, 100.0f, 2.0f));
    });
}

TEST(Stress, TinyAndHugeScale) {
    for (float scale : {1e-4f, 1e4f}) {
        auto build = [scale](Scene& s) {
            uint32_t white = s.add_material(diffuse(Color(0.7f)));
            uint32_t shiny = s.add_material(glossy(Color(0.8f), 0.3f));
            add_quad(s, 2.0f * scale, 0.0f, white);
            add_box(s, Vec3(-0.5f, -0.5f, 0.0f) * scale, Vec3(0.5f, 0.5f, 1.0f) * scale, shiny);
            add_sphere(s, 0.4f * scale, 8, 12, white);
            LightDesc l = area_light(1.0f * scale, 100.0f * scale * scale, 3.0f * scale);
            l.to_world.m[0][0] = l.to_world.m[1][1] = l.to_world.m[2][2] = 1.0f;
            s.add_light(l);
            s.add_light(point_light(Vec3(1.0f, -1.0f, 2.0f) * scale, 50.0f * scale * scale, 0.05f * scale));
            CameraDesc c = backdrop_camera();
            c.to_world.m[0][3] *= scale, c.to_world.m[1][3] *= scale, c.to_world.m[2][3] *= scale;
            c.clip_start = 1e-3f * scale;
            c.clip_end = 1e3f * scale;
            s.set_camera(c);
        };
        build_and_run(scale < 1.0f ? "scale_1e-4" : "scale_1e4", build);
    }
}

TEST(Stress, CameraInsideClosedBox) {
    build_and_run("camera_inside_box", [](Scene& s) {
        uint32_t white = s.add_material(diffuse(Color(0.7f)));
        add_box(s, {-1, -1, -1}, {1, 1, 1}, white);
        s.add_light(point_light({0.3f, 0.3f, 0.5f}, 100.0f, 0.05f));
        s.add_light(area_light(0.4f, 50.0f, 0.9f));
        s.set_world(Color(1.0f));  // outside: must never leak in
        s.set_camera(camera_looking_y({0, 0, 0}, kRes, kRes));
    });
    // Camera inside a solid glass box (every camera ray starts inside a medium).
    build_and_run("camera_inside_glass", [](Scene& s) {
        add_backdrop(s);
        uint32_t g = s.add_material(glass(1.5f, 0.0f));
        add_box(s, {-1, -4, 0.5f}, {1, -2, 2.5f}, g);
        s.add_light(area_light(1.0f, 100.0f, 3.0f));
    });
}

TEST(Stress, GrazingRays) {
    build_and_run("grazing_plane", [](Scene& s) {
        uint32_t white = s.add_material(diffuse(Color(0.7f)));
        uint32_t shiny = s.add_material(glossy(Color(0.9f), 0.05f));
        add_quad(s, 5.0f, 0.0f, white);
        add_quad(s, 5.0f, 0.0f, shiny, translation(0, 12.0f, 0));  // a second, glossy plane further on
        s.add_light(area_light(1.0f, 100.0f, 2.0f));
        s.set_world(Color(0.2f));
        // Eye exactly in the plane z = 0, looking along it: half the rays graze the floor.
        s.set_camera(camera_looking_y({0.0f, -4.0f, 0.0f}, kRes, kRes));
    });
}

// ---------------------------------------------------------------------------------------------------
// Materials

TEST(Stress, GgxRoughnessExtremes) {
    for (float alpha : {0.0f, 0.998f}) {
        for (FresnelMode fm : {FresnelMode::None, FresnelMode::Schlick, FresnelMode::Dielectric}) {
            char name[64];
            std::snprintf(name, sizeof name, "ggx_alpha_%g_fresnel%d", alpha, int(fm));
            build_and_run(name, [alpha, fm](Scene& s) {
                Material m;
                Lobe d;
                d.weight = Color(0.3f);
                Lobe g;
                g.kind = LobeKind::Microfacet;
                g.fresnel = fm;
                g.weight = Color(0.9f);
                g.f0 = Color(0.9f, 0.6f, 0.3f);
                g.alpha = alpha;
                m.lobes.push_back(d);
                m.lobes.push_back(g);
                uint32_t id = s.add_material(m);
                add_backdrop(s);
                add_sphere(s, 0.5f, 12, 16, id);
                add_quad(s, 2.0f, 0.0f, s.add_material(glossy(Color(0.9f), 0.0f)), translation(0, 0, -0.01f));
                s.add_light(area_light(0.5f, 100.0f, 2.0f));
                s.add_light(point_light({1, -1, 1.5f}, 50.0f, 0.0f));
            });
        }
    }
}

TEST(Stress, DielectricIorExtremes) {
    for (float eta : {1.0f, 4.0f})
        for (float alpha : {0.0f, 0.25f}) {
            char name[64];
            std::snprintf(name, sizeof name, "glass_ior_%g_alpha_%g", eta, alpha);
            build_and_run(name, [eta, alpha](Scene& s) {
                add_backdrop(s);
                uint32_t g = s.add_material(glass(eta, alpha));
                add_sphere(s, 0.6f, 12, 16, g);
                add_box(s, {0.3f, -0.5f, 0.0f}, {0.9f, 0.1f, 0.5f}, g);
                // Principled-like specular layer with the same IOR on a diffuse base.
                Material coat;
                Lobe base;
                base.weight = Color(0.5f);
                Lobe spec;
                spec.kind = LobeKind::Microfacet;
                spec.fresnel = FresnelMode::Dielectric;
                spec.eta = eta;
                spec.alpha = alpha;
                coat.lobes.push_back(base);
                coat.lobes.push_back(spec);
                add_box(s, {-1.5f, 0.5f, 0.0f}, {-1.0f, 1.0f, 0.5f}, s.add_material(coat));
                s.add_light(area_light(0.5f, 100.0f, 2.0f));
                s.add_light(point_light({1, -1, 1.5f}, 50.0f, 0.01f));
                s.set_world(Color(0.1f));
            });
        }
}

// Boxes whose materials carry the given parameter value in every slot (weight, f0, alpha, eta, and
// emission on every fourth).
void add_bad_material_boxes(Scene& s, const std::vector<float>& values) {
    int i = 0;
    for (float x : values)
        for (LobeKind kind : {LobeKind::Diffuse, LobeKind::Microfacet, LobeKind::Dielectric}) {
            Material m;
            Lobe l;
            l.kind = kind;
            l.fresnel = FresnelMode(i % 3);
            l.weight = Color(x, 0.5f, x);
            l.f0 = Color(x);
            l.alpha = x;
            l.eta = x;
            m.lobes.push_back(l);
            m.lobes.push_back(l);
            m.emission = Color(i % 4 == 0 ? x : 0.0f);
            uint32_t id = s.add_material(m);
            float cx = -1.5f + 0.35f * (i % 9), cy = -1.0f + 0.7f * (i / 9);
            add_box(s, {cx, cy, 0.0f}, {cx + 0.3f, cy + 0.3f, 0.3f}, id);
            ++i;
        }
}

TEST(Stress, NonFiniteMaterialParametersAreClamped) {
    // NaN / Inf / negative / denormal parameters: clamped by add_material, so not a single NaN sample.
    build_and_run("nonfinite_materials", [](Scene& s) {
        add_backdrop(s);
        add_bad_material_boxes(s, {kNaN, kPosInf, -kPosInf, -1.0f, 1e-40f});
        s.add_light(area_light(1.0f, 100.0f, 2.0f));
    });
}

TEST(Stress, HugeFiniteMaterialWeights) {
    // Weight 1e30 is finite, so it is not clamped; the throughput of a path bouncing twice off it
    // overflows to Inf (and Inf * 0 to NaN). The film guard must catch those samples: the image stays
    // finite, nan_caught reports them.
    CaseResult r = build_and_run("huge_material_weights", [](Scene& s) {
        add_backdrop(s);
        add_bad_material_boxes(s, {1e30f});
        s.add_light(area_light(1.0f, 100.0f, 2.0f));
    }, /*expect_no_nan=*/false);
    EXPECT_TRUE(r.all_finite);
}

// ---------------------------------------------------------------------------------------------------
// Lights

TEST(Stress, TinyVeryBrightLights) {
    build_and_run("tiny_bright_area_light", [](Scene& s) {
        add_backdrop(s);
        s.add_light(area_light(1e-4f, 1e6f, 1.0f));
    });
    build_and_run("tiny_point_light_radius", [](Scene& s) {
        add_backdrop(s);
        s.add_light(point_light({0.3f, 0.2f, 0.8f}, 1e6f, 1e-6f));
        s.add_light(point_light({-0.5f, 0.0f, 0.61f}, 1e6f, 1e-6f));  // 1 cm above the glossy box
    });
}

TEST(Stress, LightsTouchingSurfaces) {
    build_and_run("area_light_coplanar_floor", [](Scene& s) {
        add_backdrop(s);
        LightDesc down = area_light(1.0f, 100.0f, 0.0f);  // facing -Z, exactly in the floor plane
        s.add_light(down);
        LightDesc up = area_light(0.8f, 100.0f, 0.0f);  // flipped to face +Z, also in the floor plane
        up.to_world.m[1][1] = -1.0f, up.to_world.m[2][2] = -1.0f;
        up.to_world.m[0][3] = 1.0f;
        s.add_light(up);
        LightDesc onbox = area_light(0.6f, 100.0f, 0.6f);  // flush with the top of the glossy box
        onbox.to_world.m[0][3] = -0.5f;
        s.add_light(onbox);
    });
    build_and_run("point_light_on_surface", [](Scene& s) {
        add_backdrop(s);
        s.add_light(point_light({0.5f, 0.5f, 0.0f}, 100.0f, 0.0f));     // delta point on the floor
        s.add_light(point_light({-0.5f, 0.0f, 0.6f}, 100.0f, 0.0f));    // on the box top
        s.add_light(point_light({1.0f, -0.5f, 0.0f}, 100.0f, 0.1f));    // sphere light cut by the floor
        LightDesc spot = point_light({-0.8f, 0.0f, 0.3f}, 100.0f, 0.0f);  // on the box side
        spot.type = "SPOT";
        s.add_light(spot);
    });
}

TEST(Stress, ZeroAreaLightIsRejected) {
    Scene s;
    LightDesc l = area_light(0.0f, 100.0f, 1.0f);
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l.size = 1e-7f;  // area 1e-14 < 1e-12
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l = area_light(1.0f, 100.0f, 1.0f);
    l.shape = "RECTANGLE";
    l.size_y = 0.0f;
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l = area_light(1.0f, 100.0f, 1.0f);
    l.to_world.m[0][0] = 0.0f;  // zero scale collapses the light
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l = area_light(kNaN, 100.0f, 1.0f);
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l = area_light(1.0f, -1.0f, 1.0f);
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    l = area_light(1.0f, kNaN, 1.0f);
    EXPECT_THROW(s.add_light(l), std::invalid_argument);
    LightDesc p = point_light({0, 0, 1}, 1.0f, -1.0f);
    EXPECT_THROW(s.add_light(p), std::invalid_argument);
    LightDesc spot = point_light({0, 0, 1}, 1.0f, 0.0f);
    spot.type = "SPOT";
    spot.to_world.m[2][2] = 0.0f;  // no direction
    EXPECT_THROW(s.add_light(spot), std::invalid_argument);
    LightDesc sun;
    sun.type = "SUN";
    sun.strength = 1.0f;
    sun.angle = -0.1f;
    EXPECT_THROW(s.add_light(sun), std::invalid_argument);
    sun.angle = 0.0f;
    sun.to_world.m[2][2] = 0.0f;
    EXPECT_THROW(s.add_light(sun), std::invalid_argument);
    LightDesc unknown;
    unknown.type = "MESH";
    EXPECT_THROW(s.add_light(unknown), std::invalid_argument);
}

TEST(Stress, SpotSizeZeroBlendOne) {
    build_and_run("spot_size0_blend1", [](Scene& s) {
        add_backdrop(s);
        for (float radius : {0.0f, 0.1f}) {
            LightDesc l = point_light({radius > 0 ? 0.5f : -0.5f, 0.0f, 1.5f}, 1000.0f, radius);
            l.type = "SPOT";
            l.spot_size = 0.0f;
            l.spot_blend = 1.0f;
            s.add_light(l);
        }
        LightDesc wide = point_light({0.0f, 0.5f, 1.5f}, 100.0f, 0.0f);
        wide.type = "SPOT";
        wide.spot_size = kPi;  // 180-degree cone, blend 1
        wide.spot_blend = 1.0f;
        s.add_light(wide);
        s.add_light(area_light(0.3f, 10.0f, 2.0f));
    });
}

TEST(Stress, SunAngleExtremes) {
    for (float angle : {0.0f, kPi, 2.0f * kPi}) {
        char name[64];
        std::snprintf(name, sizeof name, "sun_angle_%g", angle);
        build_and_run(name, [angle](Scene& s) {
            add_backdrop(s);
            LightDesc sun;
            sun.type = "SUN";
            sun.strength = 5.0f;
            sun.angle = angle;
            // Tilted 30 degrees about X.
            float a = 30.0f * kPi / 180.0f;
            sun.to_world.m[1][1] = std::cos(a), sun.to_world.m[1][2] = -std::sin(a);
            sun.to_world.m[2][1] = std::sin(a), sun.to_world.m[2][2] = std::cos(a);
            s.add_light(sun);
        });
    }
}

TEST(Stress, WorldWithHugeRadiance) {
    // Radiance 1e30 is finite but its power (x pi r^2) and products along a path are not far from
    // float overflow (3.4e38); with albedos below 1 no product overflows, so no NaN sample either.
    build_and_run("world_1e30", [](Scene& s) {
        add_backdrop(s);
        s.set_world(Color(1e30f));
    });
    build_and_run("world_1e30_with_lights", [](Scene& s) {
        add_backdrop(s);
        s.add_light(area_light(0.5f, 100.0f, 2.0f));
        s.add_light(point_light({1, -1, 1}, 100.0f, 0.0f));
        s.set_world(Color(1e30f, 0.0f, 1e30f));
    });
    build_and_run("world_inf_is_dropped", [](Scene& s) {
        add_backdrop(s);
        s.add_light(area_light(0.5f, 100.0f, 2.0f));
        s.set_world(Color(kPosInf, kNaN, 1.0f));
    });
}

// ---------------------------------------------------------------------------------------------------
// Media: every integrator (path-space filtering and RIS/ReSTIR included) on fog

namespace {

// A fog box with an index-matched boundary around the backdrop's box, of the given medium.
void add_fog_box(Scene& s, const Vec3& lo, const Vec3& hi, const Color& sigma_a, const Color& sigma_s, float g) {
    Medium fog;
    fog.sigma_a = sigma_a;
    fog.sigma_s = sigma_s;
    fog.phase = HenyeyGreenstein(g);
    Material boundary;
    boundary.pass_through = true;
    boundary.medium = s.add_medium(fog);
    add_box(s, lo, hi, s.add_material(boundary));
}

}  // namespace

TEST(Stress, FogWithEveryIntegrator) {
    // Fog boxes of everyday and extreme densities (optical depths up to ~3000 across, where the
    // transmittance underflows to 0), a clear channel, a forward-peaked phase function, a mirror and
    // glass in the fog, lights inside and outside it, and a world volume around everything.
    build_and_run("fog_everyday", [](Scene& s) {
        add_backdrop(s);
        uint32_t g = s.add_material(glass(1.5f, 0.0f));
        uint32_t mirror = s.add_material(glossy(Color(0.9f), 0.0f));
        add_box(s, {0.2f, -0.5f, 0.0f}, {0.6f, -0.1f, 0.4f}, g);
        add_box(s, {1.0f, -1.0f, 0.0f}, {1.05f, 1.0f, 1.0f}, mirror);
        add_fog_box(s, {-1.5f, -1.5f, 0.01f}, {1.5f, 1.5f, 1.2f}, Color(0.05f, 0.1f, 0.0f), Color(0.5f, 0.4f, 0.0f), 0.5f);
        s.add_light(area_light(0.6f, 80.0f, 2.0f));
        s.add_light(point_light({-0.5f, 0.5f, 0.7f}, 20.0f, 0.05f));
    });
    build_and_run("fog_dense", [](Scene& s) {
        add_backdrop(s);
        add_fog_box(s, {-1.0f, -1.0f, 0.01f}, {1.0f, 1.0f, 1.0f}, Color(100.0f), Color(1000.0f), 0.95f);
        s.add_light(area_light(0.6f, 80.0f, 2.0f));
        s.add_light(point_light({0.0f, 0.0f, 0.5f}, 50.0f, 0.0f));  // inside the dense fog
    });
    build_and_run("fog_world_and_camera_inside", [](Scene& s) {
        add_backdrop(s);
        Medium thin;
        thin.sigma_a = Color(1e-4f);
        thin.sigma_s = Color(0.02f, 0.05f, 1e-6f);
        s.set_world_medium(s.add_medium(thin));
        add_fog_box(s, {-3.0f, -4.0f, -0.5f}, {3.0f, 3.0f, 3.0f}, Color(0.02f), Color(0.2f), -0.9f);
        s.add_light(area_light(0.6f, 80.0f, 2.0f));
        s.set_world(Color(0.3f));
    });
}

// The same fog (everyday and extreme densities) in every spectral mode with every integrator (the
// path-space filtering ones included, psf_spectral.h), a D65 lamp inside and dispersive glass.
TEST(Stress, FogWithEverySpectralMode) {
    for (const char* mode : {"UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT", "BRUTE_FORCE"}) {
        build_and_run("fog_spectral", [](Scene& s) {
            add_backdrop(s);
            Material g = glass(1.5f, 0.0f);
            g.spectral.dispersion = "N-SF11";
            add_box(s, {0.2f, -0.5f, 0.0f}, {0.6f, -0.1f, 0.4f}, s.add_material(g));
            add_box(s, {1.0f, -1.0f, 0.0f}, {1.05f, 1.0f, 1.0f}, s.add_material(glossy(Color(0.9f), 0.0f)));
            add_fog_box(s, {-1.5f, -1.5f, 0.01f}, {1.5f, 1.5f, 1.2f}, Color(0.05f, 0.1f, 0.0f), Color(0.5f, 0.4f, 0.0f), 0.5f);
            add_fog_box(s, {-0.4f, 0.3f, 0.02f}, {0.0f, 0.7f, 0.5f}, Color(100.0f), Color(1000.0f), 0.95f);
            s.add_light(area_light(0.6f, 80.0f, 2.0f));
            LightDesc lamp = point_light({-0.5f, 0.5f, 0.7f}, 20.0f, 0.05f);
            lamp.spectrum = "D65";
            s.add_light(lamp);
        }, true, mode);
    }
}
