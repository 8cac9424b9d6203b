// A material as the add-on translates it from Blender's shader nodes: Cycles' flattened closure list
// (lobes with their mix weights already multiplied in) plus emitted radiance.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "scene/bsdf.h"
#include "scene/texture.h"

namespace smis {

// What a hit knows about its surface beyond position and normals, for textured materials.
struct SurfaceAttribs {
    Point2 uv;                 // the mesh's render UV map at the hit (0, 0 without one)
    Color object_color{1.0f};  // Object Info > Color of the instance
};

// A lobe colour that is not constant: an image texture's Color at the hit's UV and/or the object's
// colour, multiplying the lobe's weight, or its f0 for a metal (Principled Base Color).
struct LobeInput {
    std::shared_ptr<const Texture> texture;
    bool object_color = false;
    bool to_f0 = false;
    bool varies() const { return texture || object_color; }
};

struct Material {
    std::string name;
    std::vector<Lobe> lobes;
    Color emission{0.0f};  // radiance, emitted from both sides like Cycles' mesh emission
    // Empty (every lobe constant: no per-hit work), or one entry per lobe.
    std::vector<LobeInput> inputs;
    // Tangent-space normal map (Normal Map node on an image texture) and its Strength.
    std::shared_ptr<const Texture> normal_map;
    float normal_strength = 1.0f;
    // Principled Alpha: constant, times an image texture's alpha when linked. Below 1 the surface
    // is a stochastic cut-out (Scene keeps a hit with probability alpha).
    float alpha = 1.0f;
    std::shared_ptr<const Texture> alpha_texture;
    bool cutout() const { return alpha < 1.0f || alpha_texture; }
    float alpha_at(Point2 uv) const { return alpha_texture ? alpha * alpha_texture->lookup(uv).alpha : alpha; }
    bool emissive() const { return max_component(emission) > 0.0f; }
    bool needs_uv() const {
        if (normal_map || alpha_texture) return true;
        for (const LobeInput& in : inputs)
            if (in.texture) return true;
        return false;
    }

    // The BSDF at a hit. `frame` faces the incoming direction (Cycles flips the normal of back-facing
    // hits); a back-facing hit on glass means the ray is leaving the medium, so eta is inverted.
    Bsdf make_bsdf(const Frame& frame, const Vec3& ng, bool backfacing, const SurfaceAttribs& attr = {}) const {
        Bsdf bsdf(frame, ng);
        for (size_t i = 0; i < lobes.size(); ++i) {
            Lobe lobe = lobes[i];
            if (!inputs.empty() && inputs[i].varies()) {
                const LobeInput& in = inputs[i];
                Color c = in.texture ? in.texture->lookup(attr.uv).rgb : Color(1.0f);
                if (in.object_color) c *= attr.object_color;
                if (in.to_f0) lobe.f0 = vmin(vmax(lobe.f0 * c, Color(0.0f)), Color(1.0f));
                else lobe.weight *= vmax(c, Color(0.0f));
            }
            if (backfacing && (lobe.kind == LobeKind::Dielectric || lobe.fresnel == FresnelMode::Dielectric))
                lobe.eta = 1.0f / lobe.eta;
            bsdf.add(lobe);
        }
        return bsdf;
    }
};

}  // namespace smis
