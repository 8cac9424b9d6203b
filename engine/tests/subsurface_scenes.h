// Subsurface materials for the tests (subsurface_test, spectral_subsurface_test).
#pragma once
#include "scene/subsurface_closure.h"
#include "test_scenes.h"

namespace smis::testing {

// A Subsurface Scattering closure (Principled Subsurface when `principled`) of weight and albedo
// `albedo`, radius per channel and anisotropy g, as the material's lobes.
inline Material subsurface_material(const Color& albedo, const Color& radius, float g, bool principled = false,
                                    SubsurfaceMethod method = SubsurfaceMethod::RandomWalk) {
    SubsurfaceClosure c;
    c.weight = albedo;
    c.albedo = albedo;
    c.radius = radius;
    c.anisotropy = g;
    c.method = method;
    c.principled = principled;
    Lobe lobes[3];
    Material m;
    m.lobes.assign(lobes, lobes + subsurface_lobes(c, lobes));
    return m;
}

}  // namespace smis::testing
