// The image-texture closure lowering (scene/image_closure.h): which programs it takes, and that the
// path tracer's shading of a lowered material is bit for bit what the program gives at the same hits.
#include <gtest/gtest.h>

#include <cstring>

#include "integrators/path_tracing.h"
#include "scene/image_closure.h"
#include "scene/scene.h"
#include "program_builder.h"
#include "test_scenes.h"

using namespace smis;
using smis::testing::camera_at;

namespace {

using Builder = smis::testing::ProgramBuilder;

// A 3 x 2 linear image with a black texel (its lobe is dropped on both paths) and a value above 1.
std::shared_ptr<const Texture> image(float first = 0.9f) {
    const float rgba[] = {first, 0.2f, 0.1f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.3f, 0.6f, 0.9f, 1.0f,
                          1.7f,  0.5f, 0.0f, 1.0f, 0.4f, 0.4f, 0.4f, 1.0f, 0.05f, 0.8f, 0.3f, 1.0f};
    return std::make_shared<Texture>(rgba, 3, 2, "linear", Texture::Interp::Linear, Texture::Wrap::Repeat);
}

// What the add-on compiles for Image Texture (vector unlinked) -> Diffuse BSDF Color; `tweak` changes
// the ops before the build (index 0: texcoord, 1: tex_image, 2: diffuse).
struct Pattern {
    Builder b;
    uint16_t uv, color, alpha;
    Pattern(std::shared_ptr<const Texture> tex = image(), float weight = 0.7f, float roughness = 0.0f) {
        uv = b.alloc(3);
        b.op(ShaderOpCode::TexCoord).out[2] = uv;
        b.textures.push_back(std::move(tex));
        color = b.alloc(3), alpha = b.alloc(1);
        ShaderOp& t = b.op(ShaderOpCode::TexImage);
        t.in[0] = uv, t.out[0] = color, t.out[1] = alpha, t.i[0] = 0, t.i[1] = 0;
        ShaderOp& d = b.op(ShaderOpCode::Diffuse);
        d.in[0] = b.constant(weight), d.in[1] = color, d.in[2] = b.constant(roughness);
    }
    std::shared_ptr<const ShaderProgram> build() { return b.build(); }
};

uint32_t bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
void expect_same_vec(const Vec3& a, const Vec3& b, const char* what) {
    EXPECT_EQ(bits(a.x), bits(b.x)) << what;
    EXPECT_EQ(bits(a.y), bits(b.y)) << what;
    EXPECT_EQ(bits(a.z), bits(b.z)) << what;
}

// Lobes, frame and what they evaluate to, bit for bit.
void expect_same_bsdf(const Bsdf& a, const Bsdf& b, const Vec3& wo) {
    ASSERT_EQ(a.lobe_count(), b.lobe_count());
    for (int i = 0; i < a.lobe_count(); ++i) {
        const Lobe &x = a.lobe(i), &y = b.lobe(i);
        EXPECT_EQ(x.kind, y.kind);
        EXPECT_EQ(x.fresnel, y.fresnel);
        EXPECT_EQ(x.index, y.index);
        EXPECT_EQ(x.variant, y.variant);
        expect_same_vec(x.weight, y.weight, "weight");
        expect_same_vec(x.f0, y.f0, "f0");
        expect_same_vec(x.kind_colour, y.kind_colour, "kind colour");
        EXPECT_EQ(bits(x.alpha), bits(y.alpha));
        EXPECT_EQ(bits(x.alpha_y), bits(y.alpha_y));
        EXPECT_EQ(bits(x.eta), bits(y.eta));
    }
    expect_same_vec(a.frame().n, b.frame().n, "frame n");
    expect_same_vec(a.frame().s, b.frame().s, "frame s");
    expect_same_vec(a.ng(), b.ng(), "ng");
    for (const Vec3& d : {Vec3(0, 0, 1), Vec3(0.6f, 0, 0.8f), Vec3(-0.3f, 0.9f, 0.3f), Vec3(0.1f, -0.2f, -0.97f),
                          normalize(Vec3(0.99f, 0.1f, 0.02f))}) {
        for (const Vec3& wi : {d, -d}) {
            expect_same_vec(a.eval(wo, wi), b.eval(wo, wi), "eval");  // the bump shadowing too
            EXPECT_EQ(bits(a.pdf(wo, wi)), bits(b.pdf(wo, wi)));
        }
    }
}

// A quad with UVs and smooth corner normals tilted well away from the face (grazing views then need
// ensure_valid_reflection's turn), instanced as given; the material is `program`'s.
struct QuadScene {
    std::shared_ptr<Scene> scene = std::make_shared<Scene>();
    uint32_t material = 0, mesh = 0;
    QuadScene(std::shared_ptr<const ShaderProgram> program, bool uvs = true) {
        Material mat;
        mat.name = "image into diffuse";
        mat.program = std::move(program);
        material = scene->add_material(mat);
        const float v[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
        const int32_t t[] = {0, 1, 2, 0, 2, 3};
        const Vec3 n[4] = {normalize(Vec3(-0.8f, -0.3f, 1)), normalize(Vec3(0.7f, -0.6f, 1)),
                           normalize(Vec3(0.9f, 0.8f, 1)), normalize(Vec3(-0.5f, 0.9f, 1))};
        std::vector<float> corner_normals, corner_uvs;
        for (int k : t) {
            corner_normals.insert(corner_normals.end(), {n[k].x, n[k].y, n[k].z});
            corner_uvs.insert(corner_uvs.end(), {v[3 * k] * 0.7f + 0.4f, v[3 * k + 1] * 1.3f - 0.2f});
        }
        mesh = scene->add_mesh(v, 4, t, 2, corner_normals.data(), nullptr, {material},
                               uvs ? corner_uvs.data() : nullptr);
    }
    // Rays from above and below at steep to grazing angles over the quad.
    template <class F>
    void each_hit(const Vec3& offset, F&& f) {
        for (float x : {-0.8f, -0.35f, 0.1f, 0.55f, 0.9f})
            for (float y : {-0.75f, -0.2f, 0.3f, 0.85f})
                for (float side : {1.0f, -1.0f})
                    for (float slope : {0.0f, 2.0f, 12.0f}) {
                        Vec3 d = normalize(Vec3(slope * 0.6f, slope * 0.8f, -side));
                        Vec3 target = offset + Vec3(x, y, 0.0f);
                        Ray ray{target - d * 3.0f, d};
                        SurfaceHit hit;
                        if (!scene->intersect(ray, &hit)) continue;
                        f(ray, hit);
                    }
    }
};

// At every hit, the path tracer's shading point of the lowered material against the program's BSDF,
// normal and holdout (Scene::program_bsdf, what make_shading_point ran before the lowering).
struct Counts {
    int hits = 0, lowered = 0;
};
Counts expect_lowered_matches_program(QuadScene& q, const Vec3& offset) {
    Counts c;
    q.each_hit(offset, [&](const Ray& ray, const SurfaceHit& hit) {
        ShadingPoint sp = make_shading_point(*q.scene, hit, ray.d);
        Vec3 ns;
        Color holdout(1.0f);
        Bsdf program = q.scene->program_bsdf(hit.material, hit.attr, -ray.d, sp.backfacing, ShaderRay{}, &ns, &holdout);
        expect_same_vec(sp.ns, ns, "shading normal");
        expect_same_vec(sp.holdout, holdout, "holdout");
        expect_same_bsdf(sp.bsdf, program, sp.wo);
        ++c.hits;
        c.lowered += q.scene->hit_has_program_frame(hit) ? 1 : 0;
    });
    return c;
}

}  // namespace

// The pattern is lowered to the Diffuse's lobe with a white colour: kind by Roughness, weight the
// closure's Weight, the template's index.
TEST(ImageClosure, LowersImageIntoDiffuseColour) {
    for (float rough : {0.0f, 0.45f}) {
        Pattern p(image(), 0.7f, rough);
        auto program = p.build();
        std::optional<ImageClosure> lowered = lower_image_closure(*program);
        ASSERT_TRUE(lowered.has_value());
        EXPECT_EQ(lowered->lobe.kind, rough > 0.0f ? LobeKind::OrenNayar : LobeKind::Diffuse);
        EXPECT_EQ(lowered->lobe.weight, Color(0.7f));
        EXPECT_EQ(lowered->lobe.alpha, rough);
        EXPECT_EQ(lowered->lobe.index, program->lobe_templates()[0].index);
        EXPECT_EQ(lowered->texture.get(), program->texture(0).get());
    }
}

// Through a scene, flattened and instanced (rotated, scaled, mirrored): the same BSDF, normal and
// holdout as the program at every hit, front- and back-facing, Lambert and Oren-Nayar.
TEST(ImageClosure, ShadingIsTheProgramsBitForBit) {
    for (float rough : {0.0f, 0.45f}) {
        Pattern p(image(), 0.7f, rough);
        QuadScene q(p.build());
        ASSERT_TRUE(q.scene->material(q.material).image_closure.has_value());
        Transform placed;
        placed.m[0][0] = 0.0f, placed.m[0][1] = -1.3f, placed.m[1][0] = 1.3f, placed.m[1][1] = 0.0f;  // turned, scaled
        placed.m[0][3] = 6.0f;
        Transform mirrored;
        mirrored.m[0][0] = -1.0f, mirrored.m[1][3] = 6.0f;
        q.scene->add_instance(q.mesh, Transform());
        q.scene->add_instance(q.mesh, placed);
        q.scene->add_instance(q.mesh, mirrored);
        q.scene->set_camera(camera_at(Vec3(0, 0, 5), 8, 8));
        q.scene->commit();
        for (const Vec3& offset : {Vec3(0.0f), Vec3(6, 0, 0), Vec3(0, 6, 0)})
            EXPECT_GT(expect_lowered_matches_program(q, offset).lowered, 20) << rough;
    }
}

// Where the hit's frame is not the one the program's context rebuilds, the program shades: a
// deforming mesh, a moving instance, a mesh without UVs.
TEST(ImageClosure, OnlyStaticTrianglesWithUvsTakeIt) {
    auto program = Pattern().build();
    // The hits over the quad at the origin, and how many of them took the lowered form; the shading
    // is the program's at every one of them either way.
    auto shade = [](QuadScene& q, const std::vector<Transform>& motion = {}) {
        q.scene->add_instance(q.mesh, Transform(), Color(1.0f), 0.0f, 0.0f, 1.0f, false, kRayAllVisibility, motion);
        q.scene->set_camera(camera_at(Vec3(0, 0, 5), 8, 8));
        q.scene->commit();
        return expect_lowered_matches_program(q, Vec3(0.0f));
    };
    QuadScene still(program);
    Counts c = shade(still);
    EXPECT_GT(c.hits, 20);
    EXPECT_EQ(c.lowered, c.hits);
    QuadScene deforming(program);
    const float steps[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0, -1, -1, 0.3f, 1, -1, 0, 1, 1, 0.2f, -1, 1, 0};
    deforming.scene->set_mesh_motion(deforming.mesh, steps, 2, 4);
    Transform later;
    later.m[2][3] = 0.2f;
    QuadScene moving(program), no_uvs(program, /*uvs=*/false);
    for (Counts other : {shade(deforming), shade(moving, {Transform(), later}), shade(no_uvs)}) {
        EXPECT_GT(other.hits, 20);
        EXPECT_EQ(other.lowered, 0);
    }
}

// An image with a negative texel keeps the program (the material too); so do a weight of 0 and a
// normal map on the material.
TEST(ImageClosure, NegativeTexelsKeepTheProgram) {
    Pattern negative(image(-0.25f));
    auto program = negative.build();
    EXPECT_FALSE(lower_image_closure(*program).has_value());
    QuadScene q(program);
    EXPECT_FALSE(q.scene->material(q.material).image_closure.has_value());
    EXPECT_FALSE(lower_image_closure(*Pattern(image(), 0.0f).build()).has_value());
    Material mapped;
    mapped.program = Pattern().build();
    mapped.normal_map = image();
    EXPECT_FALSE(q.scene->material(q.scene->add_material(mapped)).image_closure.has_value());
}

// Anything else than the pattern keeps the program: another vector, another projection, the image
// into another input or closure, an extra node, a second closure, a Normal input.
TEST(ImageClosure, OtherProgramsKeepIt) {
    auto refused = [](auto tweak) {
        Pattern p;
        tweak(p);
        auto program = p.build();
        EXPECT_FALSE(program->is_constant());
        return !lower_image_closure(*program).has_value();
    };
    EXPECT_TRUE(refused([](Pattern&) {}) == false);  // the pattern itself is taken
    EXPECT_TRUE(refused([](Pattern& p) { std::swap(p.b.ops[0].out[2], p.b.ops[0].out[3]); }));  // Object
    EXPECT_TRUE(refused([](Pattern& p) { p.b.ops[0].out[0] = p.b.alloc(3); }));  // Generated beside UV
    EXPECT_TRUE(refused([](Pattern& p) { p.b.ops[1].i[1] = 2; }));                // Sphere projection
    EXPECT_TRUE(refused([](Pattern& p) {                                          // the image into Roughness
        p.b.ops[2].in[2] = p.color;
        p.b.ops[2].in[1] = p.b.constant3(Color(0.5f));
    }));
    EXPECT_TRUE(refused([](Pattern& p) {  // its Alpha into Weight (whose initial value would pass)
        p.b.ops[2].in[0] = p.alpha;
        p.b.regs[p.alpha] = 0.5f;
    }));
    EXPECT_TRUE(refused([](Pattern& p) { p.b.ops[2].code = ShaderOpCode::Velvet; }));
    EXPECT_TRUE(refused([](Pattern& p) {  // an Invert between the image and the colour
        uint16_t inverted = p.b.alloc(3);
        ShaderOp inv;
        inv.code = ShaderOpCode::Invert;
        inv.in[0] = p.b.constant(1.0f), inv.in[1] = p.color, inv.out[0] = inverted;
        p.b.ops.insert(p.b.ops.begin() + 2, inv);
        p.b.ops[3].in[1] = inverted;
    }));
    EXPECT_TRUE(refused([](Pattern& p) {  // a second closure
        ShaderOp& e = p.b.op(ShaderOpCode::Emission);
        e.in[1] = p.b.constant3(Color(1.0f)), e.in[2] = p.b.constant(0.5f);
    }));
    EXPECT_TRUE(refused([](Pattern& p) { p.b.ops[2].in[3] = p.b.constant3(Vec3(0, 0, 1)); }));  // Normal
}
