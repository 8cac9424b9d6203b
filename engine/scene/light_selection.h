// How next-event estimation at surfaces chooses a light: a defensive mixture of selection by power
// and a uniform choice among the emitters (Hesterberg's defensive importance sampling, "Weighted
// average importance sampling and defensive mixture distributions", Technometrics 1995):
//   pmf_i = (1 - a) power_i / P + a / G * power_i / P_g(i),
// G the number of local emitters with power (a lamp, or all emissive triangles of one instance;
// suns and worlds, at infinity, have only their power share),
// P_g the power of light i's emitter. By power alone a dim light beside a bright one gets a
// sample now and then, and the surfaces only it lights (a strip light over a floor, beside a
// 300 W light that a wall hides) are grainy; Cycles 3.4 gives each lamp an equal share. The
// uniform part is over emitters, not lights, so a mesh of many triangles does not crowd out the
// lamps, and within an emitter it is by power. Lights without power are never chosen; with
// a = 0 this is selection by power. Every user of the selection (NEE, the MIS weights of emission
// hits, RIS/ReSTIR candidates) reads the same pmf, so the estimators stay unbiased.
#pragma once
#include <cstdint>
#include <vector>

namespace smis {

inline constexpr float kUniformEmitterShare = 0.5f;  // a
// An emitter id for lights chosen by power only (lights at infinity): not among the G emitters.
inline constexpr uint32_t kNoEmitter = 0xffffffffu;

// The mixture's weights (they sum to 1 unless no light has power); `emitter[i]` names light i's
// emitter (equal for the triangles of one instance).
std::vector<float> defensive_light_weights(const std::vector<float>& power, const std::vector<uint32_t>& emitter,
                                           float uniform_share = kUniformEmitterShare);

// Which distribution NEE chooses lights from (Scene::set_light_selection).
enum class LightSelection {
    Defensive,  // defensive_light_weights: the default
    // Cycles 3.4's own (cycles_light_weights), for the setting multiscatter_cycles_walk: Cycles'
    // multiscatter estimators are inconsistent (their light-sample eval is not their sampled walk), so
    // Cycles' converged image depends on its MIS weights, hence on how it chooses lights.
    Cycles34,
};

// How Cycles 3.4 takes part in a light's choice (before the light tree of 3.5).
enum class CyclesLightRole : uint8_t {
    NotSampled,  // never chosen: a World without spatial variation (Cycles disables its MIS), no power
    Lamp,        // a lamp, or a World that varies over directions (Cycles' background light)
    Triangle,    // an emissive triangle, chosen by area
};
// Cycles 3.4's light distribution (intern/cycles/scene/light.cpp, device_update_distribution, and
// kernel/light/light.h's pdf_lights / pdf_triangles): every lamp 1 / L, every emissive triangle its
// share of the triangles' total (world-space) area, not of their power; with both, each half:
//   pmf_lamp = (T > 0 ? 1/2 : 1) / L,   pmf_triangle_i = (L > 0 ? 1/2 : 1) area_i / sum_j area_j.
// `area[i]` is read for triangles only. The weights sum to 1 unless nothing is sampled.
std::vector<float> cycles_light_weights(const std::vector<CyclesLightRole>& role, const std::vector<float>& area);

}  // namespace smis
