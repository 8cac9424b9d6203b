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

}  // namespace smis
