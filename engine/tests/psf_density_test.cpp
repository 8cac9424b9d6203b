// Path-space filtering's density model (integrators/psf_density.h) against the BSDF's own pdf: the
// vectorised SMIS denominator must be the same sum of area-measure densities as Bsdf::pdf gives.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/rng.h"
#include "integrators/psf_density.h"

namespace smis {
namespace {

Lobe lobe_of(LobeKind kind, float alpha = 0.0f, FresnelMode fresnel = FresnelMode::None, float eta = 1.5f) {
    Lobe l;
    l.kind = kind;
    l.alpha = alpha;
    l.fresnel = fresnel;
    l.eta = eta;
    l.weight = Color(0.7f, 0.5f, 0.3f);
    l.f0 = Color(0.9f, 0.6f, 0.5f);
    return l;
}

struct Case {
    std::string name;
    std::vector<Lobe> lobes;
    TechniqueDensity::Kind kind;  // for wo above both normals
};

std::vector<Case> cases() {
    using K = LobeKind;
    return {
        {"Lambert", {lobe_of(K::Diffuse)}, TechniqueDensity::Model},
        {"PrincipledDiffuseSpecularSheen",
         {lobe_of(K::PrincipledDiffuse, 0.25f), lobe_of(K::Microfacet, 0.16f, FresnelMode::Dielectric), lobe_of(K::Sheen)},
         TechniqueDensity::Model},
        {"GlossySharp", {lobe_of(K::Microfacet, 1e-3f)}, TechniqueDensity::Model},
        {"Glossy0p01", {lobe_of(K::Microfacet, 0.01f)}, TechniqueDensity::Model},
        {"Glossy0p3", {lobe_of(K::Microfacet, 0.3f)}, TechniqueDensity::Model},
        {"GlossyRough", {lobe_of(K::Microfacet, 1.0f)}, TechniqueDensity::Model},
        {"MetalAndCoatSameAlpha",
         {lobe_of(K::Microfacet, 0.2f, FresnelMode::Schlick), lobe_of(K::Microfacet, 0.2f, FresnelMode::Dielectric)},
         TechniqueDensity::Model},
        {"DiffuseMirrorGlass",  // Dirac lobes have no density
         {lobe_of(K::Diffuse), lobe_of(K::Microfacet, 0.0f), lobe_of(K::Dielectric, 0.0f)},
         TechniqueDensity::Model},
        {"MirrorOnly", {lobe_of(K::Microfacet, 0.0f)}, TechniqueDensity::Zero},
        {"RoughGlass", {lobe_of(K::Diffuse), lobe_of(K::Dielectric, 0.2f)}, TechniqueDensity::General},
        {"Clearcoat", {lobe_of(K::PrincipledDiffuse, 0.25f), lobe_of(K::Clearcoat, 0.01f)}, TechniqueDensity::General},
        {"TwoAlphas", {lobe_of(K::Microfacet, 0.1f), lobe_of(K::Microfacet, 0.4f)}, TechniqueDensity::General},
    };
}

Vec3 random_direction(Rng& rng) {
    float z = 1.0f - 2.0f * rng.next_float(), phi = 2.0f * kPi * rng.next_float();
    float r = std::sqrt(std::max(0.0f, 1.0f - z * z));
    return {r * std::cos(phi), r * std::sin(phi), z};
}

// A technique at a random point with a shading normal tilted away from the geometric one.
struct RandomTechnique {
    Vec3 p, wo;
    Bsdf bsdf;
};
RandomTechnique random_technique(const Case& c, Rng& rng) {
    Vec3 ng = random_direction(rng);
    Vec3 ns = normalize(ng + random_direction(rng) * 0.3f);
    Bsdf b(Frame(ns), ng);
    for (const Lobe& l : c.lobes) b.add(l);
    Vec3 p(rng.next_float() * 2.0f - 1.0f, rng.next_float() * 2.0f - 1.0f, rng.next_float() * 2.0f - 1.0f);
    return {p, random_direction(rng), b};
}

// The reference: Bsdf::pdf in solid angle, times |cos theta_z| / d^2.
float reference_density(const RandomTechnique& t, const Vec3& z, const Vec3& z_ng) {
    Vec3 d = z - t.p;
    float d2 = length_sq(d);
    Vec3 w = d / std::sqrt(d2);
    return t.bsdf.pdf(t.wo, w) * absdot(w, z_ng) / d2;
}

void expect_close(float model, float reference, const std::string& what) {
    EXPECT_NEAR(model, reference, 2e-4f * std::fabs(reference) + 1e-7f) << what;
}

TEST(PsfDensity, ModelMatchesBsdfPdfForEveryLobeMixture) {
    Rng rng(7, 3);
    for (const Case& c : cases()) {
        int nonzero = 0, checked = 0;
        for (int trial = 0; trial < 400; ++trial) {
            RandomTechnique t = random_technique(c, rng);
            TechniqueDensity m = TechniqueDensity::of(t.bsdf, t.p, t.wo);
            bool above = dot(t.wo, t.bsdf.frame().n) > 0.0f;
            if (!above && c.kind != TechniqueDensity::General) {
                EXPECT_EQ(m.kind, TechniqueDensity::Zero) << c.name << ": wo under the shading normal";
            } else {
                EXPECT_EQ(m.kind, c.kind) << c.name;
            }
            if (m.kind == TechniqueDensity::General) continue;
            for (int k = 0; k < 20; ++k) {
                // Half of the targets near the reflection lobe, so sharp GGX peaks are exercised.
                Vec3 dir = k % 2 ? random_direction(rng)
                                 : normalize(reflect(t.wo, t.bsdf.frame().n) + random_direction(rng) * 0.05f);
                Vec3 z = t.p + dir * (0.2f + 3.0f * rng.next_float());
                Vec3 z_ng = random_direction(rng);
                float ref = reference_density(t, z, z_ng);
                expect_close(m.area_density(z, z_ng), ref, c.name);
                nonzero += ref > 0.0f;
                ++checked;
            }
        }
        if (c.kind == TechniqueDensity::Model) {
            EXPECT_GT(nonzero, checked / 10) << c.name << ": the test saw too few non-zero densities";
        }
    }
}

// The vectorised sum over a pixel's techniques (any count, Model and General mixed) is the sum of
// the references.
TEST(PsfDensity, DensitySumIsTheSumOfTheTechniquesDensities) {
    Rng rng(11, 5);
    std::vector<Case> all = cases();
    DensitySum sum;
    for (int trial = 0; trial < 200; ++trial) {
        const int n = 1 + trial % 37;  // across the vector widths and the scratch growth
        std::vector<RandomTechnique> ts;
        sum.reset();
        for (int j = 0; j < n; ++j) {
            ts.push_back(random_technique(all[rng.next_u32() % all.size()], rng));
            TechniqueDensity m = TechniqueDensity::of(ts.back().bsdf, ts.back().p, ts.back().wo);
            if (m.kind == TechniqueDensity::General) {
                sum.add_general(ts.back().p, ts.back().bsdf, ts.back().wo);
            } else {
                sum.add(m);
            }
        }
        for (int k = 0; k < 5; ++k) {
            Vec3 z(rng.next_float() * 4.0f - 2.0f, rng.next_float() * 4.0f - 2.0f, rng.next_float() * 4.0f - 2.0f);
            Vec3 z_ng = random_direction(rng);
            double ref = 0.0;
            for (const RandomTechnique& t : ts) ref += reference_density(t, z, z_ng);
            float got = sum(z, z_ng);
            EXPECT_NEAR(got, ref, 1e-3 * ref + 1e-6) << "n " << n;
        }
    }
}

}  // namespace
}  // namespace smis
