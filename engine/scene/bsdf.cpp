// BSDF lobes (Lambert, GGX reflection, smooth / GGX-rough dielectric) and the per-hit mixture.
//
// The lobes are modelled on Blender 3.4 Cycles' single-scattering closures:
//  * GGX uses the separable Smith masking-shadowing G = G1(wo) G1(wi), as Cycles 3.4 does.
//  * Sampling uses the distribution of visible normals, Heitz 2018, "Sampling the GGX Distribution of
//    Visible Normals" (JCGT 7(4)). Its pdf is D_wo(wm) = G1(wo) max(0, wo.wm) D(wm) / cos(wo), so
//    eval / pdf collapses to F * G1(wi): the estimator never sees D, which keeps variance low.
//  * The rough dielectric is Walter et al. 2007, "Microfacet Models for Refraction through Rough
//    Surfaces" (EGSR), with the reflect/refract choice made by the Fresnel term of the sampled normal.
//  * Diffuse and Microfacet lobes are one-sided (both wo and wi in the +z hemisphere), like Cycles'
//    closures, which see a normal already flipped towards the viewer.
//  * Refraction scales radiance by (eta_i / eta_t)^2 (see bsdf.h), so value / pdf of a refracted
//    sample is the radiance throughput, not the energy fraction.
//
// Every routine is written so that no input (grazing angles, cos = 0, tiny alpha, eta = 1, NaN
// directions) can make it divide by zero: degenerate configurations return value 0 / pdf 0.
#include "scene/bsdf.h"

namespace smis {

namespace {

// Alpha floor inside the GGX helpers: alpha^4 stays a normal float, so D never overflows to inf.
// Lobes with alpha < kDeltaAlpha never reach the helpers; this only protects direct callers.
constexpr float kMinAlpha = 1e-6f;
// Below this squared length a half vector is considered undefined (its direction is noise).
constexpr float kMinHalfLenSq = 1e-24f;
// Largest float below 1, to keep remapped random numbers in [0, 1).
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
// Cycles' CLOSURE_WEIGHT_CUTOFF: closures with a smaller |average(weight)| are dropped.
constexpr float kClosureWeightCutoff = 1e-5f;

struct EvalPdf {
    Color value{0.0f};
    float pdf = 0.0f;
};

inline float sanitize_alpha(float alpha) { return std::fmax(alpha, kMinAlpha); }  // also maps NaN

}  // namespace

// The lobe kinds after Dielectric (Principled extras, Transparent) are dispatched out of line
// (extra_is_delta, extra_terms, extra_sample), so that the switch over the three base kinds compiles
// as it did before they existed: scenes without them pay nothing per lobe call.
[[gnu::noinline]] bool extra_is_delta(const Lobe& lobe) {
    return lobe.kind == LobeKind::Transparent || (lobe.kind == LobeKind::Clearcoat && !(lobe.alpha >= kDeltaAlpha));
}

namespace {

// Fresnel term of the Microfacet lobe for the angle cos_d between the light direction and the
// microfacet normal.
Color microfacet_fresnel(const Lobe& lobe, float cos_d) {
    switch (lobe.fresnel) {
        case FresnelMode::None: return Color(1.0f);
        case FresnelMode::Schlick: return lobe.f0 + (Color(1.0f) - lobe.f0) * schlick_weight(cos_d);
        case FresnelMode::Dielectric: return Color(fresnel_dielectric(std::fabs(cos_d), lobe.eta));
    }
    return Color(1.0f);
}

// Refraction of `o` (o . m > 0) through a surface with normal m; etap = eta_t / eta_i.
// Returns false on total internal reflection.
bool refract_dir(const Vec3& o, const Vec3& m, float etap, Vec3* wt) {
    float cos_i = dot(o, m);
    float sin2_t = std::max(0.0f, 1.0f - cos_i * cos_i) / (etap * etap);
    if (!(sin2_t < 1.0f)) return false;
    float cos_t = std::sqrt(1.0f - sin2_t);
    Vec3 t = -o / etap + m * (cos_i / etap - cos_t);
    float len2 = length_sq(t);
    if (!(len2 > 0.0f) || !std::isfinite(len2)) return false;
    *wt = t / std::sqrt(len2);
    return true;
}

EvalPdf finite_or_zero(const EvalPdf& r) {
    if (!is_finite(r.value) || !std::isfinite(r.pdf) || !(r.pdf >= 0.0f)) return {};
    return r;
}

// GGX reflection: f cos_i = F D G1(wo) G1(wi) / (4 cos_o), pdf = D_wo(wm) / (4 wo.wm) = G1(wo) D / (4 cos_o).
LobeTerms microfacet_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
    Vec3 h = wo + wi;
    float len2 = length_sq(h);
    if (!(len2 > kMinHalfLenSq)) return {};
    Vec3 wm = h / std::sqrt(len2);
    float alpha = lobe.alpha;
    float d = ggx_D(wm, alpha);
    float g1o = ggx_G1(wo, alpha), g1i = ggx_G1(wi, alpha);
    // pdf of the visible-normal sample after the reflection Jacobian 1/(4 wo.wm): the wo.wm of
    // D_wo cancels the Jacobian's, so nothing here divides by a possibly tiny wo.wm.
    float common = d * g1o / (4.0f * wo.z);
    LobeTerms t;
    t.pdf = common;
    t.geom = common * g1i;
    t.cos_d = dot(wi, wm);
    return t;
}

// Walter et al. 2007 rough dielectric, with the discrete reflect/refract choice made with
// probability F(wo.wm) or 1 - F(wo.wm), so the Fresnel factors cancel in value / pdf.
LobeTerms dielectric_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (!(wo.z != 0.0f) || !(wi.z != 0.0f)) return {};  // also rejects NaN
    // Mirror the configuration so that wo is in the upper hemisphere; +z stays "wo's side".
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    Vec3 o = wo * side, i = wi * side;
    // eta_t / eta_i seen from wo's medium: +z is the outside, eta = inside / outside.
    float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;
    if (!(etap > 0.0f) || !std::isfinite(etap)) return {};
    bool reflect = i.z > 0.0f;

    // (Generalised) half vector: Walter eq. 13 / 16, h_t ~ -(eta_i o + eta_t i).
    Vec3 h = reflect ? o + i : o + i * etap;
    float len2 = length_sq(h);
    if (!(len2 > kMinHalfLenSq)) return {};
    Vec3 wm = h / std::sqrt(len2);
    if (wm.z < 0.0f) wm = -wm;
    float cos_om = dot(o, wm), cos_im = dot(i, wm);
    // Microfacets must be seen from the front by o, and i must lie on the same side of the
    // microfacet as of the macro-surface (the chi+ factors of Walter's G1).
    if (!(cos_om > 0.0f)) return {};
    if (reflect ? !(cos_im > 0.0f) : !(cos_im < 0.0f)) return {};

    float alpha = lobe.alpha;
    float d = ggx_D(wm, alpha);
    float g1o = ggx_G1(o, alpha), g1i = ggx_G1(i, alpha);
    float F = fresnel_dielectric(cos_om, etap);
    LobeTerms r;
    if (reflect) {
        float common = d * g1o / (4.0f * o.z);
        r.pdf = F * common;
        r.geom = F * common * g1i;
    } else {
        // Jacobian of the refraction mapping (Walter eq. 17, divided through by eta_t^2):
        // |dwm/dwi| = |i.wm| / (i.wm + o.wm / etap)^2, and (i.wm + o.wm/etap)^2 = |h|^2 / etap^2
        // exactly, which is bounded away from 0 once index-matched interfaces are excluded.
        float denom = len2 / (etap * etap);
        float dwm_dwi = std::fabs(cos_im) / denom;
        // D_wo(wm) = G1(o) D cos_om / cos_o (Heitz 2018 eq. 3).
        float visible = g1o * d * cos_om / o.z;
        r.pdf = (1.0f - F) * visible * dwm_dwi;
        // f cos_i = (1-F) D G |i.wm| |o.wm| / (denom cos_o); radiance is scaled by (eta_i/eta_t)^2.
        r.geom = (1.0f - F) * visible * dwm_dwi * g1i / (etap * etap);
    }
    return r;
}

// Clearcoat (Cycles 3.4's CLOSURE_BSDF_MICROFACET_GGX_CLEARCOAT_ID, Burley 2012 appendix B.2):
// f cos_i = F(wi.wm) D_GTR1(wm) G1(wo) G1(wi) / (4 cos_o), G1 GGX-Smith with alpha 0.25. Sampled by
// D_GTR1(wm) cos(theta_m) (Burley's eq. 2/5), so pdf = D cos_m / (4 wo.wm) after the reflection Jacobian.
LobeTerms clearcoat_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
    Vec3 h = wo + wi;
    float len2 = length_sq(h);
    if (!(len2 > kMinHalfLenSq)) return {};
    Vec3 wm = h / std::sqrt(len2);
    float cos_om = dot(wo, wm);
    if (!(cos_om > 0.0f)) return {};
    float d = gtr1_D(wm.z, lobe.alpha);
    float g = ggx_G1(wo, kClearcoatShadowAlpha) * ggx_G1(wi, kClearcoatShadowAlpha);
    LobeTerms t;
    t.pdf = d * wm.z / (4.0f * cos_om);
    t.geom = fresnel_dielectric(cos_om, lobe.eta) * d * g / (4.0f * wo.z);
    t.cos_d = cos_om;
    return t;
}

// Principled sheen (Cycles 3.4 bsdf_principled_sheen.h): f cos_i = (1 - wi.h)^5 cos_i, reflection only.
LobeTerms sheen_terms(const Vec3& wo, const Vec3& wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
    Vec3 h = wo + wi;
    float len2 = length_sq(h);
    if (!(len2 > kMinHalfLenSq)) return {};
    LobeTerms t;
    t.pdf = cosine_hemisphere_pdf(wi.z);
    t.geom = schlick_weight(dot(wi, h) / std::sqrt(len2)) * wi.z;
    return t;
}

LobeTerms principled_diffuse_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
    float fv = schlick_weight(wo.z), fl = schlick_weight(wi.z);
    float rr = std::sqrt(lobe.alpha) * (1.0f + dot(wi, wo));
    float f = (1.0f - 0.5f * fv) * (1.0f - 0.5f * fl) + rr * (fl + fv + fl * fv * (rr - 1.0f));
    LobeTerms t;
    t.pdf = cosine_hemisphere_pdf(wi.z);
    t.geom = wi.z * kInvPi * f;
    return t;
}

// The lobe's eval and pdf from its factored terms: weight * Fresnel * geom (bsdf.h, LobeTerms).
EvalPdf lobe_eval_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    LobeTerms t = lobe_terms(lobe, wo, wi);
    EvalPdf r;
    r.pdf = t.pdf;
    r.value = lobe.kind == LobeKind::Microfacet ? lobe.weight * microfacet_fresnel(lobe, t.cos_d) * t.geom
                                                : lobe.weight * t.geom;
    return finite_or_zero(r);
}

// Inlined into both of its callers: as a call (it is shared with the cosine-sampled Principled extras),
// every Lambert sample paid for returning its BsdfSample through memory (+0.5% instructions).
[[gnu::always_inline]] inline BsdfSample sample_diffuse(const Lobe& lobe, const Vec3& wo, Point2 u) {
    BsdfSample s;
    if (!(wo.z > 0.0f)) return s;
    Vec3 wi = sample_cosine_hemisphere(u);
    if (!(wi.z > 0.0f)) return s;  // the disk rim maps onto the horizon
    s.wi = wi;
    s.pdf = cosine_hemisphere_pdf(wi.z);
    s.value = lobe.weight * (wi.z * kInvPi);
    return s;
}

// Burley 2012 eq. 2: cos^2(theta_m) = (1 - alpha^(2 (1 - u))) / (1 - alpha^2) samples D_GTR1 cos(theta_m).
Vec3 gtr1_sample_normal(float alpha, Point2 u) {
    float a2 = alpha * alpha;
    float cos2 = a2 >= 1.0f - 1e-4f ? 1.0f - u.x : (1.0f - std::exp((1.0f - u.x) * std::log(a2))) / (1.0f - a2);
    cos2 = clampf(cos2, 0.0f, 1.0f);
    float sin_t = std::sqrt(1.0f - cos2), phi = 2.0f * kPi * u.y;
    return Vec3(sin_t * std::cos(phi), sin_t * std::sin(phi), std::sqrt(cos2));
}

// The perfect mirror of a delta reflection lobe, carrying `value` (weight x Fresnel).
[[gnu::always_inline]] inline BsdfSample mirror_sample(const Vec3& wo, const Color& value) {
    BsdfSample s;
    s.wi = Vec3(-wo.x, -wo.y, wo.z);
    s.value = value;
    s.pdf = 1.0f;
    s.delta = true;
    return s;
}

// wo reflected about the sampled microfacet normal wm, evaluated through the same code path as
// eval()/pdf() so that the three always agree.
[[gnu::always_inline]] inline BsdfSample reflect_about(const Lobe& lobe, const Vec3& wo, const Vec3& wm) {
    BsdfSample s;
    Vec3 wi = reflect(wo, wm);
    if (!(wi.z > 0.0f)) return s;  // reflected below the horizon: the single-scatter energy loss
    wi = normalize(wi);
    EvalPdf r = lobe_eval_pdf(lobe, wo, wi);
    if (!(r.pdf > 0.0f)) return s;
    s.wi = wi;
    s.value = r.value;
    s.pdf = r.pdf;
    return s;
}

BsdfSample sample_clearcoat(const Lobe& lobe, const Vec3& wo, Point2 u) {
    if (!(wo.z > 0.0f)) return {};
    // As Cycles' specular case: the Fresnel-weighted mirror, no shadowing.
    if (lobe_is_delta(lobe)) return mirror_sample(wo, lobe.weight * fresnel_dielectric(wo.z, lobe.eta));
    Vec3 wm = gtr1_sample_normal(lobe.alpha, u);
    if (!(dot(wo, wm) > 0.0f)) return {};  // back-facing normal: the reflection would leave the hemisphere
    return reflect_about(lobe, wo, wm);
}

BsdfSample sample_microfacet(const Lobe& lobe, const Vec3& wo, Point2 u) {
    if (!(wo.z > 0.0f)) return {};
    if (lobe_is_delta(lobe)) return mirror_sample(wo, lobe.weight * microfacet_fresnel(lobe, wo.z));
    return reflect_about(lobe, wo, ggx_sample_visible_normal(wo, lobe.alpha, u));
}

BsdfSample sample_dielectric(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
    BsdfSample s;
    if (!(wo.z != 0.0f)) return s;
    float side = wo.z > 0.0f ? 1.0f : -1.0f;
    float etap = wo.z > 0.0f ? lobe.eta : 1.0f / lobe.eta;  // eta_t / eta_i
    if (!(etap > 0.0f) || !std::isfinite(etap)) return s;

    if (lobe_is_delta(lobe)) {
        // Smooth interface: choose the event with its exact Fresnel probability; value / pdf is the
        // throughput multiplier (weight for reflection, weight (eta_i/eta_t)^2 for refraction).
        float cos_o = std::fabs(wo.z);
        float F = fresnel_dielectric(cos_o, etap);
        if (u_event < F) {
            s.wi = Vec3(-wo.x, -wo.y, wo.z);
            s.value = lobe.weight * F;
            s.pdf = F;
        } else {
            Vec3 wt;
            if (!refract_dir(wo * side, Vec3(0, 0, 1), etap, &wt)) return BsdfSample{};
            s.wi = wt * side;
            s.value = lobe.weight * ((1.0f - F) / (etap * etap));
            s.pdf = 1.0f - F;
            s.eta = etap;
            s.transmission = true;
        }
        s.delta = true;
        if (!s.valid()) return BsdfSample{};
        return s;
    }

    Vec3 o = wo * side;
    Vec3 wm = ggx_sample_visible_normal(o, lobe.alpha, u);
    float cos_om = dot(o, wm);
    if (!(cos_om > 0.0f)) return s;
    float F = fresnel_dielectric(cos_om, etap);
    Vec3 i;
    bool transmission = !(u_event < F);  // F = 1 under total internal reflection
    if (!transmission) {
        i = reflect(o, wm);
        if (!(i.z > 0.0f)) return s;
        i = normalize(i);
    } else {
        if (!refract_dir(o, wm, etap, &i) || !(i.z < 0.0f)) return s;
    }
    Vec3 wi = i * side;
    EvalPdf r = lobe_eval_pdf(lobe, wo, wi);
    if (!(r.pdf > 0.0f)) return s;
    s.wi = wi;
    s.value = r.value;
    s.pdf = r.pdf;
    s.transmission = transmission;
    s.eta = transmission ? etap : 1.0f;
    return s;
}

[[gnu::noinline]] LobeTerms extra_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    switch (lobe.kind) {
        case LobeKind::Clearcoat: return clearcoat_terms(lobe, wo, wi);
        case LobeKind::Sheen: return sheen_terms(wo, wi);
        case LobeKind::PrincipledDiffuse: return principled_diffuse_terms(lobe, wo, wi);
        default: return {};  // Transparent: a Dirac (lobe_terms returns before)
    }
}

[[gnu::noinline]] BsdfSample extra_sample(const Lobe& lobe, const Vec3& wo, Point2 u) {
    BsdfSample s;
    switch (lobe.kind) {
        case LobeKind::Clearcoat: return sample_clearcoat(lobe, wo, u);
        case LobeKind::Transparent:  // no refraction: same medium, no radiance scaling (eta 1)
            s.wi = -wo;
            s.value = lobe.weight;
            s.pdf = 1.0f;
            s.delta = true;
            s.transmission = true;
            return s;
        default:  // Sheen, PrincipledDiffuse: cosine sampling, evaluated through lobe_eval_pdf
            s = sample_diffuse(lobe, wo, u);
            if (s.pdf > 0.0f) s.value = lobe_eval_pdf(lobe, wo, s.wi).value;
            return s;
    }
}

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

float ggx_D(const Vec3& wm, float alpha) {
    if (!(wm.z > 0.0f)) return 0.0f;
    float a2 = sqr(sanitize_alpha(alpha));
    // 1 + cos^2 (a^2 - 1) written as sin^2 + a^2 cos^2: no cancellation when alpha is tiny.
    float cos2 = wm.z * wm.z;
    float sin2 = wm.x * wm.x + wm.y * wm.y;
    float t = sin2 + a2 * cos2;
    float denom = kPi * t * t;
    if (!(denom > 0.0f)) return 0.0f;
    float d = a2 / denom;
    return std::isfinite(d) ? d : 0.0f;
}

float ggx_G1(const Vec3& w, float alpha) {
    // Smith G1 = 1 / (1 + Lambda) = 2 / (1 + sqrt(1 + alpha^2 tan^2)); |cos| so it also serves the
    // transmitted direction of the dielectric (the sidedness chi+ is checked by the callers).
    float cos2 = w.z * w.z;
    if (!(cos2 > 0.0f)) return 0.0f;
    float sin2 = std::max(0.0f, w.x * w.x + w.y * w.y);
    float a2 = sqr(sanitize_alpha(alpha));
    float tan2 = sin2 / cos2;  // may be +inf at grazing angles: G1 -> 0, which is the limit
    float g = 2.0f / (1.0f + std::sqrt(1.0f + a2 * tan2));
    return std::isfinite(g) ? g : 0.0f;
}

float gtr1_D(float cos_m, float alpha) {
    if (!(cos_m > 0.0f)) return 0.0f;
    float a2 = sqr(sanitize_alpha(alpha));
    if (a2 >= 1.0f - 1e-4f) return kInvPi;  // (a2 - 1) / log(a2) -> 1
    float d = (a2 - 1.0f) / (kPi * std::log(a2) * (1.0f + (a2 - 1.0f) * cos_m * cos_m));
    return std::isfinite(d) ? d : 0.0f;
}

// Heitz 2018, listing 1. wo is mirrored into the upper hemisphere (D is symmetric); the returned
// normal always has z >= 0.
Vec3 ggx_sample_visible_normal(const Vec3& wo_in, float alpha, Point2 u) {
    alpha = sanitize_alpha(alpha);
    Vec3 wo = wo_in.z < 0.0f ? -wo_in : wo_in;
    // Stretch the view direction to the hemisphere configuration (alpha = 1).
    Vec3 vh(alpha * wo.x, alpha * wo.y, wo.z);
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
    Vec3 ne(alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z));
    float nlen2 = length_sq(ne);
    if (!(nlen2 > 0.0f) || !std::isfinite(nlen2)) return Vec3(0, 0, 1);
    return ne / std::sqrt(nlen2);
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

Color lobe_eval(const Lobe& lobe, const Vec3& wo, const Vec3& wi) { return lobe_eval_pdf(lobe, wo, wi).value; }

LobeTerms lobe_terms(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (lobe_is_delta(lobe)) return {};
    LobeTerms t;
    switch (lobe.kind) {
        case LobeKind::Diffuse:
            if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return {};
            t.pdf = cosine_hemisphere_pdf(wi.z);
            t.geom = wi.z * kInvPi;
            break;
        case LobeKind::Microfacet: t = microfacet_terms(lobe, wo, wi); break;
        case LobeKind::Dielectric: t = dielectric_terms(lobe, wo, wi); break;
        default: t = kWithPrincipledExtras ? extra_terms(lobe, wo, wi) : LobeTerms{}; break;
    }
    if (!std::isfinite(t.geom) || !std::isfinite(t.pdf) || !(t.pdf >= 0.0f)) return {};
    return t;
}

float lobe_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi) { return lobe_eval_pdf(lobe, wo, wi).pdf; }

BsdfSample lobe_sample(const Lobe& lobe, const Vec3& wo, Point2 u, float u_event) {
    BsdfSample s;
    switch (lobe.kind) {
        case LobeKind::Diffuse: s = sample_diffuse(lobe, wo, u); break;
        case LobeKind::Microfacet: s = sample_microfacet(lobe, wo, u); break;
        case LobeKind::Dielectric: s = sample_dielectric(lobe, wo, u, u_event); break;
        default: s = kWithPrincipledExtras ? extra_sample(lobe, wo, u) : BsdfSample{}; break;
    }
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
    l.eta = std::isfinite(l.eta) ? std::fmax(l.eta, 1e-5f) : 1.0f;
    if (lobe_is_delta(l)) ++delta_count_;
    lobes_[count_++] = l;
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
    for (int i = 0; i < count_; ++i) sum += lobe_eval(lobes_[i], wo_l, wi_l);
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
    const Vec3& o = f.wo_local;
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        float scale = 0.0f;
        if (o.z > 0.0f && !lobe_is_delta(lobe)) {
            if (lobe.kind == LobeKind::Diffuse) scale = kInvPi;
            else if (lobe.kind == LobeKind::Microfacet) scale = ggx_G1(o, lobe.alpha) / (4.0f * o.z);
        }
        f.pdf_scale[i] = std::isfinite(scale) ? scale : 0.0f;
    }
    return f;
}

// The same densities as lobe_pdf(), without evaluating the BSDF values: path-space filtering sums
// k^2 of them per pixel (eq. 17). Dielectric lobes and the Principled extras (clearcoat, sheen) take
// the general route; one comparison covers them all (LobeKind order), so the common lobes pay nothing.
float Bsdf::pdf(const FixedWo& fixed, const Vec3& wi) const {
    if (count_ == 0) return 0.0f;
    Vec3 wi_l = frame_.to_local(wi);
    if (!sides_consistent(ng_, fixed.wo, wi, fixed.wo_local, wi_l)) return 0.0f;
    const Vec3& wo_l = fixed.wo_local;
    float sum = 0.0f;
    for (int i = 0; i < count_; ++i) {
        const Lobe& lobe = lobes_[i];
        float p = 0.0f;
        if (lobe.kind >= LobeKind::Dielectric) {
            p = lobe_pdf(lobe, wo_l, wi_l);
        } else if (fixed.pdf_scale[i] > 0.0f && wi_l.z > 0.0f) {
            if (lobe.kind == LobeKind::Diffuse) {
                p = wi_l.z * fixed.pdf_scale[i];
            } else {
                Vec3 h = wo_l + wi_l;
                float len2 = length_sq(h);
                if (len2 > kMinHalfLenSq) p = ggx_D(h / std::sqrt(len2), lobe.alpha) * fixed.pdf_scale[i];
            }
        }
        sum += fixed.probs[i] * p;
    }
    return std::isfinite(sum) ? sum : 0.0f;
}

float Bsdf::pdf(const Vec3& wo, const Vec3& wi) const {
    if (count_ == 0) return 0.0f;
    return pdf(fix_wo(wo), wi);
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
            EvalPdf r = lobe_eval_pdf(lobes_[i], wo_l, ls.wi);
            out.value += r.value;
            out.pdf += probs[i] * r.pdf;
        }
        if (bumped_) out.value = eval_bumped(wi, wo_l, ls.wi);  // the mixture with diffuse lobes shadowed
    }
    if (!out.valid()) return BsdfSample{};
    return out;
}

}  // namespace smis
