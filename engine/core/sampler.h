// A pixel sample's random numbers, asked for by name (issue 21). An integrator says what it draws,
// pixel(), lens(), time(), the first vertex's first_light(), first_lobe() and first_direction(),
// and next_float() / next_2d() for everything else, instead of counting on one order of draws.
//
// With the stratified pattern (core/stratified.h) every name owns its dimension groups
// (sample_groups below): its value is a pure function of the pixel, the seed and the sample index,
// so a draw anywhere else, an extra next_float() or another name asked first, cannot shift it, and
// the names take nothing from the PCG stream, so they cannot shift the stream's draws either.
// With the random pattern (or stratification compiled out) every name draws from the stream, in
// the order asked: those images stay what they were before the Sampler, and there is nothing to
// stratify that an order could spoil.
//
// The path loop (path_loop.h) asks for the first vertex's numbers through a VertexSampler (below):
// the path tracers, photon planes' camera paths, and the camera prefixes of path-space filtering and
// ReSTIR, which hand the view on to x1 when x1 is the first vertex (camera_prefix.h).
#pragma once
#include <cstdint>

#include "core/features.h"
#include "core/rng.h"
#include "core/sampling.h"
#include "core/stratified.h"

namespace smis {

// The dimension groups of a pixel sample's stratified numbers: one table, so that two names cannot
// share a group by accident.
namespace sample_groups {
constexpr uint32_t kPixel = 0;             // position in the pixel (2D)
constexpr uint32_t kLens = 1;              // point on the lens (2D), depth of field only
constexpr uint32_t kFirstChoices = 2;      // the first vertex's light choice and lobe choice (1D each)
constexpr uint32_t kFirstLightPoint = 3;   // the first vertex's point on the light (2D)
constexpr uint32_t kFirstDirection = 4;    // the first vertex's BSDF direction (2D)
constexpr uint32_t kExtraLightPoint = 5;   // path-space filtering's extra light samples (tiles.h)
constexpr uint32_t kExtraLightChoice = 6;
constexpr uint32_t kExtraDirection = 7;    // path-space filtering's extra BSDF samples (tiles.h)
constexpr uint32_t kExtraLobe = 8;
constexpr uint32_t kTime = 9;              // time in the shutter (1D), motion blur only
constexpr uint32_t kScatteringSegment = 10;  // the first scattering segment's, 10-12 (volume.h)
}  // namespace sample_groups

// The scrambles of a pixel's stratified groups: the same for all its samples and seeds alike.
inline uint64_t stratified_pixel_key(uint32_t fx, uint32_t fy, uint32_t seed) {
    return mix64(mix64((uint64_t(fy) << 32) | fx) ^ (uint64_t(seed) * 0xd1b54a32d192ed03ull));
}

// The first vertex's light sample: which light, and the point on it.
struct LightNumbers {
    float choice = 0;
    Point2 point;
};

// Two numbers of a stream, x drawn first (two statements: the order is fixed).
inline Point2 next_2d(Rng& rng) {
    const float x = rng.next_float();
    return {x, rng.next_float()};
}

// The first scattering segment's six numbers (volume.h, segment_numbers): (select, dist), the light
// point and the focus, groups 10, 11 and 12.
inline void scattering_segment_values(uint64_t key, uint32_t s, float* v) {
    for (uint32_t g = 0; g < 3; ++g) stratified::sample_2d(s, key, sample_groups::kScatteringSegment + g, v + 2 * g);
}

class Sampler;

// What a pixel's samples share: the stream's key and the scrambles of the camera's groups, hashed
// once per pixel (where most camera rays leave the scene, these hashes were a tenth of a sample's
// cost), and those of the first vertex's groups, hashed once per pixel too, when a sample first
// asks for them (a pixel whose rays all leave the scene pays nothing). The Samplers it starts refer
// to it: it must outlive them, and belong to one thread.
class PixelSampler {
public:
    // (fx, fy): the pixel in the full frame. `lens` and `time`: whether the camera draws them.
    PixelSampler(uint32_t fx, uint32_t fy, uint32_t seed, bool stratified, bool lens, bool time)
        : stream_(pixel_stream(fx, fy, seed)), stratified_(kWithStratified && stratified) {
        if (!stratified_) return;
        key_ = stratified_pixel_key(fx, fy, seed);
        pixel_ = stratified::GroupSeeds(key_, sample_groups::kPixel);
        if (lens) lens_ = stratified::GroupSeeds(key_, sample_groups::kLens);
        if (time) time_ = stratified::GroupSeeds(key_, sample_groups::kTime);
    }
    PixelSampler(const PixelSampler&) = delete;  // Samplers point to it
    PixelSampler& operator=(const PixelSampler&) = delete;
    inline Sampler start(uint32_t s) const;
    bool stratified() const { return stratified_; }
    uint64_t key() const { return key_; }

private:
    friend class Sampler;
    // The first vertex's group scrambles (stratified only).
    struct FirstVertexSeeds {
        stratified::GroupSeeds choices, light_point, direction;
    };
    const FirstVertexSeeds& first_vertex_seeds() const {
        if (!first_seeded_) seed_first_vertex();
        return first_;
    }
    [[gnu::noinline]] void seed_first_vertex() const {
        first_ = {stratified::GroupSeeds(key_, sample_groups::kFirstChoices),
                  stratified::GroupSeeds(key_, sample_groups::kFirstLightPoint),
                  stratified::GroupSeeds(key_, sample_groups::kFirstDirection)};
        first_seeded_ = true;
    }
    uint64_t stream_, key_ = 0;
    bool stratified_;
    mutable bool first_seeded_ = false;
    stratified::GroupSeeds pixel_, lens_, time_;
    mutable FirstVertexSeeds first_;
};

// Sample s of a pixel: its named groups and its own PCG stream (a pure function of the pixel, the
// sample and the seed, whatever the thread count).
class Sampler {
public:
    Sampler() = default;
    Sampler(const PixelSampler& pixel, uint32_t s) : rng_(pixel_sample_rng(pixel.stream_, s)), pixel_(&pixel), sample_(s) {
        if (pixel.stratified_) {
            rng_.mark_scattering_segment(pixel.key_, s);
            sample_reversed_ = stratified::reverse_bits(s);
        }
    }

    Point2 pixel() { return camera_group(pixel_ ? &pixel_->pixel_ : nullptr); }
    Point2 lens() { return camera_group(pixel_ ? &pixel_->lens_ : nullptr); }
    float time() {
        if (stratified()) return camera_group(&pixel_->time_).x;
        return rng_.next_float();
    }
    LightNumbers first_light() {
        if (stratified()) {
            const auto& seeds = pixel_->first_vertex_seeds();
            const Point2 choices = group(seeds.choices);
            lobe_choice_ = choices.y;  // the lobe's half of the group, kept for first_lobe()
            return {choices.x, group(seeds.light_point)};
        }
        const float choice = rng_.next_float();
        return {choice, next_2d()};
    }
    float first_lobe() {
        if (!stratified()) return rng_.next_float();
        return lobe_choice_ >= 0.0f ? lobe_choice_ : group(pixel_->first_vertex_seeds().choices).y;
    }
    Point2 first_direction() { return stratified() ? group(pixel_->first_vertex_seeds().direction) : next_2d(); }
    // Path-space filtering's extra samples at x1 (psf_records.h, PixelStrata): extra light sample
    // `index` takes its light choice and point from groups kExtraLightChoice and kExtraLightPoint,
    // extra BSDF sample `index` its lobe and direction from kExtraLobe and kExtraDirection, so that
    // a pixel's extra samples form one stratified set of their own. (Random pattern: the stream.)
    LightNumbers extra_light(uint32_t index) {
        if (!stratified()) return first_light();
        return {extra_group(index, sample_groups::kExtraLightChoice).x, extra_group(index, sample_groups::kExtraLightPoint)};
    }
    float extra_lobe(uint32_t index) {
        return stratified() ? extra_group(index, sample_groups::kExtraLobe).x : rng_.next_float();
    }
    Point2 extra_direction(uint32_t index) {
        return stratified() ? extra_group(index, sample_groups::kExtraDirection) : next_2d();
    }

    // Everything without a name: the PCG stream.
    float next_float() { return rng_.next_float(); }
    Point2 next_2d() { return smis::next_2d(rng_); }
    // For code that takes the stream as an Rng (all of it beyond the camera and the first vertex).
    Rng& rng() { return rng_; }
    uint32_t sample_index() const { return sample_; }

private:
    bool stratified() const { return kWithStratified && pixel_ && pixel_->stratified_; }
    Point2 group(const stratified::GroupSeeds& seeds) const {
        float v[2];
        stratified::sample_2d_of_reversed(sample_reversed_, seeds, v);
        return {v[0], v[1]};
    }
    // Group g at stratum `index`: the pixel's extra samples (their groups are hashed per draw).
    Point2 extra_group(uint32_t index, uint32_t g) const {
        float v[2];
        stratified::sample_2d(index, pixel_->key_, g, v);
        return {v[0], v[1]};
    }
    Point2 camera_group(const stratified::GroupSeeds* seeds) {
        if (!stratified()) return next_2d();
        return group(*seeds);
    }
    Rng rng_;
    const PixelSampler* pixel_ = nullptr;
    uint32_t sample_ = 0;
    // reverse_bits(sample_), stratified only: every named group of the sample scrambles its index
    // from it (stratified::sample_2d_of_reversed), so it is reversed once, not once per group.
    uint32_t sample_reversed_ = 0;
    // The two choices share one group (light, lobe): first_light() computes both; -1 until then.
    float lobe_choice_ = -1.0f;
};

inline Sampler PixelSampler::start(uint32_t s) const { return Sampler(*this, s); }

// One path vertex's light sample and BSDF sample ask for their numbers by name through this view:
// light() (the light choice and the point on it), lobe() and direction(). A camera path's first
// vertex asks the pixel sample's Sampler for its named groups (first_light, first_lobe,
// first_direction), so no draw before it, a scattering segment's or a resampling candidate's,
// shifts them; every other vertex (first = null) draws them from the path's stream, in the order
// asked, as it always did. `stream` is the path's stream, the Sampler's own for a camera path.
// extra(): path-space filtering's extra light or BSDF sample `index` at x1, asked of the Sampler by
// name too (Sampler::extra_light, extra_lobe, extra_direction).
class VertexSampler {
public:
    // `first`: the camera path's Sampler at its first vertex, whose stream `stream` then is; else null.
    explicit VertexSampler(Rng& stream, Sampler* first = nullptr) : kind_(first ? kFirst : kStream) {
        if (first) named_ = first;
        else stream_ = &stream;
    }
    static VertexSampler extra(Sampler& sampler, uint32_t index) {
        VertexSampler v(sampler.rng(), &sampler);
        v.kind_ = kExtra, v.index_ = index;
        return v;
    }
    LightNumbers light() const {
        if (kind_ != kStream) return named_light(named_, kind_, index_);
        const float choice = stream_->next_float();
        return {choice, next_2d(*stream_)};
    }
    float lobe() const {
        if (kind_ != kStream) return named_lobe(named_, kind_, index_);
        return stream_->next_float();
    }
    Point2 direction() const {
        if (kind_ != kStream) return named_direction(named_, kind_, index_);
        return next_2d(*stream_);
    }
    // The Sampler this vertex asks for the first vertex's numbers; null when it draws from the stream.
    Sampler* names() const { return kind_ == kFirst ? named_ : nullptr; }

private:
    // Two words, passed in registers: the stream, or the Sampler asked by name (whose stream it is).
    enum Kind : uint32_t { kStream, kFirst, kExtra };
    // The numbers asked by name, out of line (one call per draw at a camera path's first vertex): with
    // the stratified pattern they are a few hashed groups each (Sampler::group), which, inlined, made
    // the path loop larger in the build with the pattern than in the one without it (cmake
    // -DSMIS_WITHOUT=stratified) by enough to tip the compiler's inlining of the loop's helpers
    // (sample_bsdf and clamp_contribution stayed out of line in the one, went inline in the other:
    // +1.98% instructions on psf_room with the pattern unused, docs/bench/skip_bench.md). Out of
    // line, the loops of both builds hold the same call, whatever the pattern's code grows to, so the
    // inlining of the loop cannot depend on it. Static, on the view's two words: no copy of the view
    // is spilled to memory for a `this`.
    [[gnu::noinline]] static LightNumbers named_light(Sampler* named, Kind kind, uint32_t index) {
        return kind == kExtra ? named->extra_light(index) : named->first_light();
    }
    [[gnu::noinline]] static float named_lobe(Sampler* named, Kind kind, uint32_t index) {
        return kind == kExtra ? named->extra_lobe(index) : named->first_lobe();
    }
    [[gnu::noinline]] static Point2 named_direction(Sampler* named, Kind kind, uint32_t index) {
        return kind == kExtra ? named->extra_direction(index) : named->first_direction();
    }
    union {
        Rng* stream_;
        Sampler* named_;
    };
    Kind kind_;
    uint32_t index_ = 0;  // kExtra: the extra sample's stratum
};

}  // namespace smis
