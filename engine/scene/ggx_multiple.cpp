// The interpolated multiscatter GGX table (scene/ggx_multiple.h): multilinear in roughness sqrt(alpha),
// cos_o, cos^2 of wi and the azimuth between them, flat beyond the outermost cell centres.
#include "scene/ggx_multiple.h"

#include "scene/ggx_multiple_layout.h"

namespace smis {

namespace {

using namespace ggx_multiple;

#include "ggx_multiple_table.inc"

// A coordinate x on an axis of n samples: the lower sample and the weight of the upper one.
struct Axis {
    int lo;
    float t;
};
Axis axis(float x, int n) {
    x = clampf(x, 0.0f, float(n - 1));  // also maps NaN to 0
    int lo = std::min(int(x), n - 2);
    return {lo, x - float(lo)};
}
Axis rough_axis(float alpha) { return axis(std::sqrt(clampf(alpha, 0.0f, 1.0f)) * float(kRough - 1), kRough); }
Axis cos_o_axis(float cos_o) { return axis(cos_o * float(kCosO) - 0.5f, kCosO); }

float interp(float t, float a, float b) { return a + (b - a) * t; }

}  // namespace

float ggx_multiple_brdf(const Vec3& wo, const Vec3& wi, float alpha) {
    Axis r = rough_axis(alpha), o = cos_o_axis(wo.z);
    Axis i = axis(wi.z * wi.z * float(kCosI) - 0.5f, kCosI);
    // The azimuth between the two directions' projections (0: wi on wo's side).
    float lo = std::sqrt(wo.x * wo.x + wo.y * wo.y), li = std::sqrt(wi.x * wi.x + wi.y * wi.y);
    float cos_phi = lo > 0.0f && li > 0.0f ? clampf((wo.x * wi.x + wo.y * wi.y) / (lo * li), -1.0f, 1.0f) : 1.0f;
    Axis p = axis(std::acos(cos_phi) * kInvPi * float(kPhi) - 0.5f, kPhi);
    float sum = 0.0f;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c) {
                const float* cell = kMultipleBrdf[r.lo + a][o.lo + b][i.lo + c];
                float w = (a ? r.t : 1.0f - r.t) * (b ? o.t : 1.0f - o.t) * (c ? i.t : 1.0f - i.t);
                sum += w * interp(p.t, cell[p.lo], cell[p.lo + 1]);
            }
    return sum;
}

float ggx_multiple_albedo(float cos_o, float alpha) {
    Axis r = rough_axis(alpha), o = cos_o_axis(cos_o);
    float e0 = interp(o.t, kMultipleEnergy[r.lo][o.lo], kMultipleEnergy[r.lo][o.lo + 1]);
    float e1 = interp(o.t, kMultipleEnergy[r.lo + 1][o.lo], kMultipleEnergy[r.lo + 1][o.lo + 1]);
    return interp(r.t, e0, e1);
}

float ggx_multiple_average(float alpha) {
    Axis r = rough_axis(alpha);
    float avg[2] = {0.0f, 0.0f};
    for (int a = 0; a < 2; ++a)
        for (int o = 0; o < kCosO; ++o) avg[a] += 2.0f * cos_o_of_cell(o) * kMultipleEnergy[r.lo + a][o] / float(kCosO);
    return interp(r.t, avg[0], avg[1]);
}

float ggx_multiple_half_ratio(float alpha) {
    Axis r = rough_axis(alpha);
    return interp(r.t, kMultipleHalf[r.lo], kMultipleHalf[r.lo + 1]);
}

}  // namespace smis
