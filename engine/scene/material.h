// A material as the add-on translates it from Blender's shader nodes: Cycles' flattened closure list
// (lobes with their mix weights already multiplied in) plus emitted radiance.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "scene/bsdf.h"
#include "scene/image_closure.h"
#include "scene/texture.h"
#include "shading/shader_program.h"

namespace smis {

// What spectral rendering adds to a material (Blender: material.smis); ignored by RGB rendering,
// which uses the RGB closures as they are.
struct MaterialSpectral {
    std::string emission_spectrum = "RGB";  // RGB, BLACKBODY, D65, A, F2, F10, F11 (spectral/spectra.h)
    float emission_temperature = 6500.0f;   // K, for BLACKBODY
    // NONE or a measured conductor (Au, Ag, Cu, Al): replaces the Fresnel of the Microfacet lobes
    // without a dielectric Fresnel (Glossy, Principled metallic); their colour still multiplies it.
    std::string metal = "NONE";
    // NONE, ABBE (Cauchy law through the lobe's IOR as n_d and `abbe` as V_d) or a Sellmeier glass
    // name from the table: makes the smooth Dielectric lobes (Glass, Principled transmission) dispersive.
    std::string dispersion = "NONE";
    float abbe = 40.0f;
    bool has_spectral_content() const {
        return emission_spectrum != "RGB" || metal != "NONE" || dispersion != "NONE";
    }
};

// What a hit knows about its surface beyond position and normals, for textured materials.
struct SurfaceAttribs {
    Point2 uv;                 // the mesh's render UV map at the hit (0, 0 without one)
    Color object_color{1.0f};  // Object Info > Color of the instance
    // Which triangle of which instance, and where on it (Embree's barycentrics): shader programs
    // rebuild everything else they read from these (Scene::shader_context).
    uint32_t instance = 0, prim = 0;
    float bu = 0.0f, bv = 0.0f;
};

// A lobe colour that is not constant: an image texture's Color at the hit's UV and/or the object's
// colour, multiplying the lobe's weight, or its f0 for a metal (Principled Base Color).
struct LobeInput {
    std::shared_ptr<const Texture> texture;
    bool object_color = false;
    bool to_f0 = false;
    bool varies() const { return texture || object_color; }
};

// Probability that a hit on a surface whose program produced `res` is kept (1 - its grey
// transparency); the cut-out filter and the BSDF agree on it.
float transparency_keep(const ShaderResult& res);

struct Material {
    std::string name;
    std::vector<Lobe> lobes;
    Color emission{0.0f};  // radiance, emitted from both sides like Cycles' mesh emission
    // Emission Color fed by an Image Texture: the radiance at a point is emission x its RGB.
    std::shared_ptr<const Texture> emission_texture;
    Color emission_at(Point2 uv) const {
        return kWithTexturedEmission && emission_texture ? emission * emission_texture->lookup(uv).rgb : emission;
    }
    MaterialSpectral spectral;
    // Volume: the medium inside the closed mesh (Scene::medium id), -1 for none. A material with
    // no surface shader (only a Volume output) is an index-matched boundary rays pass straight
    // through, as in Cycles.
    int32_t medium = -1;
    bool pass_through = false;
    // Empty (every lobe constant: no per-hit work), or one entry per lobe.
    std::vector<LobeInput> inputs;
    // Tangent-space normal map (Normal Map node on an image texture) and its Strength.
    std::shared_ptr<const Texture> normal_map;
    float normal_strength = 1.0f;
    // Principled Alpha: constant, times an image texture's alpha when linked. Below 1 the surface
    // is a stochastic cut-out (Scene keeps a hit with probability alpha).
    float alpha = 1.0f;
    std::shared_ptr<const Texture> alpha_texture;
    // The material's node tree compiled for per-hit evaluation (shading/shader_program.h), or null
    // when every closure input is constant: then `lobes` and `emission` hold the folded result.
    // With a program, `lobes` holds its lobe templates (kinds and indices, for spectral rendering).
    std::shared_ptr<const ShaderProgram> program;
    // The program lowered out of the VM when it is only an image texture into one closure's colour
    // (scene/image_closure.h; set by Scene::sanitize): the path tracer's shading uses it where the
    // hit allows, every other reader the program.
    std::optional<ImageClosure> image_closure;
    bool cutout() const { return alpha < 1.0f || alpha_texture || (program && program->may_be_transparent()); }
    float alpha_at(Point2 uv) const { return alpha_texture ? alpha * alpha_texture->lookup(uv).alpha : alpha; }
    bool emissive() const { return max_component(emission) > 0.0f || (program && program->may_emit()); }
    bool needs_uv() const {
        if (normal_map || alpha_texture || emission_texture || program) return true;
        for (const LobeInput& in : inputs)
            if (in.texture) return true;
        return false;
    }

    // The BSDF at a hit. `frame` faces the incoming direction (Cycles flips the normal of back-facing
    // hits); a back-facing hit on glass means the ray is leaving the medium, so eta is inverted.
    Bsdf make_bsdf(const Frame& frame, const Vec3& ng, bool backfacing, const SurfaceAttribs& attr = {}) const {
        if (!kWithTextures || prepared_) return Bsdf(frame, ng, backfacing ? back_ : front_);
        return build_bsdf(frame, ng, backfacing, attr);
    }
    // make_bsdf() into *out, copying only the lobes a prepared material has.
    void make_bsdf_into(Bsdf* out, const Frame& frame, const Vec3& ng, bool backfacing,
                        const SurfaceAttribs& attr = {}) const {
        if (!kWithTextures || prepared_) out->assign(frame, ng, backfacing ? back_ : front_);
        else *out = build_bsdf(frame, ng, backfacing, attr);
    }

    // Called once the lobes are final (Scene::add_material): when no lobe varies per hit, the two
    // lobe lists (front and back side) are built here once, so that make_bsdf() at every vertex of
    // every path only copies them instead of re-running Bsdf::add's checks.
    void prepare() {
        prepared_ = false;
        if (program) return;
        for (const LobeInput& in : inputs)
            if (in.varies()) return;
        front_ = build_bsdf(Frame(), Vec3(0, 0, 1), false, {});
        back_ = build_bsdf(Frame(), Vec3(0, 0, 1), true, {});
        prepared_ = true;
    }

    // The BSDF, emission and shading normal a program produced at a hit (`res`): Transparent BSDF
    // weights T become a cut-out (the grey part g = min(T), which Scene's filter lets through with
    // probability g, so the kept hit's closures are divided by 1 - g) and a straight-through lobe of
    // the coloured rest (T - g) / (1 - g), as the constant path does in the add-on.
    // (The emission of such a hit is Scene::program_emission's.)
    Bsdf program_bsdf(const ShaderResult& res, const Frame& frame, const Vec3& ng, bool backfacing) const;

private:
    // Out of line: make_bsdf() at every vertex should not pay for this path's register pressure.
    [[gnu::noinline]] Bsdf build_bsdf(const Frame& frame, const Vec3& ng, bool backfacing, const SurfaceAttribs& attr) const {
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
            if (backfacing && lobe_backface_inverts_eta(lobe))
                lobe.eta = 1.0f / lobe.eta;
            bsdf.add(lobe);
        }
        return bsdf;
    }
    bool prepared_ = false;
    Bsdf front_, back_;
};

}  // namespace smis
