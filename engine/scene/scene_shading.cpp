// The Scene's side of shader programs: rebuilding what a program reads at a hit (Cycles' ShaderData)
// from the triangle and its barycentrics, attributes, and running the program where integrators
// shade, emit and cut out.
#include "scene/scene.h"

#include "shading/normals.h"

namespace smis {
namespace {

inline Vec3 load3(const float* p) { return {p[0], p[1], p[2]}; }

// Surface parameters (u, v) of the offset d on the triangle's plane, from the UV map's derivatives.
Point2 uv_offset(const Vec3& dpdu, const Vec3& dpdv, const Vec3& d) {
    float a = dot(dpdu, dpdu), b = dot(dpdu, dpdv), c = dot(dpdv, dpdv);
    float det = a * c - b * b;
    if (!(std::fabs(det) > 1e-30f)) return {0.0f, 0.0f};
    float pu = dot(dpdu, d), pv = dot(dpdv, d);
    return {(c * pu - b * pv) / det, (a * pv - b * pu) / det};
}

}  // namespace

ShaderContext Scene::shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray, bool full) const {
    if (meshes_[instances_[at.instance].mesh].curves) return curve_shader_context(at, wo, ray);
    return triangle_shader_context(at, wo, ray, full);
}

ShaderContext Scene::triangle_shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                                             bool full) const {
    ShaderContext c;
    c.scene = this;
    c.ray = ray;
    const Instance& inst = instances_[at.instance];
    const Mesh& mesh = meshes_[inst.mesh];
    c.instance = at.instance;
    c.prim = at.prim;
    c.bu = at.bu;
    c.bv = at.bv;
    const uint32_t* idx = &mesh.indices[3 * at.prim];
    Vec3 a = load3(&mesh.positions[3 * idx[0]]), b = load3(&mesh.positions[3 * idx[1]]),
         cc = load3(&mesh.positions[3 * idx[2]]);
    float w = 1.0f - at.bu - at.bv;
    // Flat meshes (no corner normals, the common case) shade with the geometric normal: ns is ng
    // throughout, so its transform, normalisation and repairs below are skipped, not redone.
    const bool smooth = !mesh.corner_normals.empty();
    Vec3 ng = cross(b - a, cc - a);
    Vec3 ns = ng;
    if (smooth) {
        const Vec3* cn = &mesh.corner_normals[3 * at.prim];
        ns = cn[0] * w + cn[1] * at.bu + cn[2] * at.bv;
    }
    // Flattened meshes (identity instances) hold world-space normals, |det| M^-T times the object's.
    if (full) {
        if (smooth)
            c.N_object = inst.identity ? inst.to_world.normal_to_object(ns) / std::fabs(inst.to_world.determinant3()) : ns;
        else
            c.N_object = normalize(inst.identity ? inst.to_world.normal_to_object(ng) : ng);
    }
    Vec3 p = a * w + b * at.bu + cc * at.bv;
    if (!inst.identity) {
        const float mirror = inst.to_world.determinant3() < 0.0f ? -1.0f : 1.0f;
        p = inst.to_world.point(p);
        ng = inst.to_world.normal(ng) * mirror;
        if (smooth) ns = inst.to_world.normal(ns) * mirror;
    }
    ng = normalize(ng);
    if (smooth) {
        ns = normalize(ns);
        if (!is_finite(ns) || dot(ns, ng) == 0.0f) ns = ng;
        if (dot(ns, ng) < 0.0f) ns = -ns;
    } else {
        ns = ng;
    }
    c.P = p;
    c.I = wo;
    c.backfacing = dot(wo, ng) < 0.0f;
    c.Ng = c.backfacing ? -ng : ng;
    c.N = c.backfacing ? -ns : ns;
    const Point2* t = mesh.uvs.empty() ? nullptr : &mesh.uvs[3 * at.prim];
    if (t) {
        c.uv = {t[0].x * w + t[1].x * at.bu + t[2].x * at.bv, t[0].y * w + t[1].y * at.bu + t[2].y * at.bv};
        c.has_uv = true;
    }
    // The basic part ends here (ShaderProgram::needs_full_context).
    if (!full) return c;
    set_object_inputs(inst, &c);
    c.material_index = 0.0f;
    c.texspace_location = mesh.texspace_location;
    c.texspace_size = mesh.texspace_size;
    Vec3 dpdu(0.0f), dpdv(0.0f);
    if (t) {
        // The triangle's edges in world space: only the UV derivatives read them.
        Vec3 e1 = b - a, e2 = cc - a;
        if (!inst.identity) e1 = inst.to_world.vector(e1), e2 = inst.to_world.vector(e2);
        float du1 = t[1].x - t[0].x, dv1 = t[1].y - t[0].y, du2 = t[2].x - t[0].x, dv2 = t[2].y - t[0].y;
        float det = du1 * dv2 - du2 * dv1;
        if (std::fabs(det) > 1e-20f) {
            dpdu = (e1 * dv2 - e2 * dv1) / det;
            dpdv = (e2 * du1 - e1 * du2) / det;
            // The UV winding of the object's own mesh (Normal Map works in object space): a flattened
            // mirrored mesh had two corners swapped at commit, which flipped its winding.
            const float mirror = inst.identity && inst.to_world.determinant3() < 0.0f ? -1.0f : 1.0f;
            c.tangent_sign = (det < 0.0f ? -1.0f : 1.0f) * mirror;
        }
    }
    c.dPdu = dpdu;
    // One pixel's footprint at the point as seen from the camera (the engine has no ray differentials;
    // Cycles' dP of a camera ray is this size): the Bump node's finite differences span it.
    float dist = length(p - camera_.origin());
    float footprint = camera_.pixel_footprint(std::max(dist, 1e-6f));
    if (!(footprint > 0.0f) || !std::isfinite(footprint)) footprint = 1e-4f;
    Frame f(c.N);
    c.dPdx = f.s * footprint;
    c.dPdy = f.t * footprint;
    c.duvdx = uv_offset(dpdu, dpdv, c.dPdx);
    c.duvdy = uv_offset(dpdu, dpdv, c.dPdy);
    return c;
}

void Scene::set_object_inputs(const Instance& inst, ShaderContext* c) {
    c->to_world = inst.to_world;
    c->to_object = inst.to_object;
    c->object_location = inst.to_world.column(3);
    c->object_color = inst.object_color;
    c->object_alpha = inst.alpha;
    c->object_random = inst.random;
    c->object_index = inst.pass_index;
}

bool Scene::attribute(const ShaderContext& ctx, int32_t id, float* out) const {
    const Mesh& mesh = meshes_[instances_[ctx.instance].mesh];
    for (const MeshAttribute& a : mesh.attributes) {
        if (a.id != id) continue;
        out[3] = 1.0f;
        if (mesh.curves) {
            // One value per curve, constant along it (Cycles' ATTR_ELEMENT_CURVE).
            const float* v = &a.corners[mesh.input_curve(ctx.prim) * a.dims];
            for (int k = 0; k < a.dims; ++k) out[k] = v[k];
        } else {
            float w = 1.0f - ctx.bu - ctx.bv;
            const float* c = &a.corners[size_t(ctx.prim) * 3 * a.dims];
            for (int k = 0; k < a.dims; ++k) out[k] = c[k] * w + c[a.dims + k] * ctx.bu + c[2 * a.dims + k] * ctx.bv;
        }
        if (a.dims == 1) out[1] = out[2] = out[0];
        return true;
    }
    return false;
}

ShaderContext Scene::program_context(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                                     ShaderOutputs outputs) const {
    return shader_context(at, wo, ray, materials_[material].program->needs_full_context(outputs));
}

ShaderResult Scene::run_program(uint32_t material, const ShaderContext& ctx, ShaderOutputs outputs) const {
    ShaderResult res;
    materials_[material].program->eval(ctx, &res, outputs);
    return res;
}

ShaderResult Scene::run_program(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                                ShaderOutputs outputs) const {
    return run_program(material, program_context(material, at, wo, ray, outputs), outputs);
}

// The shading frame of an anisotropic closure: s along its tangent turned by `turns` x 2 pi about n
// (Cycles' rotate_around_axis), made perpendicular to n, t = n x s (make_orthonormals_tangent);
// Frame(n) where the tangent is along n.
static Frame tangent_frame(const Vec3& n, const Vec3& tangent, float turns) {
    float angle = 2.0f * kPi * turns;
    float c = std::cos(angle), sn = std::sin(angle);
    Vec3 t = tangent * c + cross(n, tangent) * sn + n * (dot(n, tangent) * (1.0f - c));
    Vec3 s = t - n * dot(n, t);
    float len2 = length_sq(s);
    if (!(len2 > 1e-12f) || !std::isfinite(len2)) return Frame(n);
    Frame f;
    f.n = n;
    f.s = s / std::sqrt(len2);
    f.t = cross(n, f.s);
    return f;
}

// Every anisotropic lobe about its own tangent and rotation (ShaderResult::lobe_tangents), Cycles'
// per-closure frame: its tangent's direction (cos phi, sin phi) in `frame`, stored as lobe.h's
// to_lobe_tangent reads it (the frame's own tangent where the closure had none).
static void own_tangents_in_frame(const Frame& frame, ShaderResult* res) {
    for (int i = 0; i < res->count; ++i) {
        Lobe& lobe = res->lobes[i];
        if (!lobe_has_own_tangent(lobe)) continue;
        const LobeTangent& lt = res->lobe_tangents[i];
        Vec3 t(lt.x, lt.y, lt.z);
        if (!(length_sq(t) > 0.0f)) continue;
        Vec3 s = tangent_frame(frame.n, t, lt.turns).s;
        lobe.kind_colour = Color(dot(s, frame.s) - 1.0f, dot(s, frame.t), lobe.kind_colour.z);  // z: the kind's own
    }
}

Bsdf Scene::program_bsdf(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, bool backfacing,
                         const ShaderRay& ray, Vec3* ns_out, Color* holdout_out) const {
    const ShaderContext ctx = program_context(material, at, wo, ray);
    ShaderResult res = run_program(material, ctx);
    // Every closure's normal is repaired, the interpolated one too (Cycles' svm_node_closure_bsdf).
    const Vec3 ns = shading::closure_normal(ctx.Ng, ctx.I, res.has_normal ? res.normal : ctx.N, ctx.N);
    *ns_out = ns;
    if (holdout_out) {
        // Without transparency keep is exactly 1 (and x / 1 is x).
        const float keep = res.transparent == Color(0.0f) ? 1.0f : transparency_keep(res);
        *holdout_out = keep > 1e-6f ? vmax(res.holdout, Color(0.0f)) / keep : Color(0.0f);
    }
    Frame frame = res.has_tangent ? tangent_frame(ns, res.tangent, res.tangent_rotation) : Frame(ns);
    if (res.has_tangent) own_tangents_in_frame(frame, &res);
    Bsdf bsdf = materials_[material].program_bsdf(res, frame, ctx.Ng, backfacing);
    if (!(ns == ctx.N)) bsdf.set_bump_base(ctx.N);
    return bsdf;
}

Color Scene::program_emission(const SurfaceAttribs& at, uint32_t material, const Vec3& wo) const {
    if (!materials_[material].program->may_emit()) return Color(0.0f);
    ShaderResult res = run_program(material, at, wo, ShaderRay{}, ShaderOutputs::Emission);
    float keep = transparency_keep(res);
    return keep > 1e-6f ? res.emission / keep : Color(0.0f);
}

Color Scene::emission(uint32_t instance, uint32_t prim, uint32_t material, float bu, float bv, const Vec3& wo) const {
    SurfaceAttribs at;
    at.instance = instance, at.prim = prim, at.bu = bu, at.bv = bv;
    // A light sample is seen with the probability a ray would keep the hit (the cut-out), so its
    // emission is the kept hit's emission times that probability: the unscaled program emission.
    ShaderResult res = run_program(material, at, wo, ShaderRay{}, ShaderOutputs::Emission);
    return is_finite(res.emission) ? res.emission : Color(0.0f);
}

float Scene::program_keep(uint32_t instance, uint32_t prim, float bu, float bv, const Vec3& dir) const {
    SurfaceAttribs at;
    at.instance = instance, at.prim = prim, at.bu = bu, at.bv = bv;
    // Embree's filter does not know the ray's kind: the cut-out is the one a camera ray sees, as in
    // program_bsdf for camera rays (a transparency keyed on Light Path's ray kinds is not honoured).
    uint32_t material = meshes_[instances_[instance].mesh].materials[prim];
    return transparency_keep(run_program(material, at, -dir, ShaderRay{}, ShaderOutputs::Transparency));
}

}  // namespace smis
