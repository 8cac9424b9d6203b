// A back-facing hit inverts eta only for glass (Dielectric lobes), as Cycles 3.4 does for its glass
// closures. The Principled specular layer (Microfacet, FresnelMode::Dielectric) keeps its IOR from
// both sides: inverted, it met total internal reflection beyond 42 degrees inside closed meshes
// (F = 1 on top of the diffuse base), and light bouncing inside a Principled cube with Transmission
// gained energy (gltf-blender-io 14_transmission.blend: +2.4% over Cycles, +6-11% on the cube).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/material.h"

using namespace smis;

namespace {
Material with_lobe(LobeKind kind, FresnelMode fresnel) {
    Material m;
    Lobe l;
    l.kind = kind;
    l.fresnel = fresnel;
    l.weight = Color(0.8f);
    l.alpha = 0.16f;
    l.eta = 1.5f;
    l.f0 = Color(0.04f);
    m.lobes.push_back(l);
    m.prepare();
    return m;
}
}  // namespace

TEST(BackFacing, PrincipledSpecularLayerKeepsItsIor) {
    Material m = with_lobe(LobeKind::Microfacet, FresnelMode::Dielectric);
    Vec3 n(0, 0, 1);
    // 60 degrees from the normal, mirror reflection: beyond the critical angle of 1 / 1.5.
    Vec3 wo = normalize(Vec3(std::sin(1.0472f), 0.0f, std::cos(1.0472f)));
    Vec3 wi(-wo.x, -wo.y, wo.z);
    Color front = m.make_bsdf(Frame(n), n, false).eval(wo, wi);
    Color back = m.make_bsdf(Frame(n), n, true).eval(wo, wi);
    EXPECT_GT(front.x, 0.0f);
    EXPECT_NEAR(back.x, front.x, 1e-6f * front.x);
}

TEST(BackFacing, GlassSeesTheInvertedIor) {
    Material m = with_lobe(LobeKind::Dielectric, FresnelMode::None);
    Vec3 n(0, 0, 1);
    Vec3 wo = normalize(Vec3(std::sin(1.0472f), 0.0f, std::cos(1.0472f)));
    Vec3 wt = normalize(Vec3(-0.3f, 0.0f, -1.0f));  // a refraction direction
    // From inside (back-facing) at 60 degrees: total internal reflection, nothing refracts.
    EXPECT_EQ(m.make_bsdf(Frame(n), n, true).eval(wo, wt).x, 0.0f);
    EXPECT_GT(m.make_bsdf(Frame(n), n, false).eval(wo, wt).x, 0.0f);
}
