// The interpolated multiscatter glass table (scene/ggx_glass.h): multilinear in roughness sqrt(alpha),
// the relative IOR (within its side of 1), cos_o, cos^2 of wi and the azimuth between them, flat
// beyond the outermost cell centres and IOR nodes.
#include "scene/ggx_glass.h"

#include "scene/ggx_glass_layout.h"
#include "scene/table_axis.h"

namespace smis {

namespace {

using namespace ggx_glass;

#include "scene/tables/ggx_glass_table.inc"

using namespace table_axis;

Axis rough_axis(float alpha) { return table_axis::rough_axis(alpha, kRough); }
Axis cos_o_axis(float cos_o) { return centred_axis(cos_o, kCosO); }
// The IOR rows: e = max(eta, 1 / eta) between two nodes, on eta's side of 1.
Axis eta_axis(float eta) {
    bool below = eta < 1.0f;
    float e = below ? 1.0f / eta : eta;
    if (!std::isfinite(e)) e = kEtaNodes[kEta - 1];
    int lo = 0;
    while (lo < kEta - 2 && e > kEtaNodes[lo + 1]) ++lo;
    float t = clampf((e - kEtaNodes[lo]) / (kEtaNodes[lo + 1] - kEtaNodes[lo]), 0.0f, 1.0f);
    return {lo + (below ? kEta : 0), t};
}

}  // namespace

float ggx_glass_multiple_bsdf(const Vec3& wo, const Vec3& wi, float alpha, float eta) {
    int side = wi.z > 0.0f ? 0 : 1;
    Axis r = rough_axis(alpha), e = eta_axis(eta), o = cos_o_axis(wo.z);
    Axis i = centred_axis(wi.z * wi.z, kCosI), p = azimuth_axis(wo, wi, kPhi);
    float sum = 0.0f;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                for (int d = 0; d < 2; ++d) {
                    const float* cell = kGlassBsdf[r.lo + a][e.lo + b][o.lo + c][side][i.lo + d];
                    float w = weight(r, a) * weight(e, b) * weight(o, c) * weight(i, d);
                    sum += w * interp(p.t, cell[p.lo], cell[p.lo + 1]);
                }
    return sum;
}

float ggx_glass_multiple_albedo(float cos_o, float alpha, float eta, int side) {
    Axis r = rough_axis(alpha), e = eta_axis(eta), o = cos_o_axis(cos_o);
    float sum = 0.0f;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                sum += weight(r, a) * weight(e, b) * weight(o, c) * kGlassEnergy[r.lo + a][e.lo + b][o.lo + c][side];
    return sum;
}

float ggx_glass_multiple_average(float alpha, float eta) {
    Axis r = rough_axis(alpha);
    float sum = 0.0f;
    for (float rel : {eta, 1.0f / eta}) {
        Axis e = eta_axis(rel);
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int o = 0; o < kCosO; ++o) {
                    const float* en = kGlassEnergy[r.lo + a][e.lo + b][o];
                    sum += weight(r, a) * weight(e, b) * cos_o_of_cell(o) * (en[0] + en[1]) / float(kCosO);
                }
    }
    return sum;  // 2 int E mu dmu, averaged over the two IORs
}

float ggx_glass_multiple_colour(float c, float cos_o, float alpha, float eta, int side, int mode, float spec_tint) {
    Axis r = rough_axis(alpha), e = eta_axis(eta), o = cos_o_axis(cos_o);
    float x = 1.0f - spec_tint * (1.0f - c);  // Cycles' cspec0 of the channel
    float sum = 0.0f;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            for (int d = 0; d < 2; ++d) {
                float poly = 0.0f;
                if (mode == 0) {  // Horner over the shares: bounce counts start at one further bounce
                    const float* share = kGlassBounces[r.lo + a][e.lo + b][o.lo + d][side];
                    for (int k = kBounceBins - 1; k >= 0; --k) poly = poly * c + share[k];
                    poly *= c;
                } else {  // Horner in c over the refractions n, each a polynomial in x over the reflections k
                    const float* term = kGlassTint[r.lo + a][e.lo + b][o.lo + d][side];
                    for (int n = kMaxWalkBounces; n >= 0; --n) {
                        float in_x = 0.0f;
                        for (int k = kMaxWalkBounces - n; k >= 0; --k) in_x = in_x * x + term[tint_term(n, k)];
                        poly = poly * c + in_x;
                    }
                }
                sum += weight(r, a) * weight(e, b) * weight(o, d) * poly;
            }
    return sum;
}

}  // namespace smis
