// A material as the add-on translates it from Blender's shader nodes: Cycles' flattened closure list
// (lobes with their mix weights already multiplied in) plus emitted radiance.
#pragma once
#include <string>
#include <vector>

#include "scene/bsdf.h"

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

struct Material {
    std::string name;
    std::vector<Lobe> lobes;
    Color emission{0.0f};  // radiance, emitted from both sides like Cycles' mesh emission
    MaterialSpectral spectral;
    // Volume: the medium inside the closed mesh (Scene::medium id), -1 for none. A material with
    // no surface shader (only a Volume output) is an index-matched boundary rays pass straight
    // through, as in Cycles.
    int32_t medium = -1;
    bool pass_through = false;
    bool emissive() const { return max_component(emission) > 0.0f; }

    // The BSDF at a hit. `frame` faces the incoming direction (Cycles flips the normal of back-facing
    // hits); a back-facing hit on glass means the ray is leaving the medium, so eta is inverted.
    Bsdf make_bsdf(const Frame& frame, const Vec3& ng, bool backfacing) const {
        Bsdf bsdf(frame, ng);
        for (Lobe lobe : lobes) {
            if (backfacing && (lobe.kind == LobeKind::Dielectric || lobe.fresnel == FresnelMode::Dielectric))
                lobe.eta = 1.0f / lobe.eta;
            bsdf.add(lobe);
        }
        return bsdf;
    }
};

}  // namespace smis
