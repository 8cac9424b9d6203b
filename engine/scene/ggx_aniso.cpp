// The interpolated anisotropic multiscatter GGX table (scene/ggx_aniso.h): multilinear in the two
// roughnesses sqrt(alpha), the view's polar angle and azimuth (folded into [0, pi/2], the exit mirrored
// with it: the walk is symmetric under x -> -x and y -> -y, so the table is even about both ends of
// that quarter and flat beyond its outermost centres is right to first order), cos^2 of the exit and its
// azimuth from the tangent (periodic); flat beyond the outermost nodes or cell centres elsewhere.
#include "scene/ggx_aniso.h"

#include "scene/ggx_aniso_layout.h"
#include "scene/table_axis.h"

namespace smis {

namespace {

using namespace ggx_aniso;

#include "scene/tables/ggx_aniso_table.inc"

using namespace table_axis;

// The four (rx, ry) rows around (alpha_x, alpha_y) and their weights.
struct Rows {
    int row[4];
    float w[4];
};
Rows rows_of(float ax, float ay) {
    Axis x = rough_axis(ax, kRough), y = rough_axis(ay, kRough);
    Rows r;
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            r.row[2 * a + b] = (x.lo + a) * kRough + y.lo + b;
            r.w[2 * a + b] = weight(x, a) * weight(y, b);
        }
    return r;
}

// The view folded into the first quadrant of the tangent frame, and the exit mirrored with it.
struct View {
    Axis theta, phi;
    float sx, sy;
};
View view_of(const Vec3& wo) {
    float theta = std::acos(clampf(wo.z, 0.0f, 1.0f)), phi = std::atan2(std::fabs(wo.y), std::fabs(wo.x));
    return {axis(theta * (float(kThetaO - 1) / kThetaMax), kThetaO), centred_axis(phi * (2.0f * kInvPi), kPhiO),
            wo.x < 0.0f ? -1.0f : 1.0f, wo.y < 0.0f ? -1.0f : 1.0f};
}

// An azimuth difference on kPhiI cells round the circle, sampled at their centres.
struct Periodic {
    int lo, hi;
    float t;
};
Periodic periodic_axis(float d) {
    float x = d * (0.5f * kInvPi) * float(kPhiI) - 0.5f;
    x -= float(kPhiI) * std::floor(x / float(kPhiI));  // in [0, kPhiI)
    int lo = std::min(int(x), kPhiI - 1);
    return {lo, (lo + 1) % kPhiI, clampf(x - float(lo), 0.0f, 1.0f)};
}

}  // namespace

float ggx_aniso_brdf(const Vec3& wo, const Vec3& wi, float ax, float ay) {
    View v = view_of(wo);
    Rows r = rows_of(ax, ay);
    const Axis &o = v.theta, &p = v.phi;
    Axis i = centred_axis(wi.z * wi.z, kCosI);
    float phi_i = std::atan2(v.sy * wi.y, v.sx * wi.x);
    Periodic k = periodic_axis(std::isfinite(phi_i) ? phi_i : 0.0f);
    float sum = 0.0f;
    for (int q = 0; q < 4; ++q)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                for (int d = 0; d < 2; ++d) {
                    const float* cell = kAnisoBrdf[r.row[q]][o.lo + b][p.lo + c][i.lo + d];
                    float w = r.w[q] * weight(o, b) * weight(p, c) * weight(i, d);
                    sum += w * interp(k.t, cell[k.lo], cell[k.hi]);
                }
    return sum;
}

float ggx_aniso_albedo(const Vec3& wo, float ax, float ay) {
    View v = view_of(wo);
    Rows r = rows_of(ax, ay);
    const Axis &o = v.theta, &p = v.phi;
    float sum = 0.0f;
    for (int q = 0; q < 4; ++q)
        for (int b = 0; b < 2; ++b)
            for (int c = 0; c < 2; ++c)
                sum += r.w[q] * weight(o, b) * weight(p, c) * kAnisoEnergy[r.row[q]][o.lo + b][p.lo + c];
    return sum;
}

float ggx_aniso_average(float ax, float ay) {
    Rows r = rows_of(ax, ay);
    return r.w[0] * kAnisoAverage[r.row[0]] + r.w[1] * kAnisoAverage[r.row[1]] + r.w[2] * kAnisoAverage[r.row[2]] +
           r.w[3] * kAnisoAverage[r.row[3]];
}

float ggx_aniso_half_ratio(float ax, float ay) {
    Rows r = rows_of(ax, ay);
    return r.w[0] * kAnisoHalf[r.row[0]] + r.w[1] * kAnisoHalf[r.row[1]] + r.w[2] * kAnisoHalf[r.row[2]] +
           r.w[3] * kAnisoHalf[r.row[3]];
}

}  // namespace smis
