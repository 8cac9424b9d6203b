// Light sampling: chi-square of every light's sample() against its pdf(), agreement between the
// pdf reported by sample(), pdf() and intersect(), and Cycles' units.
#include <gtest/gtest.h>

#include "scene/area_spread.h"
#include "core/sampling.h"
#include "scene/lights.h"
#include "stats.h"

using namespace smis;
using namespace smis::stats;

namespace {

Transform placed(const Vec3& pos, float rot_x = 0.0f) {
    Transform t;
    float c = std::cos(rot_x), s = std::sin(rot_x);
    t.m[1][1] = c, t.m[1][2] = -s, t.m[2][1] = s, t.m[2][2] = c;
    t.m[0][3] = pos.x, t.m[1][3] = pos.y, t.m[2][3] = pos.z;
    return t;
}

struct Case {
    std::string name;
    std::shared_ptr<Light> light;
    Vec3 ref;
};

std::vector<Case> cases() {
    std::vector<Case> out;
    auto add = [&](const std::string& name, LightDesc d, const Vec3& ref) {
        out.push_back({name, std::shared_ptr<Light>(make_light(d)), ref});
    };
    LightDesc area;
    area.type = "AREA";
    area.power = 100.0f;
    // (Positioned so no light edge is tangent to a histogram cell border, where the quadrature of
    // the pdf would miss a sliver that the samples do reach.)
    area.to_world = placed({0.3f, -0.2f, 1.05f}, 0.4f);
    for (std::string shape : {"SQUARE", "RECTANGLE", "DISK", "ELLIPSE"}) {
        area.shape = shape;
        area.size = 2.0f;
        area.size_y = 0.8f;
        add("area_" + shape, area, {0, 0, 0});
    }
    // Spread: a rectangle samples only the part of itself that can reach the point (30 degrees: a
    // small part off its centre; 100 degrees: clipped on one side), a disk all of itself.
    area.shape = "RECTANGLE";
    area.spread = 30.0f * kPi / 180.0f;
    add("area_RECTANGLE_spread30", area, {0.6f, 0.1f, 0.0f});
    area.spread = 100.0f * kPi / 180.0f;
    add("area_RECTANGLE_spread100", area, {0.9f, -0.3f, 0.0f});
    area.shape = "DISK";
    area.spread = 40.0f * kPi / 180.0f;
    add("area_DISK_spread40", area, {0.4f, 0.0f, 0.0f});
    LightDesc point;
    point.type = "POINT";
    point.power = 50.0f;
    point.radius = 0.6f;
    point.to_world = placed({0.2f, 0.1f, 1.0f});
    add("point_radius", point, {0, 0, 0});
    LightDesc spot = point;
    spot.type = "SPOT";
    spot.spot_size = 2.0f;
    spot.spot_blend = 0.5f;
    add("spot_radius", spot, {0.3f, 0.4f, 0.0f});
    LightDesc sun;
    sun.type = "SUN";
    sun.strength = 3.0f;
    sun.angle = 1.0f;
    sun.to_world = placed({0, 0, 0}, 0.5f);
    add("sun_disc", sun, {0, 0, 0});
    out.push_back({"world", std::make_shared<WorldLight>(Color(1.0f)), {0, 0, 0}});
    out.push_back({"triangle", std::make_shared<TriangleLight>(Vec3(-1, -1, 1), Vec3(1.5f, -0.5f, 0.6f),
                                                               Vec3(0, 1, 1.3f), Color(2.0f)),
                   {0.1f, 0.0f, -0.2f}});
    return out;
}

}  // namespace

TEST(Lights, SamplesFollowTheirPdf) {
    auto all = cases();
    const double alpha = sidak_significance(0.01, static_cast<int>(all.size()));
    for (const Case& c : all) {
        auto sample = [&](Rng& rng) {
            LightSample s = c.light->sample(c.ref, {rng.next_float(), rng.next_float()});
            return s.valid() ? DirSample::valid(s.wi) : DirSample::invalid();
        };
        auto pdf = [&](const Vec3& w) { return c.light->pdf(c.ref, w); };
        Chi2Options opt;
        opt.grid = SphereGrid{40, 80};
        Chi2Result r = chi2_test_directions(sample, pdf, 400000, opt);
        EXPECT_TRUE(r.passes(alpha)) << c.name << ": " << r.summary();
        EXPECT_NEAR(r.pdf_integral, double(r.n_valid) / r.n_samples, 2e-2) << c.name;
    }
}

TEST(Lights, SamplePdfAgreesWithPdfAndIntersect) {
    for (const Case& c : cases()) {
        Rng rng(7, 11);
        for (int i = 0; i < 2000; ++i) {
            LightSample s = c.light->sample(c.ref, {rng.next_float(), rng.next_float()});
            if (!s.valid()) continue;
            float p = c.light->pdf(c.ref, s.wi);
            ASSERT_NEAR(p, s.pdf, 2e-3f * s.pdf) << c.name;
            if (dynamic_cast<TriangleLight*>(c.light.get())) continue;  // geometry: hit through the BVH
            LightHit h;
            ASSERT_TRUE(c.light->intersect(Ray{c.ref, s.wi, 0.0f, kInf}, &h)) << c.name;
            ASSERT_NEAR(h.pdf, s.pdf, 2e-3f * s.pdf) << c.name;
            for (int k = 0; k < 3; ++k) ASSERT_NEAR(h.L[k], s.L[k], 1e-4f * (1.0f + s.L[k])) << c.name;
        }
    }
}

TEST(Lights, CyclesUnits) {
    // Area light: radiance P / (4 A); disk area pi D^2 / 4 (measured in Cycles 3.4, FINDINGS).
    LightDesc area;
    area.type = "AREA";
    area.power = 100.0f;
    area.to_world = placed({0, 0, 1});
    area.shape = "DISK";
    area.size = 1.0f;
    auto disk = make_light(area);
    LightSample s = disk->sample({0, 0, 0}, {0.5f, 0.5f});
    EXPECT_NEAR(s.L.x, 100.0f / (4.0f * kPi / 4.0f), 1e-3f);
    // Point light with radius r: a disc facing the receiver with radiance P / (4 pi) / (pi r^2),
    // so the irradiance at distance d is I / (d^2 + r^2) (as measured in Cycles).
    LightDesc point;
    point.type = "POINT";
    point.power = 1000.0f;
    point.radius = 1.0f;
    point.to_world = placed({0, 0, 2});
    auto p = make_light(point);
    Rng rng(3, 5);
    MeanEstimator e;
    for (int i = 0; i < 200000; ++i) {
        LightSample ls = p->sample({0, 0, 0}, {rng.next_float(), rng.next_float()});
        e.add(ls.valid() ? ls.L.x * ls.wi.z / ls.pdf : 0.0);
    }
    double expected = 1000.0 / (4.0 * kPi) / (4.0 + 1.0);
    EXPECT_GT(z_test_mean(e, expected).p_value, 1e-3) << e.mean() << " vs " << expected;
    // Spot: the extra cos to the axis inside the cone (Cycles 3.4 spot_attenuation).
    LightDesc spot;
    spot.type = "SPOT";
    spot.power = 1000.0f;
    spot.spot_size = kPi / 2;
    spot.spot_blend = 0.0f;
    spot.to_world = placed({0, 0, 2});  // a Blender spot shines along its local -Z: down
    auto sp = make_light(spot);
    Vec3 ref(2.0f * std::tan(30.0f * kPi / 180.0f), 0, 0);
    LightSample ss = sp->sample(ref, {0.5f, 0.5f});
    float d2 = length_sq(Vec3(0, 0, 2) - ref);
    EXPECT_NEAR(ss.L.x, 1000.0f / (4 * kPi) * std::cos(30.0f * kPi / 180.0f) / d2, 1e-3f);
    // Sun: strength spread over the disc's solid angle.
    LightDesc sun;
    sun.type = "SUN";
    sun.strength = 3.0f;
    sun.angle = 10.0f * kPi / 180.0f;
    auto su = make_light(sun);
    LightSample us = su->sample({0, 0, 0}, {0.3f, 0.3f});
    float omc = 1.0f - std::cos(5.0f * kPi / 180.0f);
    EXPECT_NEAR(us.L.x, 3.0f / (2 * kPi * omc), 1e-2f);
}

// Cycles' spread normalisation keeps the light's power: the attenuation weighted by cos sin over the
// hemisphere integrates to the Lambertian light's 1/2 at every spread (and spread 180 is no cone).
TEST(Lights, AreaSpreadKeepsThePower) {
    for (float degrees : {1.0f, 10.0f, 30.0f, 90.0f, 150.0f, 179.0f}) {
        AreaSpread s = AreaSpread::from_angle(degrees * kPi / 180.0f);
        ASSERT_TRUE(s.active());
        const int n = 200000;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            double x = (i + 0.5) * 0.5 * kPi / n;
            sum += s.attenuation(float(std::cos(x))) * std::cos(x) * std::sin(x) * 0.5 * kPi / n;
        }
        EXPECT_NEAR(sum, 0.5, 2e-3) << degrees << " degrees";
        // Nothing beyond half the spread.
        float h = 0.5f * std::max(degrees, 1.0f) * kPi / 180.0f;
        EXPECT_EQ(s.attenuation(std::cos(std::min(h * 1.01f, 0.5f * kPi - 1e-3f))), 0.0f) << degrees;
        EXPECT_GT(s.attenuation(std::cos(h * 0.99f)), 0.0f) << degrees;
    }
    EXPECT_FALSE(AreaSpread::from_angle(kPi).active());
}

// A sphere light's intersect() first rejects rays whose line passes far from its centre, without a
// square root or division (PointLight::misses_by_far). That shortcut may only skip rays the disk test
// would reject: every ray aimed at a point of the disk (up to 0.985 of the radius, off the rim where
// rounding decides) must still hit it, for small lights far from the origin and from the ray too.
TEST(Lights, PointLightShortcutKeepsEveryRayThatReachesTheDisk) {
    Rng rng(3, 5);
    int rays = 0, lost = 0;
    for (float scale : {1e-2f, 1.0f, 1e2f})
        for (float radius : {1e-3f, 0.1f, 1.0f})
            for (float distance : {1.5f, 10.0f, 300.0f}) {
                LightDesc d;
                d.type = "POINT";
                d.power = 10.0f;
                d.radius = radius * scale;
                const Vec3 pos = Vec3(0.3f, -0.7f, 1.1f) * (2.0f * scale);
                d.to_world = placed(pos);
                auto light = make_light(d);
                for (int i = 0; i < 200; ++i) {
                    // From a point `distance` radii away towards a point of the disk facing it.
                    Vec3 dir = sample_uniform_sphere({rng.next_float(), rng.next_float()});
                    Vec3 o = pos + dir * (distance * d.radius);
                    Frame f(dir);
                    Point2 u = sample_uniform_disk_concentric({rng.next_float(), rng.next_float()});
                    // Half the rays anywhere within 0.99 of the radius, half at 0.985 of it.
                    Vec3 off = f.s * u.x + f.t * u.y;
                    if (i % 2) off = normalize(off) * 0.995f;
                    Vec3 target = pos + off * (0.99f * d.radius);
                    Ray r{o, normalize(target - o), 0.0f, kInf};
                    LightHit h;
                    ++rays;
                    if (!light->intersect(r, &h)) ++lost;
                }
            }
    EXPECT_EQ(lost, 0) << "of " << rays << " rays aimed at the disk";
}
