// Hair curves (curves.cpp): a ray leaving a strand ignores the whole strand, every segment of it, as
// Cycles 3.4's Embree filter does (it compares the hit segment's curve, curve_segments[prim].prim,
// with the ray's own); other strands still block it.
#include <gtest/gtest.h>

#include "integrators/path_tracing.h"
#include "program_builder.h"
#include "shading/node_math.h"
#include "shading/procedural_noise.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

// A hairpin (up at x = 0, over, down at x = 0.2: its first and last segments face each other across
// 0.16 m) and a straight strand at x = 0.5, radius 0.02.
TEST(Curves, RaysLeavingAStrandIgnoreAllOfItsSegments) {
    Scene s;
    uint32_t m = s.add_material(diffuse(Color(0.5f)));
    const float r = 0.02f;
    const float points[] = {0.0f, 0.0f, 0.0f, r,   0.0f, 0.0f, 1.0f, r,   0.1f, 0.0f, 1.1f, r,
                            0.2f, 0.0f, 1.0f, r,   0.2f, 0.0f, 0.0f, r,   0.5f, 0.0f, 0.0f, r,
                            0.5f, 0.0f, 1.0f, r};
    const int32_t offsets[] = {0, 5, 7};
    s.add_instance(s.add_curves(points, 7, offsets, 2, m), Transform());
    s.set_camera(camera_at(Vec3(0.0f, -5.0f, 0.5f), 4, 4));
    s.commit();
    auto hit_x = [&](const Vec3& o, float dx) {
        SurfaceHit h;
        return s.intersect(Ray{o, Vec3(dx, 0.0f, 0.0f)}, &h) ? h.p.x : -1.0f;
    };
    // From outside, the hairpin's first arm is hit (its centre line bows towards -x, away from the
    // next control point: Catmull-Rom).
    const float arm = hit_x(Vec3(-1.0f, 0.0f, 0.5f), 1.0f);
    EXPECT_NEAR(arm, -r, 0.01f);
    // From there through the fibre (a transmission's ray, starting on segment 0): the hairpin's
    // other arm (segment 3) is ignored, the straight strand is not, as in Cycles.
    EXPECT_NEAR(hit_x(Vec3(arm, 0.0f, 0.5f), 1.0f), 0.5f - r, 1e-4f);
    // From the straight strand's surface the hairpin is another strand: its second arm, the mirror
    // image of the first about x = 0.1, is hit.
    EXPECT_NEAR(hit_x(Vec3(0.5f - r, 0.0f, 0.5f), -1.0f), 0.2f - arm, 1e-4f);
}

// Hair Info (the hair_info op): Random is Cycles' per-curve hash_uint2_to_float(curve, 0) of the
// strand's index among its object's hair (add_curves' first_curve + c), constant along the strand;
// Is Strand 1. Off hair, Random is the op's input (the Principled Hair BSDF's own Random socket).
TEST(Curves, HairInfoRandomIsCyclesHashOfTheStrandIndex) {
    auto s = std::make_shared<Scene>();
    ProgramBuilder b;
    uint16_t is_strand = b.alloc(1), random = b.alloc(1), sum = b.alloc(1);
    ShaderOp& info = b.op(ShaderOpCode::HairInfo);
    info.in[0] = b.constant(0.25f);
    info.out[0] = is_strand, info.out[1] = random;
    ShaderOp& add = b.op(ShaderOpCode::Math);  // strength = Random + 10 x Is Strand
    add.i[0] = int(shading::MathOp::MultiplyAdd);
    add.in[0] = is_strand, add.in[1] = b.constant(10.0f), add.in[2] = random, add.out[0] = sum;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = b.constant3(Color(1.0f)), e.in[2] = sum;
    Material mat;
    mat.name = "hair info";
    mat.program = b.build();
    uint32_t m = s->add_material(mat);
    const float r = 0.02f;
    const float points[] = {0.0f, 0.0f, 0.0f, r, 0.0f, 0.0f, 0.5f, r, 0.0f, 0.0f, 1.0f, r,
                            0.5f, 0.0f, 0.0f, r, 0.5f, 0.0f, 1.0f, r};
    const int32_t offsets[] = {0, 3, 5};
    s->add_instance(s->add_curves(points, 5, offsets, 2, m, 5), Transform());
    const float v[] = {-1, 2, -1, 2, 2, -1, 2, 2, 2, -1, 2, 2};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    s->add_instance(s->add_mesh(v, 4, t, 2, nullptr, nullptr, {m}), Transform());
    s->set_camera(camera_at(Vec3(0.0f, -5.0f, 0.5f), 4, 4));
    s->commit();
    auto strength = [&](float x, float z) {
        SurfaceHit h;
        EXPECT_TRUE(s->intersect(Ray{Vec3(x, -1.0f, z), Vec3(0.0f, 1.0f, 0.0f)}, &h));
        return s->emission_at(h, Vec3(0.0f, -1.0f, 0.0f)).x;
    };
    for (float z : {0.2f, 0.7f}) EXPECT_FLOAT_EQ(strength(0.0f, z), 10.0f + shading::hash_uint2_to_float(5, 0));
    EXPECT_FLOAT_EQ(strength(0.5f, 0.5f), 10.0f + shading::hash_uint2_to_float(6, 0));
    EXPECT_FLOAT_EQ(strength(0.25f, 0.5f), 0.25f);  // the wall behind: no strand
}

// An emissive strand is no light (Cycles 3.4 makes lights of mesh triangles only), yet a ray that hits
// it adds its emission, with MIS weight 1 whatever the previous vertex's BSDF density (Cycles'
// integrate_surface_emission weighs only triangles): no light sample can reach a strand. A shadow ray
// it blocks stays blocked.
TEST(Curves, EmissiveStrandAddsItsEmissionWithMisWeightOne) {
    Scene s;
    Material glow = diffuse(Color(0.5f));
    glow.emission = Color(2.0f, 1.0f, 0.5f);
    uint32_t m = s.add_material(glow);
    const float r = 0.02f;
    const float points[] = {0.0f, 0.0f, 0.0f, r, 0.0f, 0.0f, 0.5f, r, 0.0f, 0.0f, 1.0f, r};
    const int32_t offsets[] = {0, 3};
    s.add_instance(s.add_curves(points, 3, offsets, 1, m), Transform());
    s.set_camera(camera_at(Vec3(0.0f, -5.0f, 0.5f), 4, 4));
    s.commit();
    EXPECT_TRUE(s.lights().empty());
    const Ray ray{Vec3(0.0f, -1.0f, 0.5f), Vec3(0.0f, 1.0f, 0.0f)};
    SurfaceHit h;
    ASSERT_TRUE(s.intersect(ray, &h));
    EXPECT_EQ(h.light, kStrandEmission);
    RenderSettings settings;
    PathState st;  // a camera ray
    Color seen = emission_along(s, settings, ray, true, h, st);
    st.prev_delta = false, st.prev_pdf = 0.3f, st.depth = 1, st.ray_flags = kRayDiffuse;  // a BSDF sample's ray
    Color bounced = emission_along(s, settings, ray, true, h, st);
    for (int c = 0; c < 3; ++c) {
        EXPECT_FLOAT_EQ(seen[c], glow.emission[c]);
        EXPECT_FLOAT_EQ(bounced[c], glow.emission[c]);
    }
    EXPECT_TRUE(s.occluded(Vec3(0.0f, -1.0f, 0.5f), Vec3(0.0f, 1.0f, 0.0f), 2.0f));
}

// Hair UVs (add_curves' uvs and attributes): one value per strand, constant along it (Cycles'
// ATTR_ELEMENT_CURVE), found by the input curve's index even where an earlier curve was dropped.
TEST(Curves, StrandUvsAndAttributesArePerCurve) {
    auto s = std::make_shared<Scene>();
    ProgramBuilder b;
    uint16_t col = b.alloc(3);
    ShaderOp& a = b.op(ShaderOpCode::Attribute);
    a.i[0] = s->attribute_id("second map");
    a.out[0] = col;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = col, e.in[2] = b.constant(1.0f);
    Material mat;
    mat.name = "attribute";
    mat.program = b.build();
    uint32_t m = s->add_material(mat);
    const float r = 0.02f;
    // Curve 0 has one point (dropped), curve 1 stands at x = 0, curve 2 at x = 0.5.
    const float points[] = {3.0f, 0.0f, 0.0f, r, 0.0f, 0.0f, 0.0f, r, 0.0f, 0.0f, 1.0f, r,
                            0.5f, 0.0f, 0.0f, r, 0.5f, 0.0f, 1.0f, r};
    const int32_t offsets[] = {0, 1, 3, 5};
    const float uvs[] = {9.0f, 9.0f, 0.25f, 0.5f, 0.75f, 0.125f};
    const float second[] = {1.0f, 1.0f, 1.0f, 0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};
    uint32_t id = s->add_curves(points, 5, offsets, 3, m, 0, uvs, {{"second map", second, 3}});
    EXPECT_EQ(s->mesh_dropped(id), 1u);
    s->add_instance(id, Transform());
    s->set_camera(camera_at(Vec3(0.0f, -5.0f, 0.5f), 4, 4));
    s->commit();
    auto check = [&](float x, float z, int curve) {
        SurfaceHit h;
        ASSERT_TRUE(s->intersect(Ray{Vec3(x, -1.0f, z), Vec3(0.0f, 1.0f, 0.0f)}, &h));
        EXPECT_FLOAT_EQ(h.attr.uv.x, uvs[2 * curve]);
        EXPECT_FLOAT_EQ(h.attr.uv.y, uvs[2 * curve + 1]);
        Color c = s->emission_at(h, Vec3(0.0f, -1.0f, 0.0f));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(c[k], second[3 * curve + k], 1e-6f);
    };
    check(0.0f, 0.2f, 1);
    check(0.0f, 0.8f, 1);
    check(0.5f, 0.5f, 2);
}

// Rounded Ribbons (set_curve_ribbons, Cycles' CURVE_RIBBON): the strand is a flat strip facing the
// ray, met where the ray crosses the centre line's plane, and shaded with the round tube's normal at
// the same offset across it (Cycles' curve_shader_setup).
TEST(Curves, RibbonsFaceTheRayAndFakeTheTubesNormal) {
    auto hit_at = [](bool ribbons, float x) {
        Scene s;
        uint32_t m = s.add_material(diffuse(Color(0.5f)));
        const float r = 0.1f;
        const float points[] = {0.0f, 0.0f, 0.0f, r, 0.0f, 0.0f, 1.0f, r, 0.0f, 0.0f, 2.0f, r};
        const int32_t offsets[] = {0, 3};
        uint32_t id = s.add_curves(points, 3, offsets, 1, m);
        if (ribbons) s.set_curve_ribbons(id, 2);
        s.add_instance(id, Transform());
        s.set_camera(camera_at(Vec3(0.0f, -5.0f, 1.0f), 4, 4));
        s.commit();
        SurfaceHit h;
        EXPECT_TRUE(s.intersect(Ray{Vec3(x, -1.0f, 1.0f), Vec3(0.0f, 1.0f, 0.0f)}, &h));
        return h;
    };
    for (float x : {-0.05f, 0.05f, 0.08f}) {
        SurfaceHit tube = hit_at(false, x), ribbon = hit_at(true, x);
        EXPECT_NEAR(tube.p.y, -std::sqrt(0.01f - x * x), 1e-3f);
        EXPECT_NEAR(ribbon.p.y, 0.0f, 1e-4f);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(ribbon.ns[k], tube.ns[k], 2e-3f) << x;
    }
}
