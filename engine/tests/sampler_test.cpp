// The Sampler's named dimension groups (core/sampler.h): with the stratified pattern a name's value
// depends on the pixel, the seed and the sample index only, whatever else was drawn before it.
#include <gtest/gtest.h>

#include <vector>

#include "core/sampler.h"
#include "integrators/path_tracing.h"
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

// The sample's own stream carries nothing of the names: its first numbers are the PCG stream's.
// The integrators that do not ask by name yet take the stream with the first vertex's groups as its
// first six numbers, in the order the path loop asks for them (light choice, light point, lobe,
// direction): their images are the ones the names make in the path tracers.
TEST(Sampler, TheStreamIsPlainAndTheBridgeStartsWithTheFirstVertexGroups) {
    const uint32_t fx = 11, fy = 2, seed = 3;
    const PixelSampler pixel(fx, fy, seed, true, false, false);
    for (uint32_t s = 0; s < 16; ++s) {
        Sampler named = pixel.start(s);
        const LightNumbers light = named.first_light();
        const float lobe = named.first_lobe();
        const Point2 dir = named.first_direction();
        const float expected[6] = {light.choice, light.point.x, light.point.y, lobe, dir.x, dir.y};
        Rng bridge = pixel.start(s).stream_with_first_vertex_prefix();
        for (int i = 0; i < 6; ++i) EXPECT_EQ(bridge.next_float(), expected[i]) << "sample " << s << " value " << i;
        Sampler plain = pixel.start(s);
        Rng reference = pixel_sample_rng(fx, fy, s, seed);
        for (int i = 0; i < 6; ++i) EXPECT_EQ(plain.rng().next_float(), reference.next_float()) << "sample " << s;
        EXPECT_EQ(bridge.next_float(), pixel_sample_rng(fx, fy, s, seed).next_float()) << "sample " << s;  // then the stream
    }
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

// The first vertex's deferred prefix is gone from the path tracer: an integrator that draws an
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

}  // namespace
}  // namespace smis
