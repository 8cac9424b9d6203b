// The Sampler's named dimension groups (core/sampler.h): with the stratified pattern a name's value
// depends on the pixel, the seed and the sample index only, whatever else was drawn before it.
#include <gtest/gtest.h>

#include <vector>

#include "core/sampler.h"
#include "integrators/path_tracing.h"
#include "integrators/psf_rgb.h"
#include "integrators/psf_spectral.h"
#include "integrators/restir.h"
#include "integrators/tiles.h"
#include "test_scenes.h"

namespace smis {
namespace {

// Every named value of one sample, and the first numbers of its stream.
struct Drawn {
    Point2 pixel, lens, light_point, direction;
    float time = 0, light_choice = 0, lobe = 0;
    std::vector<float> stream;
};

void expect_same(const Drawn& a, const Drawn& b, uint32_t s) {
    EXPECT_EQ(a.pixel.x, b.pixel.x) << "sample " << s;
    EXPECT_EQ(a.pixel.y, b.pixel.y) << "sample " << s;
    EXPECT_EQ(a.lens.x, b.lens.x) << "sample " << s;
    EXPECT_EQ(a.lens.y, b.lens.y) << "sample " << s;
    EXPECT_EQ(a.time, b.time) << "sample " << s;
    EXPECT_EQ(a.light_choice, b.light_choice) << "sample " << s;
    EXPECT_EQ(a.light_point.x, b.light_point.x) << "sample " << s;
    EXPECT_EQ(a.light_point.y, b.light_point.y) << "sample " << s;
    EXPECT_EQ(a.lobe, b.lobe) << "sample " << s;
    EXPECT_EQ(a.direction.x, b.direction.x) << "sample " << s;
    EXPECT_EQ(a.direction.y, b.direction.y) << "sample " << s;
    EXPECT_EQ(a.stream, b.stream) << "sample " << s;
}

// Two integrators that ask for the same names in different orders, one with extra draws between
// them (an extra next_float(), next_2d(), a name asked twice), get the same value for every name,
// and the same stream: a draw in one place cannot shift another's.
TEST(Sampler, NamedGroupsDoNotShiftEachOtherOrTheStream) {
    const PixelSampler pixel(3, 5, 7, /*stratified=*/true, /*lens=*/true, /*time=*/true);
    for (uint32_t s = 0; s < 16; ++s) {
        Drawn a, b;
        Sampler in_order = pixel.start(s);
        a.pixel = in_order.pixel();
        a.lens = in_order.lens();
        a.time = in_order.time();
        const LightNumbers la = in_order.first_light();
        a.light_choice = la.choice, a.light_point = la.point;
        a.lobe = in_order.first_lobe();
        a.direction = in_order.first_direction();
        for (int i = 0; i < 10; ++i) a.stream.push_back(in_order.next_float());

        Sampler shuffled = pixel.start(s);
        b.stream.push_back(shuffled.next_float());
        b.direction = shuffled.first_direction();
        const Point2 extra = shuffled.next_2d();
        b.stream.insert(b.stream.end(), {extra.x, extra.y});
        b.lens = shuffled.lens();
        shuffled.first_light();  // asked twice: the same numbers
        const LightNumbers lb = shuffled.first_light();
        b.light_choice = lb.choice, b.light_point = lb.point;
        b.stream.push_back(shuffled.next_float());
        b.lobe = shuffled.first_lobe();
        b.time = shuffled.time();
        b.pixel = shuffled.pixel();
        while (b.stream.size() < a.stream.size()) b.stream.push_back(shuffled.next_float());
        expect_same(a, b, s);

        // Each name owns its group: no two names give the same numbers.
        EXPECT_NE(a.pixel.x, a.lens.x);
        EXPECT_NE(a.light_point.x, a.direction.x);
        EXPECT_NE(a.light_choice, a.lobe);
        EXPECT_NE(a.time, a.pixel.x);
    }
}

// The sample's own stream carries nothing of the names: its first numbers are the PCG stream's,
// whatever names were asked before.
// Every named group of a stratified pixel sample is point s of its group's scrambled Sobol set
// (stratified::sample_2d), whatever the order asked: the Sampler reverses the sample index once for
// all its groups (Sampler::sample_reversed_), and that must be index s's reversal.
TEST(Sampler, NamedGroupsArePointSOfTheirStratifiedSets) {
    const PixelSampler pixel(7, 3, 5, true, true, true);
    for (uint32_t s : {0u, 1u, 2u, 3u, 5u, 17u, 64u, 255u, 1000u, 65537u, 0x80000001u}) {
        float px[2], lens[2], time[2], choices[2], light[2], dir[2];
        stratified::sample_2d(s, pixel.key(), sample_groups::kPixel, px);
        stratified::sample_2d(s, pixel.key(), sample_groups::kLens, lens);
        stratified::sample_2d(s, pixel.key(), sample_groups::kTime, time);
        stratified::sample_2d(s, pixel.key(), sample_groups::kFirstChoices, choices);
        stratified::sample_2d(s, pixel.key(), sample_groups::kFirstLightPoint, light);
        stratified::sample_2d(s, pixel.key(), sample_groups::kFirstDirection, dir);
        Sampler sampler = pixel.start(s);
        const Point2 d = sampler.first_direction();
        const LightNumbers l = sampler.first_light();
        const float lobe = sampler.first_lobe();
        const float t = sampler.time();
        const Point2 le = sampler.lens();
        const Point2 p = sampler.pixel();
        const float got[11] = {p.x, p.y, le.x, le.y, t, l.choice, lobe, l.point.x, l.point.y, d.x, d.y};
        const float want[11] = {px[0], px[1], lens[0], lens[1], time[0], choices[0], choices[1],
                                light[0], light[1], dir[0], dir[1]};
        for (int k = 0; k < 11; ++k) EXPECT_EQ(got[k], want[k]) << "sample " << s << " value " << k;
    }
}

TEST(Sampler, TheStreamIsPlain) {
    const uint32_t fx = 11, fy = 2, seed = 3;
    const PixelSampler pixel(fx, fy, seed, true, false, false);
    for (uint32_t s = 0; s < 16; ++s) {
        Sampler sampler = pixel.start(s);
        sampler.first_light();
        sampler.first_direction();
        Rng reference = pixel_sample_rng(fx, fy, s, seed);
        for (int i = 0; i < 6; ++i) EXPECT_EQ(sampler.rng().next_float(), reference.next_float()) << "sample " << s;
    }
}

// Path-space filtering's extra light and BSDF samples at x1 ask the Sampler by name
// (VertexSampler::extra): with the stratified pattern, stratum `index` of their own groups (light
// choice, light point; lobe, direction), whatever was drawn before, and the stream is untouched;
// with the random pattern, the stream in the order asked.
TEST(Sampler, PathSpaceFilteringsExtraSamplesAskByName) {
    const uint32_t fx = 4, fy = 9, seed = 2;
    const PixelSampler pixel(fx, fy, seed, /*stratified=*/true, false, false);
    for (uint32_t s = 0; s < 8; ++s) {
        for (uint32_t index : {0u, 3u, 17u}) {
            Sampler sampler = pixel.start(s);
            sampler.next_float();  // an earlier draw shifts nothing
            const VertexSampler extra = VertexSampler::extra(sampler, index);
            float choice[2], point[2], lobe[2], dir[2];
            stratified::sample_2d(index, pixel.key(), sample_groups::kExtraLightChoice, choice);
            stratified::sample_2d(index, pixel.key(), sample_groups::kExtraLightPoint, point);
            stratified::sample_2d(index, pixel.key(), sample_groups::kExtraLobe, lobe);
            stratified::sample_2d(index, pixel.key(), sample_groups::kExtraDirection, dir);
            const LightNumbers l = extra.light();
            EXPECT_EQ(l.choice, choice[0]);
            EXPECT_EQ(l.point.x, point[0]);
            EXPECT_EQ(l.point.y, point[1]);
            EXPECT_EQ(extra.lobe(), lobe[0]);
            const Point2 d = extra.direction();
            EXPECT_EQ(d.x, dir[0]);
            EXPECT_EQ(d.y, dir[1]);
            EXPECT_EQ(extra.names(), nullptr);  // not the first vertex's names
            Rng reference = pixel_sample_rng(fx, fy, s, seed);
            reference.next_float();
            EXPECT_EQ(sampler.next_float(), reference.next_float()) << "sample " << s;
        }
    }
    const PixelSampler random(fx, fy, seed, /*stratified=*/false, false, false);
    Sampler sampler = random.start(1);
    Rng reference = pixel_sample_rng(fx, fy, 1, seed);
    const VertexSampler extra = VertexSampler::extra(sampler, 5);
    const LightNumbers l = extra.light();
    EXPECT_EQ(l.choice, reference.next_float());
    EXPECT_EQ(l.point.x, reference.next_float());
    EXPECT_EQ(l.point.y, reference.next_float());
    EXPECT_EQ(extra.lobe(), reference.next_float());
}

// A path vertex's numbers (VertexSampler): the camera path's first vertex gets the Sampler's named
// groups whatever was drawn from the stream before it, and the stream after it is untouched by
// them; every other vertex draws light choice, light point, lobe and direction from the stream in
// that order.
TEST(Sampler, TheFirstVertexAsksByNameAndOtherVerticesDrawTheStream) {
    for (bool stratified : {true, false}) {
        const PixelSampler pixel(4, 9, 1, stratified, false, false);
        for (uint32_t s = 0; s < 8; ++s) {
            Sampler named = pixel.start(s);
            const LightNumbers light = named.first_light();
            const float lobe = named.first_lobe();
            const Point2 dir = named.first_direction();

            Sampler sampler = pixel.start(s);
            Rng& stream = sampler.rng();
            if (stratified) stream.next_float();  // an integrator's extra draw before the first vertex
            Rng after = stream;
            const VertexSampler first(stream, &sampler);
            const LightNumbers l = first.light();
            const float lo = first.lobe();
            const Point2 d = first.direction();
            EXPECT_EQ(l.choice, light.choice) << "sample " << s;
            EXPECT_EQ(l.point.x, light.point.x) << "sample " << s;
            EXPECT_EQ(l.point.y, light.point.y) << "sample " << s;
            EXPECT_EQ(lo, lobe) << "sample " << s;
            EXPECT_EQ(d.x, dir.x) << "sample " << s;
            EXPECT_EQ(d.y, dir.y) << "sample " << s;
            if (stratified) {
                EXPECT_EQ(stream.next_float(), after.next_float()) << "sample " << s;
            }

            const VertexSampler later(stream);
            Rng reference = stream;
            const LightNumbers l2 = later.light();
            const float lo2 = later.lobe();
            const Point2 d2 = later.direction();
            const float drawn[6] = {l2.choice, l2.point.x, l2.point.y, lo2, d2.x, d2.y};
            for (float v : drawn) EXPECT_EQ(v, reference.next_float()) << "sample " << s;
        }
    }
}

// The random pattern keeps the numbers it had before the Sampler: every name draws from the
// sample's stream, in the order asked.
TEST(Sampler, TheRandomPatternDrawsNamesFromTheStreamInOrder) {
    const uint32_t fx = 3, fy = 5, seed = 7;
    const PixelSampler pixel(fx, fy, seed, /*stratified=*/false, true, true);
    for (uint32_t s = 0; s < 4; ++s) {
        Sampler sampler = pixel.start(s);
        Rng reference = pixel_sample_rng(fx, fy, s, seed);
        const Point2 p = sampler.pixel(), l = sampler.lens();
        const float t = sampler.time();
        const LightNumbers light = sampler.first_light();
        const float drawn[8] = {p.x, p.y, l.x, l.y, t, light.choice, light.point.x, light.point.y};
        for (float v : drawn) EXPECT_EQ(v, reference.next_float()) << "sample " << s;
        EXPECT_EQ(sampler.next_float(), reference.next_float());
    }
}

// The path tracer asks for its first vertex's numbers by name: an integrator that draws an
// extra number from the stream before the first vertex no longer shifts that vertex's light, lobe
// and direction numbers. At bounce limit 0 a camera path's radiance is its first vertex's alone (its
// light sample, and the emission its BSDF sample finds), so with the named groups it is the same
// with or without the extra draw. The same paths drawing from the stream (no Sampler) are shifted.
TEST(Sampler, AnExtraDrawBeforeTheFirstVertexDoesNotShiftIt) {
    auto scene = testing::small_room(16, 16);
    RenderSettings st;
    st.max_bounces = 0;
    LocalCounters counters;
    int samples = 0, shifted_without_names = 0, distinct = 0;
    for (uint32_t x : {3u, 8u, 12u}) {
        const PixelSampler pixel(x, 7, st.seed, /*stratified=*/true, false, false);
        const Ray ray = scene->camera().generate_ray(x + 0.5f, 7.5f);
        PathState state = camera_path_state(ray.o);
        state.first_vertex_ahead = true;
        Color previous(-1.0f);
        for (uint32_t s = 0; s < 16; ++s, ++samples) {
            Sampler plain = pixel.start(s), extra = pixel.start(s);
            const Color a = trace_path(*scene, st, ray, state, plain.rng(), counters, &plain);
            extra.next_float();
            const Color b = trace_path(*scene, st, ray, state, extra.rng(), counters, &extra);
            EXPECT_EQ(a.x, b.x) << "pixel " << x << " sample " << s;
            EXPECT_EQ(a.y, b.y) << "pixel " << x << " sample " << s;
            EXPECT_EQ(a.z, b.z) << "pixel " << x << " sample " << s;
            distinct += !(a == previous);
            previous = a;

            Sampler stream_plain = pixel.start(s), stream_extra = pixel.start(s);
            const Color c = trace_path(*scene, st, ray, state, stream_plain.rng(), counters);
            stream_extra.next_float();
            const Color d = trace_path(*scene, st, ray, state, stream_extra.rng(), counters);
            shifted_without_names += !(c == d);
        }
    }
    // Not a vacuous comparison: the radiance depends on the sample's numbers.
    EXPECT_GT(distinct, samples / 2);
    EXPECT_GT(shifted_without_names, samples / 2);
}


// The same property for the integrators that hand the first vertex's names on to x1 (camera_prefix.h):
// path-space filtering (RGB and spectral) and ReSTIR (RGB and spectral). In the diffuse small room
// x1 is the camera ray's hit, and at a small bounce limit what `trace` returns depends on x1's named
// numbers only (its light sample, its BSDF sample and what that finds), not on the stream: so an
// extra stream draw before x1 leaves it bit-equal. As a control, with the random pattern (the names
// draw from the stream) the extra draw shifts most samples, and the values vary between samples.
// trace(sampler, ray) -> the values to compare.
template <class Trace>
void expect_x1_keeps_its_names(const std::shared_ptr<Scene>& scene, const RenderSettings& st, Trace&& trace,
                               uint32_t y = 7) {
    int samples = 0, shifted_without_names = 0, distinct = 0;
    for (uint32_t x : {3u, 8u, 12u}) {
        const Ray ray = scene->camera().generate_ray(x + 0.5f, y + 0.5f);
        const PixelSampler named(x, y, st.seed, /*stratified=*/true, false, false);
        const PixelSampler random(x, y, st.seed, /*stratified=*/false, false, false);
        std::vector<float> previous;
        for (uint32_t s = 0; s < 16; ++s, ++samples) {
            Sampler plain = named.start(s), extra = named.start(s);
            const std::vector<float> a = trace(plain, ray);
            extra.next_float();
            const std::vector<float> b = trace(extra, ray);
            EXPECT_EQ(a, b) << "pixel " << x << " sample " << s;
            distinct += a != previous;
            previous = a;

            Sampler stream_plain = random.start(s), stream_extra = random.start(s);
            const std::vector<float> c = trace(stream_plain, ray);
            stream_extra.next_float();
            shifted_without_names += c != trace(stream_extra, ray);
        }
    }
    EXPECT_GT(distinct, samples / 2);
    EXPECT_GT(shifted_without_names, samples / 2);
}

// A floor under a large area light, nothing else: a BSDF sample from the floor finds the light or
// leaves the scene, so what the path brings back after its first vertex is the emission that sample
// finds, whose MIS weight tells its direction apart.
constexpr uint32_t kFloorRow = 3;
std::shared_ptr<Scene> floor_under_a_light(int w, int h) {
    auto s = std::make_shared<Scene>();
    const uint32_t white = s->add_material(testing::diffuse(Color(0.7f)));
    testing::add_box(*s, {-3.0f, -3.0f, -0.1f}, {3.0f, 3.0f, 0.0f}, white);
    testing::add_square_light(*s, 4.0f, 60.0f, {0.0f, 0.0f, 1.5f});
    s->set_camera(testing::camera_along_y({0.0f, -2.9f, 1.0f}, w, h, 22.0f));
    s->commit();
    return s;
}

std::vector<float> values(const Color& c) { return {c.x, c.y, c.z}; }

struct PrefixFixture {
    std::shared_ptr<Scene> scene = testing::small_room(16, 16);
    RenderSettings st;
    LocalCounters counters;
    Film film{16, 16};
    PixelFilter filter;
    RenderCounters render_counters;
    std::atomic<bool> cancel{false};
    RenderContext ctx() {
        return RenderContext{*scene, st, film, filter, render_counters, cancel,
                             std::chrono::steady_clock::time_point::max()};
    }
};

// Path-space filtering's stage 1 at bounce limit 1: the record's per-pixel part (x1's light sample,
// the emission its BSDF sample finds) and its z1.
TEST(Sampler, AnExtraDrawBeforePathSpaceFilteringsX1DoesNotShiftIt) {
    PrefixFixture f;
    f.st.max_bounces = 1;
    f.st.psf_light_samples = 1;  // the extra light samples draw from the stream (stratified on their own)
    auto rgb = [&](Sampler& sampler, const Ray& ray) {
        TechniqueDensity model;
        const psf_detail::PathRecord rec =
            psf_detail::trace_rgb_record(false, *f.scene, f.st, ray, sampler, f.counters, f.scene->camera(), nullptr,
                                         &model, nullptr, 0, nullptr, false, nullptr);
        EXPECT_TRUE(rec.has_vertex);
        std::vector<float> v = values(rec.fixed);
        v.insert(v.end(), {rec.z.x, rec.z.y, rec.z.z, float(rec.has_suffix)});
        return v;
    };
    expect_x1_keeps_its_names(f.scene, f.st, rgb);

    PsfSpectrum spectrum(*f.scene, spectral::SpectralMode::Hero, 4);
    spectrum.begin_iteration(f.st, 0, 1, false, false);
    auto spectral = [&](Sampler& sampler, const Ray& ray) {
        TechniqueDensity model;
        const psf_detail::PathRecord rec = spectrum.trace_record(false, 0, *f.scene, f.st, ray, sampler, f.counters,
                                                                 f.scene->camera(), nullptr, &model, nullptr, 0,
                                                                 nullptr, false, nullptr);
        EXPECT_TRUE(rec.has_vertex);
        std::vector<float> v = values(rec.fixed);
        v.insert(v.end(), {rec.z.x, rec.z.y, rec.z.z, float(rec.has_suffix)});
        return v;
    };
    expect_x1_keeps_its_names(f.scene, f.st, spectral);
}

// ReSTIR's stage 1 on a floor under a light: the path's part after x1 (the emission x1's BSDF
// sample finds); x1's candidates draw from the stream and are not compared.
TEST(Sampler, AnExtraDrawBeforeRestirsX1DoesNotShiftItsBsdfSample) {
    PrefixFixture f;
    f.scene = floor_under_a_light(16, 16);
    f.st.max_bounces = 1;
    f.st.direct_light = DirectLightStrategy::Restir;
    RestirPixel px;
    auto rgb = [&](Sampler& sampler, const Ray& ray) {
        trace_restir_pixel(*f.scene, f.st, ray, sampler, f.counters, px);
        EXPECT_TRUE(px.has_vertex);
        return values(px.fixed);
    };
    expect_x1_keeps_its_names(f.scene, f.st, rgb, kFloorRow);

    const SpectralPathIntegrator spectral_paths(*f.scene, spectral::SpectralMode::Hero, 4);
    const RenderContext ctx = f.ctx();
    float lambda[spectral::kMaxWavelengths];
    Color weight[spectral::kMaxWavelengths];
    auto spectral = [&](Sampler& sampler, const Ray& ray) {
        const Color L = spectral_paths.trace_restir_pixel(ctx, 0, 0, 0, ray, sampler, f.counters, px, lambda, weight);
        EXPECT_TRUE(px.has_vertex);
        return values(L);
    };
    expect_x1_keeps_its_names(f.scene, f.st, spectral, kFloorRow);
}

}  // namespace
}  // namespace smis
