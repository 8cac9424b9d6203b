// Accumulation buffer for the render window. Each pixel is written by one thread at a time (tiles),
// samples are added in sample order, so the sum is the same whatever the thread count.
#pragma once
#include <atomic>
#include <cstdint>
#include <vector>

#include "core/math.h"

namespace smis {

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
    // RGBA float32, rows bottom to top (Blender's order), alpha 1; pixels without samples are black.
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
};

// Non-finite radiance never reaches the film: the sample is dropped and counted.
inline bool film_accepts(const Color& c) { return is_finite(c); }

}  // namespace smis
