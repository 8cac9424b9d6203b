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

// A random-walk sphere (principled exit, anisotropic) and a thin Christensen-Burley slab on a white
// floor, lit by a rectangle above and a point light behind the slab (seen through it); mean free
// paths of the order of the objects, so the walks matter (their diffuse fallback renders darker:
// image mean 7% below, z -10 in GreyWalkAndDiskConvergeToRgb). The sphere's Principled Subsurface
// has a retro-reflection lobe beside its Subsurface one, the slab's Subsurface Scattering has its
// Subsurface lobe alone (a Dirac BSDF: the exit is the path's first non-specular vertex).
inline std::shared_ptr<Scene> subsurface_scene(const Color& albedo, const Color& radius, int w = 16, int h = 16) {
    auto s = std::make_shared<Scene>();
    add_box(*s, {-1.4f, -1.4f, -0.1f}, {1.4f, 1.4f, 0.0f}, s->add_material(diffuse(Color(0.7f))));
    add_sphere(*s, 0.45f, 16, 32,
               s->add_material(subsurface_material(albedo, radius, 0.3f, true)), true,
               {-0.5f, 0.0f, 0.45f});
    add_box(*s, {0.15f, -0.04f, 0.0f}, {0.9f, 0.04f, 0.8f},
            s->add_material(subsurface_material(albedo, radius * 0.5f, 0.0f, false, SubsurfaceMethod::ChristensenBurley)));
    s->add_light(area_light(1.5f, 60.0f, {0.0f, 0.0f, 2.2f}).hidden_from_camera());
    s->add_light(point_light(30.0f, 0.1f, {0.5f, 0.3f, 0.4f}));
    s->set_camera(camera_along_y({0.0f, -3.2f, 0.6f}, w, h, 30.0f));
    s->commit();
    return s;
}

}  // namespace smis::testing
