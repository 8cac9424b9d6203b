// Hair: curves as Embree round Catmull-Rom curves (Cycles 3.4's "3D Curves", its default shape):
// the geometry, its hits and what shader programs read at them.
//
// Cycles' thick curves (kernel/geom/curve.h, curve_shader_setup) shade a hit with the normal
// N = normalize(P - C(u)), C the curve's centre line at the hit's parameter u, N also the geometric
// normal, and dPdu = C'(u) the tangent the hair closures align to. A ray leaving a curve ignores the
// whole curve it starts on (Cycles' self-intersection skip compares curves, not segments), so the
// transmission of a hair closure leaves through the fibre; here Embree's filter drops hits on a
// curve one of whose segments' tubes holds the ray's origin, which only rays starting on it do.
#include <cstring>

#include "scene/scene.h"
#include "shading/procedural_noise.h"

namespace smis {
namespace {

inline Vec3 load3(const float* p) { return {p[0], p[1], p[2]}; }

// The uniform Catmull-Rom basis (Embree's and Cycles') at u of the segment p[0..3] (x, y, z, radius
// each): its centre, derivative and radius.
struct CurvePoint {
    Vec3 centre, tangent;
    float radius;
};
inline CurvePoint catmull_rom(const float* p, float u) {
    float u2 = u * u, u3 = u2 * u;
    const float b[4] = {0.5f * (-u3 + 2.0f * u2 - u), 0.5f * (3.0f * u3 - 5.0f * u2 + 2.0f),
                        0.5f * (-3.0f * u3 + 4.0f * u2 + u), 0.5f * (u3 - u2)};
    const float d[4] = {0.5f * (-3.0f * u2 + 4.0f * u - 1.0f), 0.5f * (9.0f * u2 - 10.0f * u),
                        0.5f * (-9.0f * u2 + 8.0f * u + 1.0f), 0.5f * (3.0f * u2 - 2.0f * u)};
    CurvePoint c{Vec3(0.0f), Vec3(0.0f), 0.0f};
    for (int k = 0; k < 4; ++k) {
        Vec3 q = load3(p + 4 * k);
        c.centre += q * b[k];
        c.tangent += q * d[k];
        c.radius += p[4 * k + 3] * b[k];
    }
    return c;
}

// Sub-segments of the centre line the self-intersection test measures distances to.
constexpr int kSelfTestPieces = 8;

inline float distance_sq_to_piece(const Vec3& o, const Vec3& a, const Vec3& b) {
    Vec3 ab = b - a;
    float len2 = length_sq(ab);
    float t = len2 > 0.0f ? clampf(dot(o - a, ab) / len2, 0.0f, 1.0f) : 0.0f;
    return length_sq(o - (a + ab * t));
}

// Whether `o` lies in (or on) the tube of segment p[0..3]: within 1.05 x its largest radius of the
// centre line, measured to a polyline of kSelfTestPieces pieces. Rays that start on another
// segment's surface are at least a radius away from it, unless the strands touch.
bool inside_segment_tube(const float* p, const Vec3& o) {
    float r = std::max(p[7], p[11]) * 1.05f + 1e-7f;
    Vec3 p1 = load3(p + 4), p2 = load3(p + 8);
    // Early out: the segment lies within its chord's bounding sphere widened by its control points.
    Vec3 mid = (p1 + p2) * 0.5f;
    float reach = 0.5f * length(p2 - p1) + length(load3(p) - p1) + length(load3(p + 12) - p2) + r;
    if (length_sq(o - mid) > reach * reach) return false;
    Vec3 prev = p1;
    for (int k = 1; k <= kSelfTestPieces; ++k) {
        Vec3 next = catmull_rom(p, float(k) / kSelfTestPieces).centre;
        if (distance_sq_to_piece(o, prev, next) <= r * r) return true;
        prev = next;
    }
    return false;
}

}  // namespace

uint32_t Scene::add_curves(const float* points, size_t np, const int32_t* curve_offsets, size_t nc, uint32_t material,
                           uint32_t first_curve, const float* curve_uvs, const std::vector<AttributeInput>& attributes) {
    if (committed_) throw std::logic_error("scene already committed");
    if (material >= materials_.size()) throw std::invalid_argument("curves with an unknown material");
    for (const AttributeInput& a : attributes)
        if (!a.corners || a.dims < 1 || a.dims > 4) throw std::invalid_argument("curve attribute '" + a.name + "' is malformed");
    Mesh mesh;
    mesh.curves = true;
    mesh.first_curve = first_curve;
    auto finite_or_zero = [](float v) { return std::isfinite(v) ? v : 0.0f; };
    if (curve_uvs)
        for (size_t c = 0; c < nc; ++c)
            mesh.curve_uvs.push_back({finite_or_zero(curve_uvs[2 * c]), finite_or_zero(curve_uvs[2 * c + 1])});
    for (const AttributeInput& a : attributes) {
        MeshAttribute attr{attribute_id(a.name), a.dims, {}};
        for (size_t k = 0; k < nc * size_t(a.dims); ++k) attr.corners.push_back(finite_or_zero(a.corners[k]));
        mesh.attributes.push_back(std::move(attr));
    }
    for (size_t c = 0; c < nc; ++c) {
        int32_t first = curve_offsets[c], end = curve_offsets[c + 1];
        bool usable = first >= 0 && end <= int32_t(np) && end - first >= 2;
        for (int32_t i = first; usable && i < end; ++i)
            for (int k = 0; k < 4; ++k) usable = usable && std::isfinite(points[4 * size_t(i) + k]);
        if (!usable) {
            mesh.dropped++;
            continue;
        }
        // Control points: the first and last point doubled (Cycles' Catmull-Rom curves), so segment
        // j of the curve runs between its points j and j + 1 with control points base + j .. + 3.
        uint32_t base = uint32_t(mesh.curve_points.size() / 4);
        // Hair Info's Intercept and Length as Cycles exports them (blender/curves.cpp): the length
        // of the polyline through the points so far, over the whole.
        std::vector<float> along(size_t(end - first), 0.0f);
        for (int32_t i = first + 1; i < end; ++i)
            along[size_t(i - first)] = along[size_t(i - first - 1)] +
                                       length(load3(&points[4 * size_t(i)]) - load3(&points[4 * size_t(i - 1)]));
        const float total = along.back();
        auto push = [&](int32_t i) {
            for (int k = 0; k < 4; ++k) mesh.curve_points.push_back(points[4 * size_t(i) + k]);
            mesh.curve_points.back() = std::max(mesh.curve_points.back(), 0.0f);
            mesh.curve_intercepts.push_back(total > 0.0f ? along[size_t(i - first)] / total : 0.0f);
        };
        push(first);
        for (int32_t i = first; i < end; ++i) push(i);
        push(end - 1);
        for (int32_t j = 0; j < end - first - 1; ++j) {
            mesh.indices.push_back(base + uint32_t(j));
            mesh.materials.push_back(material);
            mesh.segment_curves.push_back(first_curve + uint32_t(c));
            mesh.segment_lengths.push_back(total);
        }
    }
    meshes_.push_back(std::move(mesh));
    return uint32_t(meshes_.size() - 1);
}

void Scene::set_curve_ribbons(uint32_t mesh, uint32_t subdivisions) {
    if (committed_) throw std::logic_error("scene already committed");
    if (mesh >= meshes_.size() || !meshes_[mesh].curves) throw std::invalid_argument("ribbons of a mesh that is no hair");
    meshes_[mesh].ribbon_rate = std::min(subdivisions, 64u) + 1;
}

// Cycles' ribbon normal (curve_shader_setup, CURVE_RIBBON): across the strip facing the ray, the
// tube's normal at the same offset v in -1..1 (Embree's flat-curve v), so ribbons shade as round
// fibres: N = v B - sqrt(1 - v^2) normalize(T x B), B = normalize(T x wo).
// `across` (if given): the unit direction across the strip, B.
inline Vec3 ribbon_normal(const Vec3& tangent, const Vec3& wo, float v, Vec3* across = nullptr) {
    Vec3 b = cross(tangent, wo);
    if (!(length_sq(b) > 0.0f)) b = Frame(wo).s;
    b = normalize(b);
    if (across) *across = b;
    float cosine = std::sqrt(std::max(1.0f - v * v, 0.0f));
    return normalize(b * v - normalize(cross(tangent, b)) * cosine);
}

void Scene::flatten_curves(Mesh& mesh, const Transform& to_world) {
    // Radii scale with the transform's mean scale (Cycles' uniform-scale approximation).
    float scale = std::cbrt(std::fabs(to_world.determinant3()));
    for (size_t i = 0; i + 3 < mesh.curve_points.size(); i += 4) {
        Vec3 p = to_world.point(load3(&mesh.curve_points[i]));
        mesh.curve_points[i] = p.x, mesh.curve_points[i + 1] = p.y, mesh.curve_points[i + 2] = p.z;
        mesh.curve_points[i + 3] *= scale;
    }
}

void Scene::build_curve_geometry(RTCScene target, Mesh& mesh, unsigned id, uint32_t visibility) {
    RTCGeometry geom = rtcNewGeometry(device_, mesh.ribbon_rate ? RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE
                                                                : RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE);
    if (mesh.ribbon_rate) rtcSetGeometryTessellationRate(geom, float(mesh.ribbon_rate));
    rtcSetGeometryMask(geom, visibility);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, mesh.curve_points.data(), 0,
                               4 * sizeof(float), mesh.curve_points.size() / 4);
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, mesh.indices.data(), 0,
                               sizeof(uint32_t), mesh.indices.size());
    mesh.owner = this;
    rtcSetGeometryUserData(geom, &mesh);
    rtcSetGeometryIntersectFilterFunction(geom, curve_self_filter);
    rtcSetGeometryOccludedFilterFunction(geom, curve_self_filter);
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(target, geom, id);
    rtcReleaseGeometry(geom);
}

namespace {

// Whether `o` lies in the tube of any segment of the curve that segment `prim` belongs to: Cycles'
// self skip compares the hit's curve (curve_segments[prim].prim), not its segment, so a ray leaving
// a strand passes every segment of it (a bent strand's other arm, the neighbour of the segment it
// starts on near their joint). A curve's segments have consecutive first control points
// (add_curves); the next curve's first segment starts 4 further on (its doubled end points), which
// ends the walk. The segment hit is tested first: the common case, a ray leaving it.
bool inside_curve_of(const std::vector<float>& points, const std::vector<uint32_t>& indices, size_t prim,
                     const Vec3& o) {
    auto tube = [&](size_t s) { return inside_segment_tube(&points[4 * size_t(indices[s])], o); };
    if (tube(prim)) return true;
    for (size_t s = prim; s > 0 && indices[s - 1] + 1 == indices[s];)
        if (tube(--s)) return true;
    for (size_t s = prim; s + 1 < indices.size() && indices[s] + 1 == indices[s + 1];)
        if (tube(++s)) return true;
    return false;
}

}  // namespace

void Scene::curve_self_filter(const RTCFilterFunctionNArguments* args) {
    const Mesh& mesh = *static_cast<const Mesh*>(args->geometryUserPtr);
    RTCRayN* ray = const_cast<RTCRayN*>(args->ray);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        Vec3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i));
        if (inside_curve_of(mesh.curve_points, mesh.indices, prim, o)) args->valid[i] = 0;
    }
}

// The hit's centre point and tangent in world space (a moving instance: where Embree placed it at the
// ray's time, so the normal P - C(u) is the tube's; the shader context rebuilds it at the shutter's
// centre, whose normal's angle about the tangent it keeps).
void Scene::fill_curve_hit(const Ray& ray, const RTCRayHit& rh, uint32_t instance, SurfaceHit* hit) const {
    const Instance& inst = instances_[instance];
    const Mesh& mesh = meshes_[inst.mesh];
    uint32_t prim = rh.hit.primID;
    CurvePoint c = catmull_rom(&mesh.curve_points[4 * size_t(mesh.indices[prim])], rh.hit.u);
    if (!inst.identity) {
        Transform at = inst.to_world;
        if (!inst.motion.empty()) rtcGetGeometryTransform(inst.geometry, rh.ray.time, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &at.m[0][0]);
        c.centre = at.point(c.centre);
        c.tangent = at.vector(c.tangent);
    }
    Vec3 p = ray.o + ray.d * rh.ray.tfar;
    // The normal stands for the geometric one too (Ng = N), on tubes and ribbons alike.
    Vec3 n;
    if (mesh.ribbon_rate) {
        // A ribbon faces the ray, shaded with the faked round normal; Cycles' Ng = -D serves no
        // BSDF on curves (bsdf.h takes the closure's N for Ng on curves, "ribbons darken
        // otherwise"), so the faked normal stands for both, as the tube's normal does.
        n = ribbon_normal(length_sq(c.tangent) > 0.0f ? normalize(c.tangent) : Vec3(0.0f, 0.0f, 1.0f),
                          normalize(-ray.d), clampf(rh.hit.v, -1.0f, 1.0f));
    } else {
        n = p - c.centre;
        n = length_sq(n) > 0.0f ? normalize(n) : -ray.d;
    }
    if (!is_finite(n)) n = Vec3(0.0f, 0.0f, 1.0f);
    hit->t = rh.ray.tfar;
    hit->p = p;
    hit->ng = n;
    hit->ns = n;
    hit->material = mesh.materials[prim];
    hit->holdout = inst.holdout;
    hit->light = materials_[hit->material].emissive() ? kStrandEmission : -1;
    if (kWithTextures) {
        hit->attr.object_color = inst.object_color;
        if (!mesh.curve_uvs.empty()) hit->attr.uv = mesh.curve_uvs[mesh.input_curve(prim)];
        if (programs_) {
            // The normal as an angle about the tangent, in the tangent's own frame (a ribbon: its
            // v across the strip): with the segment and u, all curve_shader_context needs.
            Frame f(length_sq(c.tangent) > 0.0f ? normalize(c.tangent) : Vec3(0.0f, 0.0f, 1.0f));
            hit->attr.instance = instance;
            hit->attr.prim = prim;
            hit->attr.bu = rh.hit.u;
            hit->attr.bv = mesh.ribbon_rate ? clampf(rh.hit.v, -1.0f, 1.0f) : std::atan2(dot(n, f.t), dot(n, f.s));
        }
    }
}

ShaderContext Scene::curve_shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray) const {
    ShaderContext ctx;
    ctx.scene = this;
    ctx.ray = ray;
    const Instance& inst = instances_[at.instance];
    const Mesh& mesh = meshes_[inst.mesh];
    ctx.instance = at.instance;
    ctx.prim = at.prim;
    ctx.bu = at.bu;
    ctx.bv = at.bv;
    CurvePoint c = catmull_rom(&mesh.curve_points[4 * size_t(mesh.indices[at.prim])], at.bu);
    if (!inst.identity) {
        c.centre = inst.to_world.point(c.centre);
        c.tangent = inst.to_world.vector(c.tangent);
        c.radius *= std::cbrt(std::fabs(inst.to_world.determinant3()));
    }
    Frame f(length_sq(c.tangent) > 0.0f ? normalize(c.tangent) : Vec3(0.0f, 0.0f, 1.0f));
    Vec3 n;
    ctx.I = wo;
    if (mesh.ribbon_rate) {
        // The strip facing the ray at v across it; N (and Ng, as fill_curve_hit) the faked normal.
        Vec3 across;
        n = ribbon_normal(f.n, wo, at.bv, &across);
        ctx.P = c.centre + across * (at.bv * c.radius);
        ctx.backfacing = false;
        ctx.Ng = ctx.N = n;
    } else {
        n = f.s * std::cos(at.bv) + f.t * std::sin(at.bv);
        ctx.P = c.centre + n * c.radius;
        ctx.backfacing = dot(wo, n) < 0.0f;
        ctx.Ng = ctx.N = ctx.backfacing ? -n : n;
    }
    // Hair Info's Random: Cycles' ATTR_STD_CURVE_RANDOM, hash_uint2_to_float(curve, 0) of the curve's
    // index in its object's hair (blender/curves.cpp, ExportCurveSegments and export_hair_curves).
    ctx.curve = true;
    ctx.curve_random = shading::hash_uint2_to_float(mesh.segment_curves[at.prim], 0u);
    // Intercept and Thickness: the segment's end points' values at u, linearly (Cycles'
    // curve_attribute_float on curve keys and curve_thickness: 2 x the radius, not the Catmull-Rom
    // radius the tube has); the segment runs between control points k + 1 and k + 2.
    const size_t k = mesh.indices[at.prim];
    const float u = at.bu;
    ctx.curve_intercept = (1.0f - u) * mesh.curve_intercepts[k + 1] + u * mesh.curve_intercepts[k + 2];
    ctx.curve_length = mesh.segment_lengths[at.prim];
    float radius = (1.0f - u) * mesh.curve_points[4 * (k + 1) + 3] + u * mesh.curve_points[4 * (k + 2) + 3];
    if (!inst.identity) radius *= std::cbrt(std::fabs(inst.to_world.determinant3()));
    ctx.curve_thickness = 2.0f * radius;
    ctx.N_object = inst.identity ? normalize(inst.to_world.normal_to_object(n)) : normalize(inst.to_object.vector(n));
    ctx.dPdu = c.tangent;
    if (!mesh.curve_uvs.empty()) {
        ctx.uv = mesh.curve_uvs[mesh.input_curve(at.prim)];
        ctx.has_uv = true;
    }
    set_object_inputs(inst, &ctx);
    float dist = length(ctx.P - camera_.origin());
    float footprint = camera_.pixel_footprint(std::max(dist, 1e-6f));
    if (!(footprint > 0.0f) || !std::isfinite(footprint)) footprint = 1e-4f;
    Frame nf(ctx.N);
    ctx.dPdx = nf.s * footprint;
    ctx.dPdy = nf.t * footprint;
    return ctx;
}

}  // namespace smis
