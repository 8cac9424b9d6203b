// Shader programs (shading/shader_program.h): constant folding, per-hit evaluation through the scene,
// the Principled expansion, transparency and emission, and bad programs refused or made harmless.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "scene/scene.h"
#include "shading/node_math.h"
#include "shading/shader_program.h"
#include "program_builder.h"
#include "test_scenes.h"

using namespace smis;
using smis::testing::camera_at;

namespace {

using Builder = smis::testing::ProgramBuilder;


// Emission of (value of a Math op on constants) x colour: everything folds.
TEST(ShaderProgram, ConstantTreeFoldsToNothingPerHit) {
    Builder b;
    uint16_t a = b.constant(3.0f), c = b.constant(0.0f), out = b.alloc(1);
    ShaderOp& m = b.op(ShaderOpCode::Math);
    m.in[0] = a, m.in[1] = c, m.out[0] = out, m.i[0] = int(shading::MathOp::Divide);  // safe division: 0
    uint16_t s = b.alloc(1);
    ShaderOp& m2 = b.op(ShaderOpCode::Math);
    m2.in[0] = out, m2.in[1] = b.constant(2.0f), m2.out[0] = s, m2.i[0] = int(shading::MathOp::Add);
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = b.constant3(Color(1.0f, 0.5f, 0.25f));
    e.in[2] = s;
    auto p = b.build();
    EXPECT_TRUE(p->is_constant());
    EXPECT_EQ(p->varying_op_count(), 0u);
    ShaderResult r = p->eval_constant();
    EXPECT_FLOAT_EQ(r.emission.x, 2.0f);
    EXPECT_FLOAT_EQ(r.emission.y, 1.0f);
    EXPECT_FLOAT_EQ(r.emission.z, 0.5f);
    EXPECT_TRUE(p->may_emit());
}

// A texture coordinate feeding a checker feeding a diffuse colour stays per hit; the constant
// scale before it folds.
TEST(ShaderProgram, HitDependentOpsStayAndTheirConstantInputsFold) {
    Builder b;
    uint16_t scale = b.alloc(1);
    ShaderOp& m = b.op(ShaderOpCode::Math);
    m.in[0] = b.constant(2.0f), m.in[1] = b.constant(2.5f), m.out[0] = scale, m.i[0] = int(shading::MathOp::Multiply);
    uint16_t co = b.alloc(3);
    ShaderOp& tc = b.op(ShaderOpCode::TexCoord);
    tc.out[3] = co;
    uint16_t col = b.alloc(3), fac = b.alloc(1);
    ShaderOp& ch = b.op(ShaderOpCode::TexChecker);
    ch.in[0] = co, ch.in[1] = b.constant3(Color(1.0f)), ch.in[2] = b.constant3(Color(0.0f)), ch.in[3] = scale;
    ch.out[0] = col, ch.out[1] = fac;
    ShaderOp& d = b.op(ShaderOpCode::Diffuse);
    d.in[1] = col;
    auto p = b.build();
    EXPECT_FALSE(p->is_constant());
    EXPECT_EQ(p->varying_op_count(), 2u);  // texcoord and checker; the multiply folded
    EXPECT_FALSE(p->may_emit());
    EXPECT_FALSE(p->may_be_transparent());
}

// A textured base colour makes neither an emitter nor a cut-out: only the emission and alpha inputs
// (and the weight) decide those, so such a material gets no triangle lights.
TEST(ShaderProgram, TexturedPrincipledIsNeitherEmissiveNorTransparent) {
    Builder b;
    uint16_t co = b.alloc(3);
    b.op(ShaderOpCode::TexCoord).out[3] = co;
    // The weight register sits right before the per-hit colour: a float input must not be taken
    // for varying because its neighbours are (a vector read spans three registers, a float one).
    uint16_t weight = b.constant(1.0f);
    uint16_t col = b.alloc(3);
    ShaderOp& ch = b.op(ShaderOpCode::TexChecker);
    ch.in[0] = co, ch.out[0] = col;
    ShaderOp& pr = b.op(ShaderOpCode::Principled);
    pr.in[0] = weight;
    pr.in[1] = col;
    pr.in[20] = b.constant3(Color(0.0f));  // Emission black
    pr.in[21] = b.constant(1.0f);          // Emission Strength
    pr.in[22] = b.constant(1.0f);          // Alpha
    auto p = b.build();
    EXPECT_FALSE(p->is_constant());
    EXPECT_FALSE(p->may_emit());
    EXPECT_FALSE(p->may_be_transparent());
    // The same material with the checker into Emission does emit.
    Builder e = b;
    e.ops.back().in[20] = col;
    EXPECT_TRUE(e.build()->may_emit());
}

// An image of one texel (the magenta stand-in for a missing file) folds whatever reads it: the
// program is constant, and the hit-reading ops before it are never run without a hit (they were,
// and crashed, when a missing environment image folded a World).
TEST(ShaderProgram, SingleTexelImageFoldsAndSkipsItsDeadInputs) {
    Builder b;
    uint16_t co = b.alloc(3);
    ShaderOp& tc = b.op(ShaderOpCode::TexCoord);
    tc.out[3] = co;
    const float magenta[4] = {1, 0, 1, 1};
    b.textures.push_back(std::make_shared<Texture>(magenta, 1, 1, "linear", Texture::Options{}));
    uint16_t col = b.alloc(3);
    ShaderOp& img = b.op(ShaderOpCode::TexImage);
    img.in[0] = co, img.out[0] = col, img.i[0] = 0;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = col;
    auto p = b.build();
    EXPECT_TRUE(p->is_constant());
    ShaderResult r = p->eval_constant();
    EXPECT_FLOAT_EQ(r.emission.x, 1.0f);
    EXPECT_FLOAT_EQ(r.emission.y, 0.0f);
    EXPECT_FLOAT_EQ(r.emission.z, 1.0f);
}

// Dead-code elimination and the narrow evaluations (ShaderOutputs): a checker nothing reads never
// runs; a cut-out test runs only what the transparency reads, an emission query only that and what
// the emission reads; and their transparency and emission are bit for bit the full evaluation's.
TEST(ShaderProgram, DeadOpsAndOpsOutsideTheAskedOutputsDoNotRun) {
    Builder b;
    uint16_t pos = b.alloc(3), back = b.alloc(1);
    ShaderOp& g = b.op(ShaderOpCode::Geometry);
    g.out[0] = pos, g.out[6] = back;
    auto checker = [&](float scale, uint16_t* fac) {
        uint16_t col = b.alloc(3);
        *fac = b.alloc(1);
        ShaderOp& ch = b.op(ShaderOpCode::TexChecker);
        ch.in[0] = pos, ch.in[3] = b.constant(scale), ch.out[0] = col, ch.out[1] = *fac;
        return col;
    };
    auto math = [&](shading::MathOp m, uint16_t a, float c) {
        uint16_t out = b.alloc(1);
        ShaderOp& op = b.op(ShaderOpCode::Math);
        op.in[0] = a, op.in[1] = b.constant(c), op.out[0] = out, op.i[0] = int(m), op.i[1] = 1;
        return out;
    };
    uint16_t fac_a, fac_b, fac_c, fac_dead;
    checker(2.0f, &fac_a);                        // A: the Principled's alpha
    uint16_t col_b = checker(3.0f, &fac_b);       // B: colours only
    uint16_t col_c = checker(5.0f, &fac_c);       // C: the emission
    checker(7.0f, &fac_dead);                     // read by nothing
    uint16_t transparent_w = math(shading::MathOp::Multiply, back, 0.5f);
    uint16_t alpha = math(shading::MathOp::Add, fac_a, 0.25f);
    ShaderOp& d = b.op(ShaderOpCode::Diffuse);
    d.in[0] = b.constant(0.5f), d.in[1] = col_b;
    ShaderOp& t = b.op(ShaderOpCode::Transparent);
    t.in[0] = transparent_w;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = col_c, e.in[2] = b.constant(2.0f);
    ShaderOp& pr = b.op(ShaderOpCode::Principled);
    pr.in[0] = b.constant(0.5f), pr.in[1] = col_b, pr.in[20] = col_c, pr.in[21] = b.constant(1.0f), pr.in[22] = alpha;
    auto p = b.build();
    // geometry, A, B, C, the two maths (the dead checker left out; it ran before, 7)
    EXPECT_EQ(p->varying_op_count(ShaderOutputs::All), 6u);
    EXPECT_EQ(p->varying_op_count(ShaderOutputs::Transparency), 4u);  // geometry, A, the two maths
    EXPECT_EQ(p->varying_op_count(ShaderOutputs::Emission), 5u);      // and C
    std::vector<float> transparencies, emissions;
    for (int k = 0; k < 16; ++k) {
        ShaderContext c;
        c.P = Vec3(0.37f * float(k % 4) - 0.6f, 0.29f * float(k / 4) - 0.5f, 0.1f);
        c.N = c.Ng = c.I = Vec3(0.0f, 0.0f, 1.0f);
        c.backfacing = k % 3 == 0;
        ShaderResult all, transparency, emission;
        p->eval(c, &all);
        p->eval(c, &transparency, ShaderOutputs::Transparency);
        p->eval(c, &emission, ShaderOutputs::Emission);
        EXPECT_GT(all.count, 0);
        EXPECT_EQ(transparency.count, 0);  // no lobe built for a cut-out test
        EXPECT_EQ(emission.count, 0);
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(transparency.transparent[i], all.transparent[i]) << k;
            EXPECT_EQ(emission.transparent[i], all.transparent[i]) << k;
            EXPECT_EQ(emission.emission[i], all.emission[i]) << k;
        }
        EXPECT_TRUE(is_black(transparency.emission));  // not asked for
        transparencies.push_back(all.transparent.x);
        emissions.push_back(all.emission.x);
    }
    // The points see different transparencies and emissions (the comparison is not between zeros).
    EXPECT_GT(*std::max_element(transparencies.begin(), transparencies.end()),
              *std::min_element(transparencies.begin(), transparencies.end()));
    EXPECT_GT(*std::max_element(emissions.begin(), emissions.end()),
              *std::min_element(emissions.begin(), emissions.end()));
}

// Through a scene: a quad whose material is checker(Object coordinates) into emission; the camera
// sees the pattern, and the program's emission at a hit agrees with the checker's definition.
TEST(ShaderProgram, EvaluatesAtSceneHits) {
    auto scene = std::make_shared<Scene>();
    Builder b;
    uint16_t co = b.alloc(3);
    b.op(ShaderOpCode::TexCoord).out[3] = co;
    uint16_t col = b.alloc(3), fac = b.alloc(1);
    ShaderOp& ch = b.op(ShaderOpCode::TexChecker);
    ch.in[0] = co, ch.in[1] = b.constant3(Color(1.0f)), ch.in[2] = b.constant3(Color(0.0f)), ch.in[3] = b.constant(2.0f);
    ch.out[0] = col, ch.out[1] = fac;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = col;
    e.in[2] = b.constant(1.0f);
    Material mat;
    mat.name = "checker";
    mat.program = b.build();
    uint32_t id = scene->add_material(mat);
    EXPECT_TRUE(scene->material(id).emissive());
    const float v[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    uint32_t mesh = scene->add_mesh(v, 4, t, 2, nullptr, nullptr, {id});
    Transform shift;
    shift.m[0][3] = 10.0f;  // object coordinates must not move with the object
    scene->add_instance(mesh, shift);
    scene->set_camera(camera_at(Vec3(10, 0, 5), 8, 8));
    scene->commit();
    int bright = 0, dark = 0;
    for (float x : {-0.7f, -0.2f, 0.3f, 0.8f})
        for (float y : {-0.7f, -0.2f, 0.3f, 0.8f}) {
            Ray ray{Vec3(10 + x, y, 5), Vec3(0, 0, -1)};
            SurfaceHit hit;
            ASSERT_TRUE(scene->intersect(ray, &hit));
            Color L = scene->emission_at(hit, Vec3(0, 0, 1));
            // Cycles' checker at scale 2 on object coordinates: cells of 0.5; with z in cell 0,
            // Color1 where the x and y cells' parities differ.
            float px = (x * 2.0f + 1e-6f) * 0.999999f, py = (y * 2.0f + 1e-6f) * 0.999999f;
            bool differ = std::abs(int(std::floor(px))) % 2 != std::abs(int(std::floor(py))) % 2;
            float expected = differ ? 1.0f : 0.0f;
            EXPECT_FLOAT_EQ(L.x, expected) << x << " " << y;
            (expected > 0.5f ? bright : dark)++;
        }
    EXPECT_GT(bright, 0);
    EXPECT_GT(dark, 0);
}

// Principled with alpha 0.25 folds into a cut-out with the closures unscaled (Cycles mixes a
// transparent closure of weight 0.75 in; the kept quarter of the hits carries the full closures).
TEST(ShaderProgram, PrincipledAlphaFoldsIntoACutOut) {
    auto scene = std::make_shared<Scene>();
    Builder b;
    ShaderOp& pr = b.op(ShaderOpCode::Principled);
    for (auto& r : pr.in) r = kNoReg;
    pr.in[1] = b.constant3(Color(0.5f));      // base colour
    pr.in[22] = b.constant(0.25f);            // alpha
    Material mat;
    mat.name = "leaf";
    mat.program = b.build();
    uint32_t id = scene->add_material(mat);
    const Material& m = scene->material(id);
    EXPECT_FALSE(m.program);  // constant: plain lobes
    EXPECT_NEAR(m.alpha, 0.25f, 1e-6f);
    ASSERT_GE(m.lobes.size(), 1u);
    EXPECT_EQ(m.lobes[0].kind, LobeKind::PrincipledDiffuse);
    EXPECT_NEAR(m.lobes[0].weight.x, 0.5f, 1e-6f);
}

TEST(ShaderProgram, BadProgramsAreRefusedOrMadeHarmless) {
    Builder b;
    ShaderOp& e = b.op(ShaderOpCode::Emission);
    e.in[1] = 500;  // beyond the register file
    EXPECT_THROW(ShaderProgram(b.ops, b.regs, {}, {}), std::invalid_argument);
    ShaderOpCode code;
    EXPECT_FALSE(ShaderProgram::op_by_name("no_such_op", &code));
    EXPECT_TRUE(ShaderProgram::op_by_name("tex_noise", &code));
    // NaN socket values are zeroed, absurd scales and log of negatives stay finite.
    Builder n;
    uint16_t out = n.alloc(1);
    ShaderOp& m = n.op(ShaderOpCode::Math);
    m.in[0] = n.constant(-1.0f), m.in[1] = n.constant(std::numeric_limits<float>::quiet_NaN());
    m.out[0] = out, m.i[0] = int(shading::MathOp::Logarithm);
    ShaderOp& em = n.op(ShaderOpCode::Emission);
    em.in[1] = n.constant3(Color(1e30f));
    em.in[2] = out;
    auto p = n.build();
    ShaderResult r = p->eval_constant();
    EXPECT_TRUE(is_finite(r.emission));
}

}  // namespace

// Programs whose context ops read only ShaderContext's basic part get only that part
// (ShaderProgram::needs_full_context, Scene::program_context): every context op, output by output,
// on a turned, scaled and shifted instance with UVs and smooth normals, must give the same value in
// the context the scene chooses as in the full one.
TEST(ShaderProgram, BasicContextGivesEveryContextOpItsFullValue) {
    const float v[] = {-1, -1, 0, 1, -1, 0.2f, 1, 1, 0.1f, -1, 1, 0};
    const int32_t t[] = {0, 1, 2, 0, 2, 3};
    const float normals[] = {0.1f, 0, 1, 0, 0.2f, 1, 0, 0, 1, 0.1f, 0, 1, 0, 0, 1, -0.1f, 0.1f, 1};
    const float uvs[] = {0, 0, 0.9f, 0.1f, 1, 1, 0, 0, 1, 1, 0.2f, 0.8f};
    Transform turn;  // 30 degrees about z, scaled (2, 0.5, 1.5), shifted
    const float c = std::cos(0.5236f), s = std::sin(0.5236f);
    turn.m[0][0] = 2 * c, turn.m[0][1] = -0.5f * s, turn.m[0][3] = 3;
    turn.m[1][0] = 2 * s, turn.m[1][1] = 0.5f * c, turn.m[1][3] = -1;
    turn.m[2][2] = 1.5f, turn.m[2][3] = 0.5f;
    int basic = 0, full = 0;
    for (int code = int(ShaderOpCode::TexCoord); code <= int(ShaderOpCode::Displacement); ++code) {
        const auto op_code = ShaderOpCode(code);
        const bool context_op = code <= int(ShaderOpCode::NormalMap) || op_code == ShaderOpCode::VectorTransform ||
                                op_code == ShaderOpCode::Displacement;
        if (!context_op || op_code == ShaderOpCode::BumpEnter || op_code == ShaderOpCode::BumpLeave) continue;
        for (int k = 0; k < 13; ++k) {
            Builder b;
            uint16_t out = b.alloc(3);
            ShaderOp& op = b.op(op_code);
            op.out[k] = out;
            ShaderOp& e = b.op(ShaderOpCode::Emission);
            e.in[1] = out;
            e.in[2] = b.constant(1.0f);
            Scene scene;
            Material mat;
            mat.program = b.build();
            if (!mat.program || mat.program->is_constant()) continue;
            const uint32_t id = scene.add_material(mat);
            const uint32_t mesh = scene.add_mesh(v, 4, t, 2, normals, nullptr, {id}, uvs);
            scene.add_instance(mesh, turn);
            scene.set_camera(camera_at(Vec3(3, -1, 6), 8, 8));
            scene.commit();
            const ShaderProgram& program = *scene.material(id).program;
            const Vec3 wo = normalize(Vec3(0.2f, -0.3f, 1.0f));
            for (uint32_t prim : {0u, 1u}) {
                SurfaceAttribs at;
                at.instance = 0, at.prim = prim, at.bu = 0.3f, at.bv = 0.25f;
                const Color chosen = scene.emission(0, prim, id, at.bu, at.bv, wo);
                ShaderResult r;
                program.eval(scene.shader_context(at, wo, ShaderRay{}, true), &r, ShaderOutputs::Emission);
                EXPECT_EQ(chosen.x, r.emission.x) << "op " << code << " output " << k;
                EXPECT_EQ(chosen.y, r.emission.y) << "op " << code << " output " << k;
                EXPECT_EQ(chosen.z, r.emission.z) << "op " << code << " output " << k;
            }
            (program.needs_full_context(ShaderOutputs::Emission) ? full : basic)++;
        }
    }
    // Both kinds occur (UV, Light Path, Fresnel ... basic; Generated, Object Info, Normal Map ... full).
    EXPECT_GT(basic, 5);
    EXPECT_GT(full, 5);
}

namespace {

// Material::program_bsdf without any Transparent weight (its shortcut: keep is exactly 1) against
// the same result with a grey transparency g: the kept hit's lobes are the same lobes divided by
// 1 - g, and on both paths a back-facing hit inverts the glass lobe's eta and keeps the diffuse one.
TEST(ShaderProgram, OpaqueProgramLobesAreTheTransparentPathsUndivided) {
    Material m;
    ShaderResult res;
    Lobe diffuse;
    diffuse.kind = LobeKind::Diffuse;
    diffuse.weight = Color(0.3f, 0.5f, 0.7f);
    Lobe glass;
    glass.kind = LobeKind::Dielectric;
    glass.weight = Color(0.9f);
    glass.eta = 1.45f;
    res.lobes[0] = diffuse;
    res.lobes[1] = glass;
    res.count = 2;
    const Frame frame(Vec3(0, 0, 1));
    const Vec3 ng(0, 0, 1);
    ShaderResult grey = res;
    grey.transparent = Color(0.5f);  // keep 1/2: every weight doubled
    for (bool backfacing : {false, true}) {
        const Bsdf opaque = m.program_bsdf(res, frame, ng, backfacing);
        const Bsdf cut = m.program_bsdf(grey, frame, ng, backfacing);
        ASSERT_EQ(opaque.lobe_count(), 2);
        ASSERT_EQ(cut.lobe_count(), 2);
        for (int i = 0; i < 2; ++i) {
            EXPECT_EQ(opaque.lobe(i).kind, res.lobes[i].kind);
            EXPECT_EQ(opaque.lobe(i).weight, res.lobes[i].weight) << i;
            EXPECT_EQ(cut.lobe(i).weight, res.lobes[i].weight * 2.0f) << i;
            EXPECT_EQ(opaque.lobe(i).eta, cut.lobe(i).eta) << i << " backfacing " << backfacing;
        }
        EXPECT_EQ(opaque.lobe(1).eta, backfacing ? 1.0f / 1.45f : 1.45f);
        EXPECT_EQ(opaque.lobe(0).eta, diffuse.eta);
    }
}

}  // namespace
