// Accumulation buffer for the render window. Each pixel is written by one thread at a time (tiles),
// samples are added in sample order, so the sum is the same whatever the thread count.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "core/features.h"
#include "core/math.h"

namespace smis {

// Cycles' depth for rays that hit nothing.
constexpr float kBackgroundDepth = 1e10f;

// What the auxiliary passes record at a sample's first camera hit: planar camera depth (Cycles'
// Z), world shading normal facing the camera, albedo, and the integrator's diagnostic value.
struct AuxSample {
    float depth = kBackgroundDepth;
    Vec3 normal{0.0f, 0.0f, 0.0f};
    Color albedo{0.0f};
    float diagnostic = 0.0f;
};

// The auxiliary passes' channels inside one pixel's record.
enum class AuxPass : int { Depth = 0, Normal = 1, Albedo = 4, Diagnostic = 7 };
constexpr int kAuxChannels = 8;
int aux_pass_channels(AuxPass pass);

class Film {
public:
    Film(int width, int height) : width_(width), height_(height), sum_(3 * size_t(width) * height, 0.0),
                                  count_(size_t(width) * height) {}
    int width() const { return width_; }
    int height() const { return height_; }
    // x, y in window pixels, y = 0 the bottom row. The caller guarantees c is finite.
    void add(int x, int y, const Color& c) {
        size_t i = size_t(y) * width_ + x;
        sum_[3 * i] += c.x, sum_[3 * i + 1] += c.y, sum_[3 * i + 2] += c.z;
        count_[i].store(count_[i].load(std::memory_order_relaxed) + 1, std::memory_order_release);
    }
    // Film Transparent: the part of a sample's camera path that reached the background unseen (see
    // PathState::transparent_background); alpha = 1 - its mean. Costs nothing unless enabled.
    void enable_transparency() { transparency_sum_.assign(size_t(width_) * height_, 0.0); }
    bool has_transparency() const { return !transparency_sum_.empty(); }
    // A sample's colour and its transparency (ignored when the film is opaque).
    void add(int x, int y, const Color& c, float transparency) {
        if (has_transparency()) transparency_sum_[size_t(y) * width_ + x] += transparency;
        add(x, y, c);
    }
    // Auxiliary passes cost nothing (no memory, no rays) unless enabled before rendering.
    // depth_only: Blender's default Z pass alone (files saved by Blender 2.8-2.9 enable it) keeps one
    // channel per pixel, not kAuxChannels: 8 bytes a pixel instead of 64. Fresh memory is what a
    // render pays for here (a page fault per 4 KiB; the allocator hands blocks over 8 MB back to the
    // system, so each render faults them in again): 480x270 with all channels was 8.3 MB, 2,000
    // page faults per render. The other passes then read as empty.
    void enable_aux(bool depth_only = false);
    bool has_aux() const { return kWithAuxPasses && !aux_count_.empty(); }
    void add_aux(int x, int y, const AuxSample& a) {
        size_t i = size_t(y) * width_ + x;
        if (aux_channels_ == 1) {
            aux_sum_[i] += a.depth;
        } else {
            double* s = &aux_sum_[kAuxChannels * i];
            const float v[kAuxChannels] = {a.depth,    a.normal.x, a.normal.y, a.normal.z,
                                           a.albedo.x, a.albedo.y, a.albedo.z, a.diagnostic};
            for (int c = 0; c < kAuxChannels; ++c) s[c] += v[c];
        }
        aux_count_[i].store(aux_count_[i].load(std::memory_order_relaxed) + 1, std::memory_order_release);
    }
    // One auxiliary pass averaged over its samples: width x height x aux_pass_channels(pass) floats,
    // rows bottom to top; empty when the passes are off.
    std::vector<float> resolve_aux(AuxPass pass) const;
    // RGBA float32, rows bottom to top (Blender's order); pixels without samples are black. Alpha is 1
    // unless the film is transparent, then 1 - the mean transparency clamped to [0, 1] (Cycles'
    // film_get_pass_pixel_combined).
    void resolve(float* rgba) const;
    std::vector<float> resolve() const {
        std::vector<float> out(4 * size_t(width_) * height_);
        resolve(out.data());
        return out;
    }

private:
    int width_, height_;
    std::vector<double> sum_;
    std::vector<std::atomic<uint32_t>> count_;
    std::vector<double> transparency_sum_;
    std::vector<double> aux_sum_;  // aux_channels_ per pixel
    std::vector<std::atomic<uint32_t>> aux_count_;
    int aux_channels_ = kAuxChannels;
};

// Non-finite radiance never reaches the film: the sample is dropped and counted.
inline bool film_accepts(const Color& c) { return is_finite(c); }

}  // namespace smis
