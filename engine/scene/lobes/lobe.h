// One BSDF lobe: its parameters, what its routines return, and the interface every lobe kind provides.
//
// Conventions (shared by every lobe and by the integrators):
//  * Lobes work in the local shading frame: +z is the shading normal, wo points away from the surface
//    (towards the previous vertex), wi is the sampled / queried direction, also pointing away.
//  * eval() returns f(wo, wi) * |cos theta_i|  (the BSDF times the foreshortening of wi), like Mitsuba.
//  * pdf() is the solid-angle density of sample() producing wi; sample() returns the same value as
//    eval()/pdf() for non-delta lobes (value = eval, pdf = pdf), so sample(), eval() and pdf() agree.
//  * Delta lobes (smooth mirror, smooth glass) return delta = true from sample(); pdf is the
//    probability of the discrete event chosen (e.g. F for reflection off glass) and value/pdf is the
//    throughput multiplier of that event; eval()/pdf() return 0 for them.
//  * Radiance transport: refraction from IOR eta_i into eta_t scales radiance by (eta_i/eta_t)^2.
//
// Each kind is a struct in its own header of this folder (diffuse.h, microfacet.h, ...) with these
// static members; lobes/dispatch.h lists the kinds and calls them, so a kind that lacks one of them
// does not compile, and a LobeKind without its struct fails dispatch.h's static_asserts:
//   kKind, kName                      the enum value, and the kind's name in the Python bindings
//   kEnabled, kFeature                compiled in (core/features.h), and the SMIS_WITHOUT name (or nullptr)
//   kLabel                            the ray label of its scattered rays (Light Path, bump shadowing)
//   kDensity                          its density model for path-space filtering (psf_density.h)
//   kSpectral, kDispersive            its spectral terms (spectral_path.cpp): where its Fresnel lives,
//                                     and whether its Dirac refraction disperses
//   kBackfaceInvertsEta               its IOR is inverted when the hit is on the back face (glass)
//   kOwnTangent                       an anisotropic lobe about its own tangent (to_lobe_tangent)
//   kTinted                           eval = weight * fresnel(cos_d) * geom (else weight * geom)
//   kColourEval                       eval and pdf from eval_pdf(lobe, wo, wi) and pdf(lobe, wo, wi), not
//                                     from terms() (a colour no product weight x Fresnel x geom gives)
//   is_delta(lobe)                    a Dirac lobe (no eval/pdf)
//   terms(lobe, wo, wi)               eval and pdf, factored (LobeTerms)
//   fresnel(lobe, cos_d)              the RGB Fresnel factor on top of terms().geom (kTinted lobes)
//   sample(lobe, wo, u, u_event)      a direction with its value and pdf (BsdfSample)
//   fixed_wo_scale(lobe, wo)          the wo-only factor of its pdf (0: none), for many wi with one wo
//   fixed_wo_pdf(lobe, scale, wo, wi) its pdf from that factor (Bsdf::pdf(FixedWo, wi))
//   albedo(lobe)                      its reflectance for the Albedo pass
// Kinds derive from LobeDefaults<Kind>, which supplies the pieces most kinds share (see there).
#pragma once
#include "core/features.h"
#include "core/math.h"
#include "core/sampling.h"

namespace smis {

// The order of the kinds is their index in dispatch.h's list; new kinds are appended.
enum class LobeKind : uint8_t {
    Diffuse,      // Lambert: color / pi
    Microfacet,   // GGX reflection (Glossy BSDF, metals, Principled specular); fresnel selects the tint
    Dielectric,   // glass: Fresnel-weighted reflection + refraction, smooth (alpha = 0) or GGX-rough
    Clearcoat,    // Principled clearcoat (lobes/clearcoat.h)
    Sheen,        // Principled sheen (lobes/sheen.h)
    Transparent,  // Transparent BSDF's coloured part: a Dirac straight through (wi = -wo), value = weight
    PrincipledDiffuse,  // Cycles 3.4's principled diffuse (lobes/principled_diffuse.h)
    OrenNayar,    // Diffuse BSDF with Roughness > 0 (lobes/oren_nayar.h)
    Velvet,       // Velvet BSDF (lobes/velvet.h)
    Translucent,  // Translucent BSDF (lobes/translucent.h)
    Refraction,   // Refraction BSDF (lobes/refraction.h)
    Beckmann,     // Glossy BSDF with the Beckmann distribution (lobes/beckmann.h)
    ToonDiffuse,  // Toon BSDF, Diffuse (lobes/toon_diffuse.h)
    ToonGlossy,   // Toon BSDF, Glossy (lobes/toon_glossy.h)
    MultiGgx,     // Multiscatter GGX, its single scattering (lobes/multiscatter_ggx.h)
    GgxMultiple,  // Multiscatter GGX, the energy of its multiple scattering (lobes/multiscatter_ggx.h)
    AnisoGgx,     // Anisotropic GGX: Anisotropic BSDF, Principled Anisotropic (lobes/anisotropic.h)
    AnisoBeckmann,  // Anisotropic BSDF with the Beckmann distribution (lobes/anisotropic.h)
    PrincipledGlass,  // Principled BSDF's transmission (lobes/principled_glass.h)
    Subsurface,   // a BSSRDF's entry: the path tracer walks inside the object (lobes/subsurface.h)
    PrincipledPart,  // one component of Cycles' principled diffuse (lobes/principled_part.h)
    HairReflection,    // Hair BSDF, Reflection (lobes/hair.h)
    HairTransmission,  // Hair BSDF, Transmission (lobes/hair.h)
    PrincipledHairR,     // Principled Hair BSDF, its four paths R, TT, TRT, TRRT+ (lobes/principled_hair.h)
    PrincipledHairTT,
    PrincipledHairTRT,
    PrincipledHairTRRT,
    MultiGlass,     // Multiscatter GGX glass, its single scattering (lobes/multi_glass.h)
    GlassMultiple,  // Multiscatter GGX glass, its multiple scattering (lobes/glass_multiple.h)
    AshikhminShirley,  // Glossy / Anisotropic BSDF with the Ashikhmin-Shirley distribution (lobes/ashikhmin_shirley.h)
    MultiAnisoGgx,     // anisotropic Multiscatter GGX, its single scattering (lobes/multiscatter_aniso_ggx.h)
    AnisoGgxMultiple,  // anisotropic Multiscatter GGX, its multiple scattering (lobes/multiscatter_aniso_ggx.h)
    MultiGgxWalk,      // Multiscatter GGX as Cycles estimates it, on request (lobes/multiscatter_walk.h)
    MultiGlassWalk,    // Multiscatter GGX glass as Cycles estimates it, on request (lobes/multi_glass_walk.h)
    Count
};

enum class FresnelMode : uint8_t {
    None,        // F = 1: Cycles' Glossy BSDF (the colour is the weight)
    Schlick,     // F = f0 + (1 - f0)(1 - cos)^5 with coloured f0: Principled metallic
    Dielectric,  // exact dielectric Fresnel with `eta`: Principled specular layer on top of diffuse
};

// Which of Cycles' pair of glass closures (reflection weighted by F, refraction by 1 - F) a
// Dielectric lobe holds: both, unless a caustics toggle left one out (lobe_ray_types.h).
constexpr uint8_t kGlassReflection = 1, kGlassRefraction = 2, kGlassBoth = 3;

struct Lobe {
    LobeKind kind = LobeKind::Diffuse;
    FresnelMode fresnel = FresnelMode::None;
    uint8_t index = 0;   // position in the material's lobe list (set by Scene::add_material; spectral data)
    uint8_t glass_events = kGlassBoth;  // Dielectric and PrincipledGlass only (in the padding before weight)
    uint8_t variant = 0; // a kind's sub-mode (PrincipledPart's component, Subsurface's method and exit)
    Color weight{1.0f};  // closure weight (colour x mix factors)
    Color f0{1.0f};      // Schlick reflectance at normal incidence (FresnelMode::Schlick); f0.x: Toon's
                         // Smooth, the hair lobes' Offset
    float alpha = 0.0f;  // GGX alpha = roughness^2 (Blender's convention); below kDeltaAlpha -> delta
    float eta = 1.5f;    // IOR of the inside over the outside (Dielectric lobe / FresnelMode::Dielectric)
    float alpha_y = 0.0f;  // anisotropic lobes: alpha across the tangent (alpha is along it, the frame's s);
                           // GlassMultiple: the albedo its weight holds (lobes/glass_multiple.h)
    // A colour parameter of the lobe's own kind: Subsurface's mean free path per channel
    // (lobes/subsurface.h), the Principled glass' Specular Tint in x (lobes/principled_glass.h), an
    // anisotropic lobe's own tangent in the Bsdf's frame (kOwnTangent: lobe_detail::to_lobe_tangent).
    // One field for all keeps Lobe small: every hit copies its lobes.
    Color kind_colour{0.0f};
};

// N lobe slots that start unconstructed: a mixture reads only the slots it filled (by assigning
// whole lobes), and every shaded hit builds several arrays of them (its shader's result, the Bsdf
// made from it, the shading point's), whose default member initialisers cost more than the one
// or two lobes a hit holds (callgrind, PATH, 240x135, 4 spp: textured_plane -1.8 %, cornell -1.4 %
// of the render loop's instructions). Copies copy every slot's bytes (a union's object
// representation), as the array did.
template <int N>
struct LobeSlots {
    LobeSlots() {}
    Lobe& operator[](int i) { return slot[i]; }
    const Lobe& operator[](int i) const { return slot[i]; }
    union {
        Lobe slot[N];
    };
};

// The label of the rays a lobe scatters (Cycles' LABEL_DIFFUSE / GLOSSY / TRANSPARENT): Light Path
// outputs, the depth counters, and which lobes the bump shadowing term darkens (diffuse ones).
enum class RayLabel : uint8_t { Diffuse, Glossy, Transparent };

// Path-space filtering's density model of a lobe (psf_density.h): cosine sampled, GGX visible-normal
// sampled (one shared alpha per technique), or anything else (the technique keeps its Bsdf).
enum class DensityModel : uint8_t { Cosine, Ggx, General };

// Where a lobe's Fresnel lives, for the spectral tracer (spectral_path.cpp):
//   None   value = weight x geom; a Dirac event's throughput is weight (times the radiance scaling of
//          a refraction), the dispersion of kDispersive lobes applied on top;
//   Tinted value = weight x F_lambda(cos_d) x geom, F from FresnelMode or the material's measured metal;
//   Fixed  a wavelength-independent Fresnel at the lobe's own IOR, inside geom and multiplying its
//          Dirac event's throughput.
enum class SpectralFresnel : uint8_t { None, Tinted, Fixed };

// Schlick's (1 - cos)^5, shared by the RGB and spectral Fresnel of FresnelMode::Schlick.
inline float schlick_weight(float cos_d) {
    float m = clampf(1.0f - std::fabs(cos_d), 0.0f, 1.0f);
    return (m * m) * (m * m) * m;
}

// Roughness under which a microfacet lobe is treated as a perfect (delta) reflector/refractor,
// as Cycles does; evaluating GGX with smaller alpha only produces fireflies.
constexpr float kDeltaAlpha = 1e-4f;
// A rough dielectric whose |eta - 1| is below this is an index-matched interface: the transmission
// lobe collapses onto -wo whatever the roughness and the Walter Jacobian becomes singular
// (the generalised half vector wo + eta wi vanishes), so it is treated as the smooth (delta) case.
constexpr float kIndexMatchedEps = 1e-3f;
// Below this squared length a half vector is considered undefined (its direction is noise).
constexpr float kMinHalfLenSq = 1e-24f;

struct BsdfSample {
    Vec3 wi;                 // sampled direction (local frame for Lobe, world frame for Bsdf)
    Color value{0.0f};       // eval(wo, wi) for non-delta, Dirac weight for delta lobes
    float pdf = 0.0f;        // solid-angle pdf (non-delta); probability of the discrete event (delta)
    float eta = 1.0f;        // relative IOR crossed by wi (1 for reflection), for Russian roulette
    bool delta = false;
    bool transmission = false;
    int8_t lobe = -1;        // the Bsdf's lobe that was sampled (Bsdf::sample only)
    bool valid() const { return pdf > 0.0f && std::isfinite(pdf) && is_finite(value); }
};

// eval() factored as weight * fresnel(cos_d) * geom, where only kTinted lobes have a Fresnel
// factor (at the angle cos_d between wi and the microfacet normal; the dielectric lobe's Fresnel is
// inside geom). Spectral rendering evaluates weight and Fresnel per wavelength on top of the
// wavelength-independent geom; pdf is the same as lobe_pdf(). Zero for Dirac lobes.
struct LobeTerms {
    float geom = 0.0f, cos_d = 1.0f, pdf = 0.0f;
};

struct EvalPdf {
    Color value{0.0f};
    float pdf = 0.0f;
};

// The dispatched pdf of any lobe (bsdf.cpp).
float lobe_pdf(const Lobe& lobe, const Vec3& wo, const Vec3& wi);

// Shared math of the lobes, defined in bsdf.cpp: the one translation unit that evaluates lobes, so
// that these inline into them.
Vec3 ggx_sample_visible_normal(const Vec3& wo, float alpha, Point2 u);
Vec3 ggx_sample_visible_normal(const Vec3& wo, float alpha_x, float alpha_y, Point2 u);  // anisotropic
// A visible normal of the isotropic Beckmann distribution of roughness alpha seen from wo (wo.z > 0),
// and Smith's exact masking of that distribution (both for lobes/anisotropic.h's Cycles sampler).
Vec3 beckmann_sample_visible_normal(const Vec3& wo, float alpha, Point2 u);
float beckmann_smith_G1(const Vec3& w, float alpha);
float fresnel_dielectric(float cos_i, float eta);
// Burley 2012's GTR1 (gamma = 1) normal distribution of the clearcoat, normalised so that
// integral D(m) cos(theta_m) dm = 1; alpha >= 1 is the uniform-in-cosine limit 1/pi.
float gtr1_D(float cos_m, float alpha);

namespace lobe_detail {

// Alpha floor inside the GGX helpers: alpha^4 stays a normal float, so D never overflows to inf.
// Lobes with alpha < kDeltaAlpha never reach the helpers; this only protects direct callers.
constexpr float kMinAlpha = 1e-6f;
inline float sanitize_alpha(float alpha) { return std::fmax(alpha, kMinAlpha); }  // also maps NaN

inline EvalPdf finite_or_zero(const EvalPdf& r) {
    if (!is_finite(r.value) || !std::isfinite(r.pdf) || !(r.pdf >= 0.0f)) return {};
    return r;
}

// Refraction of `o` (o . m > 0) through a surface with normal m; etap = eta_t / eta_i.
// Returns false on total internal reflection.
inline bool refract_dir(const Vec3& o, const Vec3& m, float etap, Vec3* wt) {
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

// The half vector of a reflection with wo and wi above the surface, or false where it is undefined.
inline bool reflection_half_vector(const Vec3& wo, const Vec3& wi, Vec3* wm) {
    if (!(wo.z > 0.0f) || !(wi.z > 0.0f)) return false;
    Vec3 h = wo + wi;
    float len2 = length_sq(h);
    if (!(len2 > kMinHalfLenSq)) return false;
    *wm = h / std::sqrt(len2);
    return true;
}

// An anisotropic lobe's own tangent (kOwnTangent kinds): Cycles gives every anisotropic closure its
// Tangent and Rotation, a Bsdf has one frame. Scene::program_bsdf stores the lobe's tangent direction
// (cos phi, sin phi) in that frame as kind_colour = (cos phi - 1, sin phi), so that the default 0 is the
// frame's own s axis; these turn a direction of the Bsdf's frame into the lobe's (x along its tangent,
// y = n x tangent, as Cycles' make_orthonormals_tangent) and back.
inline Vec3 to_lobe_tangent(const Lobe& lobe, const Vec3& w) {
    float c = 1.0f + lobe.kind_colour.x, s = lobe.kind_colour.y;
    return Vec3(c * w.x + s * w.y, c * w.y - s * w.x, w.z);
}
inline Vec3 from_lobe_tangent(const Lobe& lobe, const Vec3& w) {
    float c = 1.0f + lobe.kind_colour.x, s = lobe.kind_colour.y;
    return Vec3(c * w.x - s * w.y, s * w.x + c * w.y, w.z);
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

// A cosine-weighted direction about +z valued as Lambert (value = weight cos / pi); the lobes that
// share cosine sampling re-evaluate the value with their own terms.
[[gnu::always_inline]] inline BsdfSample sample_cosine(const Lobe& lobe, const Vec3& wo, Point2 u) {
    BsdfSample s;
    if (!(wo.z > 0.0f)) return s;
    Vec3 wi = sample_cosine_hemisphere(u);
    if (!(wi.z > 0.0f)) return s;  // the disk rim maps onto the horizon
    s.wi = wi;
    s.pdf = cosine_hemisphere_pdf(wi.z);
    s.value = lobe.weight * (wi.z * kInvPi);
    return s;
}

}  // namespace lobe_detail

// GGX (Trowbridge-Reitz) normal distribution and Smith masking, inline: every GGX lobe evaluation
// needs them.
inline float ggx_D(const Vec3& wm, float alpha) {
    if (!(wm.z > 0.0f)) return 0.0f;
    float a2 = sqr(lobe_detail::sanitize_alpha(alpha));
    // 1 + cos^2 (a^2 - 1) written as sin^2 + a^2 cos^2: no cancellation when alpha is tiny.
    float cos2 = wm.z * wm.z;
    float sin2 = wm.x * wm.x + wm.y * wm.y;
    float t = sin2 + a2 * cos2;
    float denom = kPi * t * t;
    if (!(denom > 0.0f)) return 0.0f;
    float d = a2 / denom;
    return std::isfinite(d) ? d : 0.0f;
}

inline float ggx_G1(const Vec3& w, float alpha) {
    // Smith G1 = 1 / (1 + Lambda) = 2 / (1 + sqrt(1 + alpha^2 tan^2)); |cos| so it also serves the
    // transmitted direction of the dielectric (the sidedness chi+ is checked by the callers).
    float cos2 = w.z * w.z;
    if (!(cos2 > 0.0f)) return 0.0f;
    float sin2 = std::max(0.0f, w.x * w.x + w.y * w.y);
    float a2 = sqr(lobe_detail::sanitize_alpha(alpha));
    float tan2 = sin2 / cos2;  // may be +inf at grazing angles: G1 -> 0, which is the limit
    float g = 2.0f / (1.0f + std::sqrt(1.0f + a2 * tan2));
    return std::isfinite(g) ? g : 0.0f;
}

// The checked terms of lobe kind L: zero for Dirac configurations and for non-finite results.
template <class L>
inline LobeTerms lobe_terms_of(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if (L::is_delta(lobe)) return {};
    LobeTerms t = L::terms(lobe, wo, wi);
    if (!std::isfinite(t.geom) || !std::isfinite(t.pdf) || !(t.pdf >= 0.0f)) return {};
    return t;
}

// eval and pdf of lobe kind L from its factored terms: weight * Fresnel * geom.
template <class L>
inline EvalPdf lobe_eval_pdf_of(const Lobe& lobe, const Vec3& wo, const Vec3& wi) {
    if constexpr (L::kColourEval) return lobe_detail::finite_or_zero(L::eval_pdf(lobe, wo, wi));
    LobeTerms t = lobe_terms_of<L>(lobe, wo, wi);
    EvalPdf r;
    r.pdf = t.pdf;
    if constexpr (L::kTinted) r.value = lobe.weight * L::fresnel(lobe, t.cos_d) * t.geom;
    else r.value = lobe.weight * t.geom;
    return lobe_detail::finite_or_zero(r);
}

// A sampled direction of lobe kind L valued through the same code as eval()/pdf(), so that the three
// always agree; `transmission`/`eta` describe the crossing, if any.
template <class L>
inline BsdfSample lobe_sample_at(const Lobe& lobe, const Vec3& wo, const Vec3& wi, bool transmission = false,
                                 float eta = 1.0f) {
    BsdfSample s;
    EvalPdf r = lobe_eval_pdf_of<L>(lobe, wo, wi);
    if (!(r.pdf > 0.0f)) return s;
    s.wi = wi;
    s.value = r.value;
    s.pdf = r.pdf;
    s.transmission = transmission;
    s.eta = eta;
    return s;
}

// A cosine-weighted direction of a cosine-sampled kind L, valued by L's own eval.
template <class L>
inline BsdfSample cosine_sample_of(const Lobe& lobe, const Vec3& wo, Point2 u) {
    BsdfSample s = lobe_detail::sample_cosine(lobe, wo, u);
    if (s.pdf > 0.0f) s.value = lobe_eval_pdf_of<L>(lobe, wo, s.wi).value;
    return s;
}

// What a lobe kind inherits unless it says otherwise (CRTP: Self is the kind). Only the pieces most
// kinds share: every kind states its label, density model, spectral terms, albedo, is_delta, terms
// and sample itself (dispatch.h does not compile without them).
template <class Self>
struct LobeDefaults {
    static constexpr bool kTinted = false;  // no Fresnel factor outside terms().geom
    static constexpr bool kDispersive = false;
    static constexpr bool kBackfaceInvertsEta = false;
    static constexpr bool kOwnTangent = false;  // kind_colour is its tangent in the frame (to_lobe_tangent)
    static constexpr bool kColourEval = false;  // eval_pdf() and pdf() instead of terms() (lobe.h's list)
    static Color fresnel(const Lobe&, float) { return Color(1.0f); }
    // No wo-only shortcut: fixed_wo_pdf evaluates the lobe (out of line, so that the loops over the
    // lobes inline only the shortcuts).
    static float fixed_wo_scale(const Lobe&, const Vec3&) { return 0.0f; }
    static float fixed_wo_pdf(const Lobe& lobe, float, const Vec3& wo, const Vec3& wi) { return lobe_pdf(lobe, wo, wi); }
    // Spectral terms of kTinted lobes: f0 is a colour to upsample (FresnelMode::Schlick), a measured
    // metal replaces the Fresnel (all but the dielectric layer), and the Fresnel factor at one
    // wavelength from f0_at(), the lobe's f0 there.
    static bool colour_f0(const Lobe& lobe) { return lobe.fresnel == FresnelMode::Schlick; }
    static bool measured_metal(const Lobe& lobe) { return lobe.fresnel != FresnelMode::Dielectric; }
    template <class F0At>
    static float spectral_colour(const Lobe& lobe, F0At&& f0_at, float cos_d) {
        switch (lobe.fresnel) {
            case FresnelMode::None: return 1.0f;
            case FresnelMode::Schlick: {
                float f0 = f0_at();
                return f0 + (1.0f - f0) * schlick_weight(cos_d);
            }
            case FresnelMode::Dielectric: return fresnel_dielectric(std::fabs(cos_d), lobe.eta);
        }
        return 1.0f;
    }
};

}  // namespace smis
