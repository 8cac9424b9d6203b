#include "scene/media_light_choice.h"

#include <algorithm>
#include <cmath>

namespace smis {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;  // the largest float below 1
}  // namespace

MediaLightChoice::MediaLightChoice(const std::vector<std::unique_ptr<Light>>& lights,
                                   const DiscreteDistribution& power) {
    entries_.resize(lights.size());
    for (int skip = 0; skip < 2; ++skip) {
        Mode& m = mode_[skip];
        m.power_pmf.assign(lights.size(), 0.0f);
        double total = 0.0;
        for (uint32_t i = 0; i < lights.size(); ++i) {
            const Light& l = *lights[i];
            if (!(l.visibility & kRayVolumeScatter)) continue;  // Ray Visibility > Volume Scatter off
            if (skip && (l.rectangle(nullptr) || l.point(nullptr))) continue;  // Entry::plane
            m.eligible.push_back(i);
            m.power_pmf[i] = power.pmf(i);
            total += power.pmf(i);
        }
        // Without power among them (all dark), the power part is uniform too.
        for (uint32_t i : m.eligible)
            m.power_pmf[i] = total > 0.0 ? float(m.power_pmf[i] / total) : 1.0f / float(m.eligible.size());
        m.power = DiscreteDistribution(m.power_pmf);
    }
    for (uint32_t i = 0; i < lights.size(); ++i) {
        entries_[i].bounded = lights[i]->bounds(&entries_[i].bounds);
        entries_[i].plane = lights[i]->rectangle(nullptr) || lights[i]->point(nullptr);
        entries_[i].power = power.pmf(i);
    }
}

// w_i / power_i of the header's segment part, and the optical depth tau_i it leaves out (the
// caller takes exp(tau_min - tau_i), so that far lights in dense media do not all underflow).
float MediaLightChoice::segment_weight(const Segment& s, const Entry& e, float* tau) const {
    *tau = 0.0f;
    if (!e.bounded) return 0.0f;
    const LightBounds& b = e.bounds;
    const Vec3 rel = b.centre - s.o;
    if (b.one_sided) {
        // Behind the light at both ends of a (convex) segment: behind it everywhere.
        const float start = -dot(rel, b.normal), slope = dot(s.d, b.normal);
        const bool end_behind = std::isinf(s.len) ? slope <= 0.0f : start + slope * s.len <= 0.0f;
        if (start <= 0.0f && end_behind) return 0.0f;
    }
    const float delta = dot(rel, s.d);
    const float h_sq = std::max(0.0f, length_sq(rel) - delta * delta);
    const float h = std::sqrt(std::max(h_sq + b.radius * b.radius, 1e-12f));
    const float g = (std::atan((s.len - delta) / h) + std::atan(delta / h)) / h;
    const float tc = std::clamp(delta, 0.0f, s.len);
    if (s.sigma_t > 0.0f) *tau = s.sigma_t * (tc + length(rel - s.d * tc));
    return std::isfinite(g) && g > 0.0f ? g : 0.0f;
}

MediaLightChoice::Eligible MediaLightChoice::eligible(const Segment& s, EligibleStorage* storage) const {
    const Mode& m = mode_[s.skip_plane_lights];
    if (!(s.skip_plane_lights && s.keep_plane_lights) || entries_.size() > size_t(kMaxSegmentLights))
        return {m.eligible.data(), m.eligible.size(), m.power_pmf.data()};
    // The lights of the mode without skipping, less the plane lights not kept, in the same order.
    const Mode& all = mode_[0];
    size_t n = 0;
    double total = 0.0;
    for (uint32_t i : all.eligible) {
        storage->power_pmf[i] = 0.0f;
        if (entries_[i].plane && !(s.keep_plane_lights >> i & 1u)) continue;
        storage->index[n++] = i;
        total += entries_[i].power;
    }
    for (size_t k = 0; k < n; ++k) {
        const uint32_t i = storage->index[k];
        storage->power_pmf[i] = total > 0.0 ? float(entries_[i].power / total) : 1.0f / float(n);
    }
    return {storage->index, n, storage->power_pmf};
}

void MediaLightChoice::segment_pmfs(const Segment& s, const Eligible& e, float* pmf) const {
    float g[kMaxSegmentLights], tau[kMaxSegmentLights];
    float tau_min = kInf;
    for (size_t k = 0; k < e.count; ++k) {
        const uint32_t i = e.index[k];
        g[i] = segment_weight(s, entries_[i], &tau[i]);
        if (g[i] > 0.0f) tau_min = std::min(tau_min, tau[i]);
    }
    double total = 0.0;
    for (size_t k = 0; k < e.count; ++k) {
        const uint32_t i = e.index[k];
        // exp(0) = 1 exactly: the light that sets tau_min (often the only one near) needs no exp.
        if (g[i] > 0.0f) g[i] *= e.power_pmf[i] * (tau[i] == tau_min ? 1.0f : std::exp(tau_min - tau[i]));
        total += g[i];
    }
    const bool segment = total > 0.0 && std::isfinite(total);
    // Without a segment part (only lights at infinity, or every one behind), the defensive two.
    const float norm = segment ? 1.0f : 1.0f / (kPowerWeight + kUniformWeight);
    const float uniform = kUniformWeight / float(e.count);
    for (size_t i = 0; i < entries_.size(); ++i) pmf[i] = 0.0f;
    for (size_t k = 0; k < e.count; ++k) {
        const uint32_t i = e.index[k];
        pmf[i] = norm * (kPowerWeight * e.power_pmf[i] + uniform + (segment ? float(kSegmentWeight * g[i] / total) : 0.0f));
    }
}

bool MediaLightChoice::sample(const Segment& s, float u, uint32_t* light, float* pmf, float* remapped) const {
    const Mode& m = mode_[s.skip_plane_lights];
    EligibleStorage storage;
    const Eligible e = eligible(s, &storage);
    if (e.count == 0) return false;
    if (entries_.size() > size_t(kMaxSegmentLights)) {
        // The defensive mixture alone: the first half of u chooses by power, the second uniformly.
        float r = 0.0f;
        if (u < 0.5f) {
            *light = uint32_t(m.power.sample(2.0f * u, &r));
        } else {
            const float v = (2.0f * u - 1.0f) * float(m.eligible.size());
            size_t k = std::min(m.eligible.size() - 1, size_t(v));
            *light = m.eligible[k];
            r = v - float(k);
        }
        if (remapped) *remapped = std::clamp(r, 0.0f, kOneMinusEpsilon);
        *pmf = this->pmf(s, *light);
        return *pmf > 0.0f;
    }
    float p[kMaxSegmentLights];
    segment_pmfs(s, e, p);
    // Inverse CDF over the eligible lights; rounding past the end falls on the last one.
    float cdf = 0.0f, below = 0.0f;
    *light = e.index[e.count - 1];
    for (size_t k = 0; k < e.count; ++k) {
        const uint32_t i = e.index[k];
        below = cdf;
        cdf += p[i];
        if (u < cdf) {
            *light = i;
            break;
        }
    }
    *pmf = p[*light];
    if (remapped) *remapped = *pmf > 0.0f ? std::clamp((u - below) / *pmf, 0.0f, kOneMinusEpsilon) : 0.0f;
    return *pmf > 0.0f;
}

float MediaLightChoice::pmf(const Segment& s, uint32_t light) const {
    const Mode& m = mode_[s.skip_plane_lights];
    EligibleStorage storage;
    const Eligible e = eligible(s, &storage);
    if (light >= entries_.size() || e.count == 0) return 0.0f;
    if (entries_.size() > size_t(kMaxSegmentLights)) {
        const bool eligible = std::binary_search(m.eligible.begin(), m.eligible.end(), light);
        return eligible ? 0.5f * (m.power.pmf(light) + 1.0f / float(m.eligible.size())) : 0.0f;
    }
    float p[kMaxSegmentLights];
    segment_pmfs(s, e, p);
    return p[light];
}

}  // namespace smis
