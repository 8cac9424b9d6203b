// Discrete distribution with an O(1) pdf and O(log n) sampling; used for light selection by power.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

namespace smis {

class DiscreteDistribution {
public:
    DiscreteDistribution() = default;
    explicit DiscreteDistribution(const std::vector<float>& weights) {
        pmf_.resize(weights.size());
        cdf_.resize(weights.size() + 1);
        cdf_[0] = 0.0;
        for (size_t i = 0; i < weights.size(); ++i) {
            double w = weights[i] > 0.0f && std::isfinite(weights[i]) ? weights[i] : 0.0;
            cdf_[i + 1] = cdf_[i] + w;
        }
        total_ = cdf_.back();
        for (size_t i = 0; i < weights.size(); ++i)
            pmf_[i] = total_ > 0.0 ? static_cast<float>((cdf_[i + 1] - cdf_[i]) / total_) : 0.0f;
    }
    bool empty() const { return total_ <= 0.0; }
    size_t size() const { return pmf_.size(); }
    float pmf(size_t i) const { return i < pmf_.size() ? pmf_[i] : 0.0f; }
    // Returns the index; *remapped is u rescaled to [0,1) within the chosen bin, for reuse.
    size_t sample(float u, float* remapped = nullptr) const {
        double target = u * total_;
        size_t i = std::upper_bound(cdf_.begin(), cdf_.end(), target) - cdf_.begin();
        i = std::min(std::max<size_t>(i, 1), pmf_.size()) - 1;
        while (pmf_[i] == 0.0f && i > 0) --i;  // never return a zero-probability bin
        if (remapped) {
            double w = cdf_[i + 1] - cdf_[i];
            *remapped = w > 0 ? std::min(0.99999994f, static_cast<float>((target - cdf_[i]) / w)) : 0.0f;
        }
        return i;
    }

private:
    std::vector<float> pmf_;
    std::vector<double> cdf_;
    double total_ = 0.0;
};

}  // namespace smis
