#include "film/film.h"

namespace smis {

void Film::resolve(float* rgba) const {
    for (size_t i = 0; i < count_.size(); ++i) {
        uint32_t n = count_[i].load(std::memory_order_acquire);
        double inv = n ? 1.0 / n : 0.0;
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = static_cast<float>(sum_[3 * i + c] * inv);
        rgba[4 * i + 3] = has_transparency() ? clampf(float(1.0 - transparency_sum_[i] * inv), 0.0f, 1.0f) : 1.0f;
    }
}

int aux_pass_channels(AuxPass pass) {
    switch (pass) {
        case AuxPass::Depth: return 1;
        case AuxPass::Normal: return 3;
        case AuxPass::Albedo: return 3;
        case AuxPass::Diagnostic: return 1;
    }
    return 0;
}

void Film::enable_aux(bool depth_only) {
    size_t n = size_t(width_) * height_;
    aux_channels_ = depth_only ? 1 : kAuxChannels;
    aux_sum_.assign(aux_channels_ * n, 0.0);
    aux_count_ = std::vector<std::atomic<uint32_t>>(n);
}

std::vector<float> Film::resolve_aux(AuxPass pass) const {
    if (!has_aux()) return {};
    const int first = static_cast<int>(pass), channels = aux_pass_channels(pass);
    std::vector<float> out(channels * aux_count_.size(), 0.0f);
    if (aux_channels_ == 1 && pass != AuxPass::Depth) return out;  // not recorded (enable_aux)
    for (size_t i = 0; i < aux_count_.size(); ++i) {
        uint32_t n = aux_count_[i].load(std::memory_order_acquire);
        if (!n) {
            if (pass == AuxPass::Depth) out[i] = kBackgroundDepth;
            continue;
        }
        for (int c = 0; c < channels; ++c)
            out[channels * i + c] = static_cast<float>(aux_sum_[aux_channels_ * i + first + c] / n);
    }
    return out;
}

}  // namespace smis
