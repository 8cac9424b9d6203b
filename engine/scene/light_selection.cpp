#include "scene/light_selection.h"

#include <cmath>
#include <unordered_map>

namespace smis {

std::vector<float> defensive_light_weights(const std::vector<float>& power, const std::vector<uint32_t>& emitter,
                                           float uniform_share) {
    auto usable = [](float p) { return p > 0.0f && std::isfinite(p); };
    double total = 0.0;
    std::unordered_map<uint32_t, double> emitter_power;
    for (size_t i = 0; i < power.size(); ++i)
        if (usable(power[i])) {
            total += power[i];
            if (emitter[i] != kNoEmitter) emitter_power[emitter[i]] += power[i];
        }
    std::vector<float> w(power.size(), 0.0f);
    if (!(total > 0.0) || !std::isfinite(total)) return w;
    // Without emitters in the uniform part, selection by power alone.
    const double a = emitter_power.empty() ? 0.0 : double(uniform_share);
    const double share = emitter_power.empty() ? 0.0 : a / double(emitter_power.size());
    for (size_t i = 0; i < power.size(); ++i)
        if (usable(power[i]))
            w[i] = float((1.0 - a) * power[i] / total +
                         (emitter[i] != kNoEmitter ? share * power[i] / emitter_power[emitter[i]] : 0.0));
    return w;
}

std::vector<float> cycles_light_weights(const std::vector<CyclesLightRole>& role, const std::vector<float>& area) {
    // Triangles without a finite positive area are never chosen.
    auto sampled_triangle = [&](size_t i) {
        return role[i] == CyclesLightRole::Triangle && area[i] > 0.0f && std::isfinite(area[i]);
    };
    size_t lamps = 0;
    double triangle_area = 0.0;
    for (size_t i = 0; i < role.size(); ++i) {
        if (role[i] == CyclesLightRole::Lamp) ++lamps;
        if (sampled_triangle(i)) triangle_area += area[i];
    }
    // Cycles' pdf_lights and pdf_triangles: half each when the scene has both.
    const double lamp_share = lamps == 0 ? 0.0 : (triangle_area > 0.0 ? 0.5 : 1.0) / double(lamps);
    const double triangle_share = triangle_area > 0.0 ? (lamps > 0 ? 0.5 : 1.0) / triangle_area : 0.0;
    std::vector<float> w(role.size(), 0.0f);
    for (size_t i = 0; i < role.size(); ++i) {
        if (role[i] == CyclesLightRole::Lamp) w[i] = float(lamp_share);
        else if (sampled_triangle(i)) w[i] = float(triangle_share * area[i]);
    }
    return w;
}

}  // namespace smis
