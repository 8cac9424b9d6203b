// What a shader program can read at a surface point: Cycles' ShaderData, for the node evaluator.
// Filled by Scene::shader_context() only for materials that have a program (constant materials never
// build one).
#pragma once
#include <cstring>

#include "core/math.h"
#include "core/sampling.h"

namespace smis {

class Scene;

// The ray that found the point, for the Light Path node (Cycles' path flags and depths).
struct ShaderRay {
    bool camera = true, shadow = false, diffuse = false, glossy = false, singular = false,
         reflection = false, transmission = false, volume_scatter = false;
    float length = 0.0f;
    int depth = 0, diffuse_depth = 0, glossy_depth = 0, transmission_depth = 0, transparent_depth = 0;
    // A key of the path (0: none), for closures that draw numbers per path and bounce as Cycles'
    // shading-point LCG does (the Principled Hair BSDF's longitudinal sample, lobes/principled_hair.h).
    uint32_t path_key = 0;
};

// ShaderRay::path_key of a path from its first ray (a hash of the ray's bits: no random numbers
// drawn, so the path's stream is the same with or without it), never 0.
inline uint32_t shader_path_key(const Vec3& o, const Vec3& d) {
    uint32_t h = 0x9e3779b9u;
    for (float f : {o.x, o.y, o.z, d.x, d.y, d.z}) {
        uint32_t b;
        std::memcpy(&b, &f, sizeof b);
        h = (h ^ b) * 0x85ebca6bu;
        h ^= h >> 13;
        h *= 0xc2b2ae35u;
        h ^= h >> 16;
    }
    return h ? h : 1u;
}

struct ShaderContext {
    Vec3 P;            // world position
    Vec3 N;            // shading normal facing the incoming ray (Cycles flips back-facing normals)
    Vec3 Ng;           // geometric normal, same side as N
    Vec3 I;            // towards the viewer (the incoming ray reversed)
    bool backfacing = false;
    // Surface offsets of one pixel footprint, for the Bump node (Cycles' dP.dx / dP.dy, here from the
    // ray length and the camera's pixel spread, since the engine carries no ray differentials).
    Vec3 dPdx, dPdy;
    Point2 duvdx, duvdy;
    // The smooth normal in object space, unflipped and unnormalised (interpolated corner normals; the
    // unit geometric normal on flat meshes): what Cycles' tangent-space Normal Map combines.
    Vec3 N_object;
    Vec3 dPdu;         // the default UV map's u direction on the triangle (tangents), 0 without UVs
    float tangent_sign = 1.0f;  // -1 where the UV map is mirrored (the bitangent flips)
    // Where attributes come from: the scene, the instance and the triangle with its barycentrics.
    const Scene* scene = nullptr;
    uint32_t instance = 0, prim = 0;
    float bu = 0.0f, bv = 0.0f;
    Point2 uv;         // the default (active render) UV map
    bool has_uv = false;
    // Object: world -> object transform, location, Object Info outputs, texture space (Generated).
    Transform to_object;
    Transform to_world;
    Vec3 object_location;
    Color object_color{1.0f};
    float object_alpha = 1.0f, object_random = 0.0f, object_index = 0.0f, material_index = 0.0f;
    Vec3 texspace_location{0.0f}, texspace_size{1.0f};
    // Hair (Scene::curve_shader_context): Hair Info's Is Strand, Random (per curve, as Cycles'),
    // Intercept (0 at the root, 1 at the tip), Length and Thickness.
    bool curve = false;
    float curve_random = 0.0f, curve_intercept = 0.0f, curve_length = 0.0f, curve_thickness = 0.0f;
    ShaderRay ray;
    // The World (Cycles' background shader data, EnvironmentLight::context): P is the direction the
    // ray leaves the scene in, N = Ng = I = -P, no object; Texture Coordinate reads it differently.
    bool background = false;
};

}  // namespace smis
