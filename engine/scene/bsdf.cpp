// The per-hit lobe mixture (Bsdf) and the per-lobe entry points, dispatched over the kinds of
// scene/lobes/ (dispatch.h), plus the GGX and Fresnel helpers the lobes share.
//
// Every routine is written so that no input (grazing angles, cos = 0, tiny alpha, eta = 1, NaN
// directions) can make it divide by zero: degenerate configurations return value 0 / pdf 0.
#include "scene/bsdf.h"

namespace smis {

namespace {

// Largest float below 1, to keep remapped random numbers in [0, 1).
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
// Cycles' CLOSURE_WEIGHT_CUTOFF: closures with a smaller |average(weight)| are dropped.
constexpr float kClosureWeightCutoff = 1e-5f;

using lobe_detail::sanitize_alpha;

// Local-frame vs geometric-normal hemisphere agreement (light-leak guard). Shading normals can make a
// direction look like reflection in the shading frame while it actually crosses the geometry (or the
// reverse); those configurations would leak light through surfaces, so they contribute nothing.
bool sides_consistent(const Vec3& ng, const Vec3& wo, const Vec3& wi, const Vec3& wo_l, const Vec3& wi_l) {
    float go = dot(wo, ng), gi = dot(wi, ng);
    if (!(go != 0.0f) || !(gi != 0.0f) || !(wo_l.z != 0.0f) || !(wi_l.z != 0.0f)) return false;
    bool geometric_reflection = (go > 0.0f) == (gi > 0.0f);
    bool local_reflection = (wo_l.z > 0.0f) == (wi_l.z > 0.0f);
    return geometric_reflection == local_reflection;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// GGX helpers

float gtr1_D(float cos_m, float alpha) {
    if (!(cos_m > 0.0f)) return 0.0f;
    float a2 = sqr(sanitize_alpha(alpha));
    if (a2 >= 1.0f - 1e-4f) return kInvPi;  // (a2 - 1) / log(a2) -> 1
    float d = (a2 - 1.0f) / (kPi * std::log(a2) * (1.0f + (a2 - 1.0f) * cos_m * cos_m));
    return std::isfinite(d) ? d : 0.0f;
}

Vec3 ggx_sample_visible_normal(const Vec3& wo, float alpha, Point2 u) {
    return ggx_sample_visible_normal(wo, alpha, alpha, u);
}

// Heitz 2018, listing 1 (with alpha_x along x, alpha_y along y). wo is mirrored into the upper
// hemisphere (D is symmetric); the returned normal always has z >= 0.
Vec3 ggx_sample_visible_normal(const Vec3& wo_in, float alpha_x, float alpha_y, Point2 u) {
    alpha_x = sanitize_alpha(alpha_x);
    alpha_y = sanitize_alpha(alpha_y);
    Vec3 wo = wo_in.z < 0.0f ? -wo_in : wo_in;
    // Stretch the view direction to the hemisphere configuration (alpha = 1).
    Vec3 vh(alpha_x * wo.x, alpha_y * wo.y, wo.z);
    float vlen2 = length_sq(vh);
    if (!(vlen2 > 0.0f) || !std::isfinite(vlen2)) return Vec3(0, 0, 1);
    vh = vh / std::sqrt(vlen2);
    // Orthonormal basis around vh (T1 undefined at normal incidence: any tangent works).
    float lensq = vh.x * vh.x + vh.y * vh.y;
    Vec3 t1 = lensq > 0.0f ? Vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq) : Vec3(1, 0, 0);
    Vec3 t2 = cross(vh, t1);
    // Uniform disk point, then warp its lower half onto the visible half-disk.
    float r = std::sqrt(u.x);
    float phi = 2.0f * kPi * u.y;
    float p1 = r * std::cos(phi);
    float p2 = r * std::sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * safe_sqrt(1.0f - p1 * p1) + s * p2;
    // Project onto the hemisphere and unstretch.
    Vec3 nh = t1 * p1 + t2 * p2 + vh * safe_sqrt(1.0f - p1 * p1 - p2 * p2);
    Vec3 ne(alpha_x * nh.x, alpha_y * nh.y, std::max(0.0f, nh.z));
    float nlen2 = length_sq(ne);
    if (!(nlen2 > 0.0f) || !std::isfinite(nlen2)) return Vec3(0, 0, 1);
    return ne / std::sqrt(nlen2);
}

// ---------------------------------------------------------------------------------------------
// Beckmann visible normals (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the
// Distribution of Visible Normals", section 4): the view is stretched to the unit-roughness
// configuration, where it has polar angle theta and a = cot(theta). There a slope (x, y) along and
// across the view's azimuth is seen with the density
//   P(x, y) ~ (a - x) exp(-x^2 - y^2),   x < a,
// so y is normal with variance 1/2, apart from x, and x has the cumulative
//   C(x) ~ a erfc(-x) + exp(-x^2) / sqrt(pi)      (dC/dx = 2 (a - x) exp(-x^2) / sqrt(pi)).
// Both are inverted by Newton's method kept inside a shrinking bracket (double precision).

namespace {

constexpr double kInvSqrtPi = 0.56418958354775628;

// x in [lo, hi] with f(x) = target for an increasing f (df its derivative).
template <class F, class DF>
double invert_increasing(F&& f, DF&& df, double target, double lo, double hi) {
    double x = 0.5 * (lo + hi);
    for (int it = 0; it < 64; ++it) {
        double r = f(x) - target;
        if (r > 0.0) hi = x;
        else lo = x;
        double d = df(x), next = d > 0.0 ? x - r / d : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (std::fabs(next - x) <= 1e-12 * (1.0 + std::fabs(x))) return next;
        x = next;
    }
    return x;
}

// Slopes beyond 8 hold exp(-64) of the distribution: the bracket of both slopes.
constexpr double kSlopeBound = 8.0;

}  // namespace

Vec3 beckmann_sample_visible_normal(const Vec3& wo, float alpha, Point2 u) {
    alpha = sanitize_alpha(alpha);
    const double sx = double(alpha) * wo.x, sy = double(alpha) * wo.y, sin_t = std::sqrt(sx * sx + sy * sy);
    // a = cot of the stretched view's polar angle; at normal incidence any azimuth will do.
    const double a = sin_t > 0.0 ? std::min(double(std::fabs(wo.z)) / sin_t, 1e8) : 1e8;
    const double cos_p = sin_t > 0.0 ? sx / sin_t : 1.0, sin_p = sin_t > 0.0 ? sy / sin_t : 0.0;
    auto cx = [a](double x) { return a * std::erfc(-x) + std::exp(-x * x) * kInvSqrtPi; };
    auto dcx = [a](double x) { return 2.0 * (a - x) * std::exp(-x * x) * kInvSqrtPi; };
    const double hi = std::min(a, kSlopeBound);
    const double x = invert_increasing(cx, dcx, double(u.x) * cx(a), -kSlopeBound, hi);
    auto cy = [](double y) { return 0.5 * std::erfc(-y); };
    auto dcy = [](double y) { return std::exp(-y * y) * kInvSqrtPi; };
    const double y = invert_increasing(cy, dcy, double(u.y), -kSlopeBound, kSlopeBound);
    // Turned to the view's azimuth and unstretched; the normal of slope s is (-s_x, -s_y, 1).
    const double mx = alpha * (cos_p * x - sin_p * y), my = alpha * (sin_p * x + cos_p * y);
    return normalize(Vec3(float(-mx), float(-my), 1.0f));
}

// Smith's masking of the Beckmann distribution (Walter et al. 2007, eq. 25 before its rational
// approximation): G1 = 1 / (1 + Lambda), Lambda = (erf(a) - 1) / 2 + exp(-a^2) / (2 a sqrt(pi)),
// a = 1 / (alpha tan theta).
float beckmann_smith_G1(const Vec3& w, float alpha) {
    const double t = double(sanitize_alpha(alpha)) * std::sqrt(double(w.x) * w.x + double(w.y) * w.y);
    if (!(t > 0.0)) return 1.0f;
    const double a = std::fabs(w.z) / t;
    const double lambda = 0.5 * (std::erf(a) - 1.0) + 0.5 * std::exp(-a * a) * kInvSqrtPi / a;
    return float(1.0 / (1.0 + lambda));
}

// Unpolarised Fresnel reflectance of a dielectric interface. cos_i > 0: incident from the side the
// normal points to, where eta = eta_other_side / eta_this_side; cos_i < 0 flips the interface.
float fresnel_dielectric(float cos_i, float eta) {
    if (!(eta > 0.0f) || !std::isfinite(eta)) return 1.0f;
    cos_i = clampf(cos_i, -1.0f, 1.0f);  // clampf maps NaN to -1
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (!(sin2_t < 1.0f)) return 1.0f;  // total internal reflection (also the grazing eta = 1 case)
    float cos_t = std::sqrt(1.0f - sin2_t);
    // Both denominators are > 0 here: cos_i = 0 implies cos_t > 0 once TIR is excluded.
    float r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return clampf(0.5f * (r_parl * r_parl + r_perp * r_perp), 0.0f, 1.0f);
}

// ---------------------------------------------------------------------------------------------
// Per-lobe interface

Color lobe_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    return visit_lobe(lobe.kind, [&](auto k) { return lobe_eval_pdf_of<decltype(k)>(lobe, wo, wi).value; });
}

LobeTerms lobe_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    return visit_lobe(lobe.kind, [&](auto k) { return lobe_terms_of<decltype(k)>(lobe, wo, wi); });
}

float lobe_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    return visit_lobe(lobe.kind, [&](auto k) {
        using L = decltype(k);
        if constexpr (L::kColourEval) return L::pdf(lobe, wo, wi);  // without its eval (a random walk)
        else return lobe_eval_pdf_of<L>(lobe, wo, wi).pdf;
    });
}

BsdfSample lobe_sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
    BsdfSample s = visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::sample(lobe, wo, u, u_event); });
    if (!s.valid()) return BsdfSample{};
    return s;
}

float lobe_sample_weight(const Lobe& lobe, const Vec3& /*wo*/) {
    // Cycles' sample_weight = |average(closure weight)|: cheap and view independent.
    float w = std::fabs(average(lobe.weight));
    return std::isfinite(w) ? w : 0.0f;
}

// ---------------------------------------------------------------------------------------------
// Mixture

void Bsdf::add(const Lobe& lobe) {
    if (count_ >= kMaxLobes) return;
    if (!is_finite(lobe.weight)) return;
    // Same cutoff as Cycles' bsdf_alloc: negligible closures only cost samples.
    if (!(std::fabs(average(lobe.weight)) >= kClosureWeightCutoff)) return;
    Lobe l = lobe;
    // Keep the lobe routines' inputs sane (Cycles clamps the IOR the same way).
    l.alpha = std::isfinite(l.alpha) ? std::max(l.alpha, 0.0f) : 0.0f;
    // std::max, not std::fmax: the same for a finite eta, and fmax is a libm call (with the spills
    // around it, a third of add()'s instructions).
    l.eta = std::isfinite(l.eta) ? std::max(l.eta, 1e-5f) : 1.0f;
    if (lobe_is_delta(l)) ++delta_count_;
    lobes_[count_++] = l;
}

void Bsdf::subsurface_as_diffuse() {
    for (int i = 0; i < count_; ++i) {
        Lobe& l = lobes_[i];
        if (l.kind != LobeKind::Subsurface) continue;
        const bool principled = l.variant & SubsurfaceLobe::kPrincipledExit;
        l.kind = principled ? LobeKind::PrincipledPart : LobeKind::Diffuse;
        l.variant = PrincipledPartLobe::kLambert;
        --delta_count_;
    }
}

Color Bsdf::albedo_weight() const {
    Color sum(0.0f);
    for (int i = 0; i < count_; ++i) sum += lobes_[i].weight;
    return sum;
}

void Bsdf::selection_probabilities(const Vec3& wo_local, float* probs) const {
    float total = 0.0f;
    for (int i = 0; i < count_; ++i) {
        probs[i] = lobe_sample_weight(lobes_[i], wo_local);
        total += probs[i];
    }
    float inv = total > 0.0f && std::isfinite(total) ? 1.0f / total : 0.0f;
    for (int i = 0; i < count_; ++i) probs[i] *= inv;
}

float Bsdf::bump_shadowing(const Vec3& wi) const {
    // g = cos(base, wi) / (cos(N, wi) cos(base, N)): 1 where the bent normal sees no more of the
    // light than the surface does, smoothly to 0 at the surface's own horizon.
    Vec3 base = bump_base_;
    float cos_ni = dot(frame_.n, wi);
    if (cos_ni < 0.0f) base = -base;
    float denom = cos_ni * dot(base, frame_.n);
    float g = denom != 0.0f ? dot(base, wi) / denom : 0.0f;
    if (g >= 1.0f) return 1.0f;
    if (!(g >= 0.0f)) return 0.0f;
    float g2 = g * g;
    return -g2 * g + g2 + g;
}

Color Bsdf::eval(const Vec3& wo, const Vec3& wi) const {
    if (count_ == 0) return Color(0.0f);
    Vec3 wo_l = frame_.to_local(wo), wi_l = frame_.to_local(wi);
    if (!sides_consistent(ng_, wo, wi, wo_l, wi_l)) return Color(0.0f);
    if (bumped_) return eval_bumped(wi, wo_l, wi_l);
    Color sum(0.0f);
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        sum += visit_lobe(lobe.kind, [&](auto k) { return lobe_eval_pdf_of<decltype(k)>(lobe, wo_l, wi_l).value; });
    }
    return is_finite(sum) ? sum : Color(0.0f);
}

Color Bsdf::eval_bumped(const Vec3& wi, const Vec3& wo_l, const Vec3& wi_l) const {
    float shadowing = bump_shadowing(wi);
    Color sum(0.0f);
    for (int i = 0; i < count_; ++i) {
        Color c = lobe_eval(lobes_[i], wo_l, wi_l);
        sum += diffuse_labelled(lobes_[i]) ? c * shadowing : c;
    }
    return is_finite(sum) ? sum : Color(0.0f);
}

Color Bsdf::bumped_sample_value(Color chosen_value, int chosen, const Vec3& wi, const Vec3& wo_l, const Vec3& wi_l) const {
    if (!walk_lobe(lobes_[chosen])) return eval_bumped(wi, wo_l, wi_l);
    float shadowing = bump_shadowing(wi);
    Color sum(0.0f);
    for (int i = 0; i < count_; ++i) {
        Color c = i == chosen ? chosen_value : lobe_eval(lobes_[i], wo_l, wi_l);
        sum += diffuse_labelled(lobes_[i]) ? c * shadowing : c;
    }
    return sum;
}

void Bsdf::shadow_diffuse_terms(const Vec3& wi, LobeTerms* terms) const {
    float shadowing = bump_shadowing(wi);
    for (int i = 0; i < count_; ++i)
        if (diffuse_labelled(lobes_[i])) terms[i].geom *= shadowing;
}

bool Bsdf::eval_terms(const Vec3& wo, const Vec3& wi, LobeTerms* terms) const {
    Vec3 wo_l = frame_.to_local(wo), wi_l = frame_.to_local(wi);
    if (count_ == 0 || !sides_consistent(ng_, wo, wi, wo_l, wi_l)) return false;
    for (int i = 0; i < count_; ++i) terms[i] = lobe_terms(lobes_[i], wo_l, wi_l);
    if (bumped_) shadow_diffuse_terms(wi, terms);
    return true;
}

Bsdf::FixedWo Bsdf::fix_wo(const Vec3& wo) const {
    FixedWo f;
    f.wo = wo;
    f.wo_local = frame_.to_local(wo);
    selection_probabilities(f.wo_local, f.probs);
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        float scale = visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::fixed_wo_scale(lobe, f.wo_local); });
        f.pdf_scale[i] = std::isfinite(scale) ? scale : 0.0f;
    }
    return f;
}

// The same densities as lobe_pdf(), without evaluating the BSDF values where the lobe has a wo-only
// shortcut (fixed_wo_pdf): path-space filtering sums k^2 of them per pixel (eq. 17).
float Bsdf::pdf(const FixedWo& fixed, const Vec3& wi) const {
    if (count_ == 0) return 0.0f;
    Vec3 wi_l = frame_.to_local(wi);
    if (!sides_consistent(ng_, fixed.wo, wi, fixed.wo_local, wi_l)) return 0.0f;
    const Vec3& wo_l = fixed.wo_local;
    float sum = 0.0f;
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        float scale = fixed.pdf_scale[i];
        float p = visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::fixed_wo_pdf(lobe, scale, wo_l, wi_l); });
        sum += fixed.probs[i] * p;
    }
    return std::isfinite(sum) ? sum : 0.0f;
}

int Bsdf::lobe_at(const Vec3& wo, const Vec3& wi, float u) const {
    if (count_ <= 1) return 0;
    const FixedWo fixed = fix_wo(wo);
    const Vec3 wi_l = frame_.to_local(wi);
    float p[kMaxLobes], sum = 0.0f;
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        const float scale = fixed.pdf_scale[i];
        p[i] = fixed.probs[i] *
               visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::fixed_wo_pdf(lobe, scale, fixed.wo_local, wi_l); });
        if (!(p[i] > 0.0f) || !std::isfinite(p[i])) p[i] = 0.0f;
        sum += p[i];
    }
    if (!(sum > 0.0f)) return 0;
    float below = 0.0f;
    int last = 0;
    for (int i = 0; i < count_; ++i) {
        if (p[i] == 0.0f) continue;
        last = i;
        below += p[i];
        if (u * sum < below) return i;
    }
    return last;
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    if (count_ == 0) return 0.0f;
    if (count_ == 1) return pdf_one_lobe(wo, wi);
    return pdf(fix_wo(wo), wi);
}

// pdf(fix_wo(wo), wi) for a single lobe (a plain diffuse surface, the common case): the same
// operations on the same values, so bit-identical, without filling and reading back FixedWo's arrays
// (they were ~270 instructions of a textured diffuse plane's ~7,700 per path).
float Bsdf::pdf_one_lobe(const Vec3& wo, const Vec3& wi) const {
    const Lobe& lobe = lobes_[0];
    const Vec3 wo_l = frame_.to_local(wo);
    // selection_probabilities() for one lobe: w / w, or 0 when w is not positive and finite.
    const float w = lobe_sample_weight(lobe, wo_l);
    const float total = 0.0f + w;
    const float prob = w * (total > 0.0f && std::isfinite(total) ? 1.0f / total : 0.0f);
    float scale = visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::fixed_wo_scale(lobe, wo_l); });
    scale = std::isfinite(scale) ? scale : 0.0f;
    const Vec3 wi_l = frame_.to_local(wi);
    if (!sides_consistent(ng_, wo, wi, wo_l, wi_l)) return 0.0f;
    const float p = visit_lobe(lobe.kind, [&](auto k) { return decltype(k)::fixed_wo_pdf(lobe, scale, wo_l, wi_l); });
    const float sum = 0.0f + prob * p;
    return std::isfinite(sum) ? sum : 0.0f;
}

BsdfSample Bsdf::sample(const Vec3& wo, Point2 u, float u_lobe) const {
    if (count_ == 0) return BsdfSample{};
    Vec3 wo_l = frame_.to_local(wo);
    if (!(wo_l.z != 0.0f)) return BsdfSample{};
    float probs[kMaxLobes];
    selection_probabilities(wo_l, probs);

    // Pick a lobe with probability probs[k]; the leftover of u_lobe within the chosen interval is
    // re-stretched to [0,1) and drives the lobe's discrete reflect/refract choice.
    int chosen = -1;
    float start = 0.0f, chosen_start = 0.0f;
    for (int i = 0; i < count_; ++i) {
        if (!(probs[i] > 0.0f)) continue;
        chosen = i;
        chosen_start = start;
        if (u_lobe < start + probs[i]) break;
        start += probs[i];
    }
    if (chosen < 0) return BsdfSample{};
    float u_event = clampf((u_lobe - chosen_start) / probs[chosen], 0.0f, kOneMinusEpsilon);

    BsdfSample ls = lobe_sample(lobes_[chosen], wo_l, u, u_event);
    if (!ls.valid()) return BsdfSample{};
    Vec3 wi = frame_.to_world(ls.wi);
    if (!sides_consistent(ng_, wo, wi, wo_l, ls.wi)) return BsdfSample{};

    BsdfSample out;
    out.wi = wi;
    out.delta = ls.delta;
    out.transmission = ls.transmission;
    out.eta = ls.eta;
    out.lobe = static_cast<int8_t>(chosen);
    if (ls.delta) {
        // Dirac: the other lobes have zero density at this exact direction.
        out.value = ls.value;
        out.pdf = probs[chosen] * ls.pdf;
    } else {
        // One-sample MIS over the lobes (the mixture density), as eval() and pdf() compute it.
        out.value = ls.value;
        out.pdf = probs[chosen] * ls.pdf;
        for (int i = 0; i < count_; ++i) {
            if (i == chosen) continue;
            const Lobe& lobe = lobes_[i];
            EvalPdf r = visit_lobe(lobe.kind, [&](auto k) { return lobe_eval_pdf_of<decltype(k)>(lobe, wo_l, ls.wi); });
            out.value += r.value;
            out.pdf += probs[i] * r.pdf;
        }
        // The mixture with diffuse lobes shadowed; Cycles' walk lobes (multiscatter_cycles_walk) keep
        // their sample's value, the walk's weight, which their eval (a random estimate) is not.
        if (bumped_) out.value = bumped_sample_value(ls.value, chosen, wi, wo_l, ls.wi);
    }
    if (!out.valid()) return BsdfSample{};
    return out;
}

}  // namespace smis
