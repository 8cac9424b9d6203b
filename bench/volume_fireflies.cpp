// Where single scattering's rare bright samples came from, and what solid-angle sampling of
// rectangle lights (integrators/volume.cpp, issue 22) changed: both estimators (RectangleSampling
// kSolidAngle / kArea) on a replica of scenes/volume_planes.blend (its fog, boxes and six aimed
// rectangle lights; pinhole camera rays through 32 x 32 pixel centres, single scattering only).
//
//   cmake --build build --target volume_fireflies && build/engine/tests/volume_fireflies
//   valgrind --tool=callgrind build/engine/tests/volume_fireflies --gtest_filter='*Cost'   (MODE=area: old)
//
// RelMSE: relMSE (eps 0.01, bench/metrics.py's) at 16 spp over 32 repetitions against the new
// estimator at REF_SPP (default 4096) per pixel. Outliers: the share of the summed relative squared
// error from samples above 50x their pixel's mean, by technique (u_technique < 0.5: equiangular)
// and by the light chosen. Cost / RenderCost: work to count with callgrind (single_scattering's
// inclusive instructions per call, and its share of a whole 48 x 48, 8 spp render).
#include <gtest/gtest.h>

#include <cstdlib>

#include "integrators/volume.h"
#include "test_scenes.h"

using namespace smis;
using namespace smis::testing;

namespace {

// A rectangle light at `loc` whose emitting side (-Z) faces `target`, as build_scenes.py's aim().
LightDesc aimed_light(const Vec3& loc, const Vec3& target, float sx, float sy, float power, const Color& color) {
    LightDesc l;
    l.type = "AREA";
    l.shape = "RECTANGLE";
    l.size = sx;
    l.size_y = sy;
    l.power = power;
    l.color = color;
    Vec3 z = normalize(loc - target);
    Vec3 up = std::fabs(z.z) > 0.99f ? Vec3(0.0f, 1.0f, 0.0f) : Vec3(0.0f, 0.0f, 1.0f);
    Vec3 x = normalize(cross(up, z)), y = cross(z, x);
    for (int r = 0; r < 3; ++r) l.to_world.m[r][0] = x[r], l.to_world.m[r][1] = y[r], l.to_world.m[r][2] = z[r];
    l.to_world.m[0][3] = loc.x, l.to_world.m[1][3] = loc.y, l.to_world.m[2][3] = loc.z;
    return l;
}

const Vec3 kEye{0.0f, -5.4f, 1.45f};
constexpr int kW = 32, kH = 32;

std::shared_ptr<Scene> volume_planes_replica() {
    auto s = std::make_shared<Scene>();
    uint32_t white = s->add_material(diffuse(Color(0.8f)));
    Material boundary;
    boundary.name = "fog";
    boundary.pass_through = true;
    Medium fog;
    fog.sigma_s = Color(0.9f, 0.85f, 0.8f) * 0.35f;
    fog.sigma_a = (Color(1.0f) - Color(0.8f, 0.9f, 1.0f)) * 0.15f;
    boundary.medium = s->add_medium(fog);
    add_box(*s, {-2.6f, -2.6f, -0.3f}, {2.6f, 2.6f, 3.4f}, s->add_material(boundary));
    add_box(*s, {-2.4f, -2.4f, -0.1f}, {2.4f, 2.4f, 0.0f}, white);
    add_box(*s, {-2.4f, 2.3f, 0.0f}, {2.4f, 2.4f, 3.0f}, white);
    add_box(*s, {-1.0f, 0.6f, 0.0f}, {-0.7f, 0.9f, 2.2f}, white);
    add_box(*s, {0.8f, 1.0f, 0.0f}, {1.1f, 1.3f, 1.8f}, white);
    add_box(*s, {-0.25f, -0.65f, 0.0f}, {0.45f, 0.05f, 0.7f}, white);  // the cube, unrotated
    s->add_light(aimed_light({-1.2f, -0.6f, 2.6f}, {-0.6f, 0.3f, 0.0f}, 0.8f, 0.5f, 60.0f, {1.0f, 0.9f, 0.75f}));
    s->add_light(aimed_light({1.3f, 0.4f, 2.7f}, {0.9f, 0.6f, 0.0f}, 1.6f, 0.08f, 50.0f, {0.75f, 0.85f, 1.0f}));
    s->add_light(aimed_light({-2.0f, 1.3f, 1.2f}, {0.0f, 0.9f, 0.5f}, 0.12f, 0.9f, 40.0f, {1.0f, 0.7f, 0.6f}));
    s->add_light(aimed_light({0.3f, 1.8f, 2.2f}, {0.2f, 0.0f, 0.0f}, 0.6f, 0.6f, 35.0f, {0.8f, 1.0f, 0.8f}));
    s->add_light(aimed_light({1.8f, -1.0f, 0.6f}, {0.0f, 0.5f, 0.3f}, 0.5f, 0.05f, 25.0f, {1.0f, 0.95f, 0.9f}));
    s->add_light(aimed_light({0.0f, 0.2f, 3.0f}, {0.1f, 0.1f, 0.0f}, 1.0f, 0.3f, 45.0f, {0.9f, 0.9f, 1.0f}));
    CameraDesc c = camera_at(kEye, 48, 48);
    c.to_world.m[1][1] = 0.0f, c.to_world.m[1][2] = -1.0f;  // looking along +Y
    c.to_world.m[2][1] = 1.0f, c.to_world.m[2][2] = 0.0f;
    c.lens = 32.0f;
    s->set_camera(c);
    s->commit();
    return s;
}

// The pixel centres' rays of a 32 mm lens on a 36 mm sensor, with their media.
struct PixelRays {
    std::vector<Ray> rays;
    std::vector<RayMedia> media;
    explicit PixelRays(const Scene& scene) : media(kW * kH) {
        const float tan_half = 18.0f / 32.0f;
        for (int p = 0; p < kW * kH; ++p) {
            float sx = ((p % kW + 0.5f) / kW * 2.0f - 1.0f) * tan_half, sy = (1.0f - (p / kW + 0.5f) / kH * 2.0f) * tan_half;
            rays.push_back(Ray{kEye, normalize(Vec3(sx, 1.0f, sy)), 0.0f, kInf});
            SurfaceHit hit;
            intersect_through(scene, rays.back(), kNoMedium, &hit, &media[p]);
        }
    }
};

const RectangleSampling kModes[] = {RectangleSampling::kSolidAngle, RectangleSampling::kArea};
const char* const kModeNames[] = {"solid angle (new)", "area (before)"};

}  // namespace

TEST(VolumeFireflies, RelMSE) {
    auto scene = volume_planes_replica();
    PixelRays px(*scene);
    const int ref_spp = std::getenv("REF_SPP") ? std::atoi(std::getenv("REF_SPP")) : 4096;
    const int spp = 16, reps = 32;
    LocalCounters counters;
    auto estimate = [&](int p, RectangleSampling mode, int n, uint64_t seed) {
        Color sum(0.0f);
        for (int i = 0; i < n; ++i) {
            Rng rng(seed * 1000003 + p, i);
            sum += single_scattering(*scene, px.rays[p], px.media[p], rng, counters, false, mode);
        }
        return sum * (1.0f / n);
    };
    std::vector<Color> ref(kW * kH);
    for (int p = 0; p < kW * kH; ++p) ref[p] = estimate(p, RectangleSampling::kSolidAngle, ref_spp, 99);
    double rel[2] = {0.0, 0.0};
    for (int r = 0; r < reps; ++r)
        for (int k = 0; k < 2; ++k)
            for (int p = 0; p < kW * kH; ++p) {
                Color e = estimate(p, kModes[k], spp, 1 + r);
                for (int c = 0; c < 3; ++c)
                    rel[k] += (e[c] - ref[p][c]) * (e[c] - ref[p][c]) / (ref[p][c] * ref[p][c] + 0.01) / (3.0 * kW * kH * reps);
            }
    for (int k = 0; k < 2; ++k)
        std::printf("%-18s relMSE %.4g at %d spp (reference %d spp, %d repetitions)\n", kModeNames[k], rel[k], spp, ref_spp, reps);
    std::printf("relMSE before / after: %.2f\n", rel[1] / rel[0]);
}

TEST(VolumeFireflies, Outliers) {
    auto scene = volume_planes_replica();
    PixelRays px(*scene);
    const DiscreteDistribution& selection = scene->light_selection();
    LocalCounters counters;
    const int n = 2048;
    for (int k = 0; k < 2; ++k) {
        double total = 0.0, tail[2] = {0.0, 0.0};
        long count[2] = {0, 0};
        std::vector<int> by_light(scene->lights().size(), 0);
        for (int p = 0; p < kW * kH; ++p) {
            std::vector<double> v(n);
            double mean = 0.0;
            for (int i = 0; i < n; ++i) {
                Rng rng(p, i);
                v[i] = single_scattering(*scene, px.rays[p], px.media[p], rng, counters, false, kModes[k]).y;
                mean += v[i] / n;
            }
            for (int i = 0; i < n; ++i) {
                double e = (v[i] - mean) * (v[i] - mean) / (mean * mean + 1e-2);
                total += e;
                if (!(v[i] > 50.0 * mean)) continue;
                Rng rng(p, i);  // single_scattering's first two numbers: the light, the technique
                float u_select = rng.next_float(), u_technique = rng.next_float();
                int technique = u_technique < 0.5f ? 0 : 1;
                tail[technique] += e;
                ++count[technique];
                ++by_light[selection.sample(u_select)];
            }
        }
        std::printf("%-18s summed relative squared error %.4g; from samples > 50x their pixel's mean: equiangular "
                    "%.3f (%ld samples), distance %.3f (%ld samples); their lights:",
                    kModeNames[k], total, tail[0] / total, count[0], tail[1] / total, count[1]);
        for (int c : by_light) std::printf(" %d", c);
        std::printf("\n");
    }
}

TEST(VolumeFireflies, Cost) {
    auto scene = volume_planes_replica();
    PixelRays px(*scene);
    const char* mode = std::getenv("MODE");
    RectangleSampling rectangles = mode && std::string(mode) == "area" ? RectangleSampling::kArea : RectangleSampling::kSolidAngle;
    LocalCounters counters;
    double sum = 0.0;
    for (int p = 0; p < kW * kH; ++p)
        for (int i = 0; i < 64; ++i) {
            Rng rng(p, i);
            sum += single_scattering(*scene, px.rays[p], px.media[p], rng, counters, false, rectangles).y;
        }
    std::printf("%d calls, mean %g\n", kW * kH * 64, sum / (kW * kH * 64));
}

TEST(VolumeFireflies, RenderCost) {
    RenderSettings s;
    s.samples = 8;
    s.max_bounces = 1;
    s.filter = PixelFilterKind::Box;
    s.filter_width = 1.0f;
    s.threads = 1;
    auto img = render(volume_planes_replica(), s);
    double sum = 0.0;
    for (float v : img) sum += v;
    std::printf("image sum %g\n", sum);
}
