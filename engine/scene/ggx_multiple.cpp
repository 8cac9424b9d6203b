// The interpolated multiscatter GGX table (scene/ggx_multiple.h): multilinear in roughness sqrt(alpha),
// cos_o, cos^2 of wi and the azimuth between them, flat beyond the outermost cell centres.
#include "scene/ggx_multiple.h"

#include "scene/ggx_multiple_layout.h"
#include "scene/table_axis.h"

namespace smis {

namespace {

using namespace ggx_multiple;

#include "scene/tables/ggx_multiple_table.inc"

using namespace table_axis;

Axis rough_axis(float alpha) { return table_axis::rough_axis(alpha, kRough); }
Axis cos_o_axis(float cos_o) { return centred_axis(cos_o, kCosO); }

}  // namespace

float ggx_multiple_brdf(const Vec3& wo, const Vec3& wi, float alpha) {
    Axis r = rough_axis(alpha), o = cos_o_axis(wo.z);
    Axis i = centred_axis(wi.z * wi.z, kCosI), p = azimuth_axis(wo, wi, kPhi);
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
