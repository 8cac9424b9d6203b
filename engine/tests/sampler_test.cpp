// The Sampler's named dimension groups (core/sampler.h): with the stratified pattern a name's value
// depends on the pixel, the seed and the sample index only, whatever else was drawn before it.
#include <gtest/gtest.h>

#include <vector>

#include "core/sampler.h"

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

// Until the path tracers ask for the first vertex by name, the sample's Rng hands out the same
// groups as its first six numbers, in the order the path tracers draw them (light choice, light
// point, lobe, direction): the images the prefix made are the images the names make.
TEST(Sampler, TheStreamStartsWithTheFirstVertexGroups) {
    const PixelSampler pixel(11, 2, 3, true, false, false);
    for (uint32_t s = 0; s < 16; ++s) {
        Sampler named = pixel.start(s);
        const LightNumbers light = named.first_light();
        const float lobe = named.first_lobe();
        const Point2 dir = named.first_direction();
        const float expected[6] = {light.choice, light.point.x, light.point.y, lobe, dir.x, dir.y};
        Sampler stream = pixel.start(s);
        for (int i = 0; i < 6; ++i) EXPECT_EQ(stream.rng().next_float(), expected[i]) << "sample " << s << " value " << i;
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

}  // namespace
}  // namespace smis
