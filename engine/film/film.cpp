#include "film/film.h"

namespace smis {

void Film::resolve(float* rgba) const {
    for (size_t i = 0; i < count_.size(); ++i) {
        uint32_t n = count_[i].load(std::memory_order_acquire);
        double inv = n ? 1.0 / n : 0.0;
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = static_cast<float>(sum_[3 * i + c] * inv);
        rgba[4 * i + 3] = 1.0f;
    }
}

}  // namespace smis
