// The commonest textured material, lowered out of the shader program VM: a node tree that is only an
// Image Texture (flat projection, Vector from the UV map) into the Color of one Diffuse BSDF whose
// other inputs are constant. Its BSDF at a hit is the closure's lobe with its weight times the
// texture at the hit's UV, as Material::inputs' texture path builds it, bit for bit the lobe the
// program would push (Diffuse: weight = vmax(colour x w, 0), Lambert or Oren-Nayar by Roughness).
//
// The program stays the material's: every other reader (emission, cut-out, holdout, spectral
// templates, path-space filtering's records) runs it as before, and the path tracer's shading takes
// the lowered form only where the hit's frame is the one the program's context would rebuild
// (Scene::hit_has_program_frame: a static triangle mesh with a UV map).
#pragma once
#include <memory>
#include <optional>

#include "scene/bsdf.h"
#include "scene/texture.h"
#include "shading/shader_program.h"

namespace smis {

struct ImageClosure {
    Lobe lobe;  // the closure's lobe with a white colour: weight = the closure's Weight
    std::shared_ptr<const Texture> texture;

    // What Material::program_bsdf makes of the program's result at a hit with this UV (frame on the
    // closure normal, as Scene::program_bsdf turns it).
    Bsdf bsdf(const Frame& frame, const Vec3& ng, bool backfacing, Point2 uv) const {
        Bsdf b(frame, ng);
        Lobe l = lobe;
        // Weight x vmax(c, 0) is vmax(c x weight, 0) for a weight > 0, -0 and overflows included.
        l.weight *= vmax(texture->lookup(uv).rgb, Color(0.0f));
        if (backfacing && lobe_backface_inverts_eta(l)) l.eta = 1.0f / l.eta;
        b.add(l);
        return b;
    }
};

// The lowered form of `program`, or nothing when the program is not exactly that pattern: one
// Texture Coordinate op writing only its UV, one flat Image Texture reading it and a Diffuse reading
// the texture's Color, with a finite Weight > 0, a constant Roughness and no Normal input, run per
// hit; any other per-hit op, closure or input keeps the program. Textures with negative texels keep
// it too (Texture::non_negative).
std::optional<ImageClosure> lower_image_closure(const ShaderProgram& program);

}  // namespace smis
