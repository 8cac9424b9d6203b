// The records path-space filtering keeps per pixel between its two stages (path_space_filtering.cpp,
// and its spectral stage 1, psf_spectral.cpp). Internal to those files.
#pragma once
#include <algorithm>

#include "integrators/camera_prefix.h"
#include "integrators/path_tracing.h"
#include "integrators/volume.h"

namespace smis {
namespace psf_detail {

// What a camera prefix (camera_prefix.h) left at x1, its first non-specular vertex, with x1's
// shading point: the RGB and spectral prefix policies record it (psf_rgb.cpp, psf_spectral.cpp).
// Its distance sets the radius.
struct X1PrefixEnd : PrefixEnd {
    ShadingPoint sp;
};

// A suffix's first vertex z1 and what it carried back, as stage 2 reads it.
struct SuffixVertex {
    Vec3 z, z_ng, z_ns;       // z1, its geometric and shading normals (both on the geometric side)
    uint32_t z_material = 0;
    Color L_out{0.0f};        // radiance leaving z1 towards x1, emission at z1 excluded (with media: as
                              // it arrives at x1, times the segment's transmittance)
    // z1's own estimators, kept so the unbiased variant can re-evaluate z1's BSDF for another x1:
    // L_out(wo) = f(wo, nee_dir) nee_weighted + f(wo, next_dir) next_weighted.
    Vec3 nee_dir, next_dir;
    Color nee_weighted{0.0f}, next_weighted{0.0f};
};

// Everything stage 2 needs about one pixel's path: its prefix endpoint x1, and its suffix (the
// SuffixVertex base, valid with has_suffix). Shading state is stored, not the Bsdf, and rebuilt on
// demand from the material (cheap, and keeps the record small).
struct PathRecord : SuffixVertex {
    Color fixed{0.0f};   // per-pixel part: prefix emission, NEE at x1, emission found by x1's sample
    float transparency = 0.0f;  // Film Transparent: the prefix's throughput that reached the World unseen
    bool has_vertex = false;
    bool has_suffix = false;
    // The technique sets it may join (technique_class): the prefix's Dirac bounces before x1 (they set
    // the suffix's bounce budget) and, spectrally, its wavelengths' relative densities.
    uint16_t technique_class = 0;
    // Prefix endpoint x1.
    Color beta{0.0f};    // prefix throughput f_e / p up to x1
    Vec3 p, wo, ng, ns;  // ns: the interpolated shading normal on wo's side (bsdf_at turns it)
    uint32_t material = 0;
    bool backfacing = false;
    float radius = 0.0f;
};

// Texture coordinates and object colours of a record's x1 and z1, kept beside the records and only
// for scenes whose materials vary over surfaces (Scene::has_varying_materials), so the records of
// other scenes stay small (the gather stage is bound by reading them).
struct RecordAttribs {
    SurfaceAttribs x1, z1;
};

// The media at a record's x1, beside the records and only for scenes with media: the medium on each
// side of x1's surface (a ray leaving x1 towards its ng side starts in `front`, the one the prefix
// arrived in, else in `back`), and the transmittance along the own suffix's segment x1 -> z1.
struct RecordMedia {
    int32_t front = kNoMedium, back = kNoMedium;
    Color suffix_tr{1.0f};
    int32_t towards(const Vec3& ng, const Vec3& d) const { return dot(d, ng) > 0.0f ? front : back; }
};

inline Bsdf bsdf_at(const Scene& scene, uint32_t material, const Vec3& ns, const Vec3& ng, bool backfacing,
             const SurfaceAttribs& attr, const Vec3& wo) {
    const Material& m = scene.material(material);
    if (m.program) {
        Vec3 program_ns;
        return scene.program_bsdf(material, attr, wo, backfacing, ShaderRay{}, &program_ns);
    }
    Bsdf bsdf;
    Vec3 closure_ns;
    constant_bsdf_on_closure_normal(m, ns, ng, wo, backfacing, attr, &bsdf, &closure_ns);
    return bsdf;
}

// The pixel sample's place in the stratified sampler (for the extra light and BSDF samples at x1).
struct PixelStrata {
    uint64_t key;
    uint32_t sample;
    uint32_t extra_bsdf;  // the pixel's extra BSDF samples taken in earlier iterations
};
// The numbers of x1's extra light sample i (1 <= i < light_samples) and of its extra BSDF sample m,
// asked of the pixel sample's Sampler by name (VertexSampler::extra) with the stratified pattern
// (strata), else drawn from the stream. Light sample i of pixel sample s is stratum
// s (light_samples - 1) + i - 1, so a pixel's extra light samples over all its pixel samples are one
// stratified set, as its first light sample is over the pixel samples; the pixel's BSDF samples are
// numbered over the whole render.
inline VertexSampler extra_light_numbers(const PixelStrata* strata, Sampler& sampler, int i, int light_samples) {
    if (!strata) return VertexSampler(sampler.rng());
    return VertexSampler::extra(sampler, strata->sample * uint32_t(light_samples - 1) + uint32_t(i - 1));
}
inline VertexSampler extra_bsdf_numbers(const PixelStrata* strata, Sampler& sampler, int m) {
    if (!strata) return VertexSampler(sampler.rng());
    return VertexSampler::extra(sampler, strata->extra_bsdf + uint32_t(m));
}

// One of x1's own BSDF samples and the suffix it starts: the path's own sample (stored for sharing)
// or one of the pixel's private extra samples.
struct SuffixSample : SuffixVertex {
    Color fixed{0.0f};  // its per-pixel part: the emission it finds at z1, or a Dirac lobe's whole path
    bool has_suffix = false;
    SurfaceAttribs z_attr;
    Color segment_tr{1.0f};  // with media: the transmittance along x1 -> z1 (folded into L_out)
    // The suffix reached z1 at hit h1.
    void found_z1(const SurfaceHit& h1) {
        has_suffix = true;
        z = h1.p;
        z_ng = h1.ng;
        z_ns = h1.ns;
        z_material = h1.material;
        z_attr = h1.attr;
    }
};

// The geometry of connecting x1 at p to a suffix vertex z (normal z_ng): the direction, the squared
// distance and the area-measure factor |cos theta_z| / d^2. Invalid when z coincides with p.
struct Connection {
    Vec3 dir;
    float dist2 = 0.0f;
    float g = 0.0f;
    bool valid() const { return dist2 > 0.0f; }
};
inline Connection connect(const Vec3& p, const Vec3& z, const Vec3& z_ng) {
    Connection c;
    Vec3 d = z - p;
    float dist2 = length_sq(d);
    if (!(dist2 > 0.0f)) return c;
    c.dist2 = dist2;
    c.dir = d / std::sqrt(dist2);
    c.g = absdot(c.dir, z_ng) / dist2;
    return c;
}

// A private extra suffix: kept by its pixel, in the area measure at z1 like the shared ones.
struct PrivateSuffix {
    Vec3 z, z_ng;
    Color contribution{0.0f};  // f_1(x1 -> z1) L_out |cos theta_z1| / d^2 (0: the sample found no z1)
};

// A connection from a technique's x1 to a gathered z stands for a bounce ray of x1: the objects any
// bounce ray sees block it (an approximation where objects are hidden from some ray types only:
// the gathering pixel's lobe would decide the type).
constexpr uint32_t kConnectionVisibility = kRayBounceTypes;

// A technique set holds prefixes of one Dirac depth ("One Dirac depth per technique set",
// path_space_filtering.cpp) and, in spectral rendering, of one spectral class (psf_spectral.cpp):
// kSharedClass in RGB. A prefix of kPrivateClass shares nothing: its pixel keeps its own suffixes.
constexpr uint8_t kSharedClass = 0, kPrivateClass = 255;
inline uint16_t technique_class(int dirac_depth, uint8_t spectral_class) {
    return uint16_t(std::min(dirac_depth, 255) | int(spectral_class) << 8);
}
inline bool private_class(uint16_t c) { return (c >> 8) == kPrivateClass; }

// The record of a prefix that reached x1 (end.sp), of spectral class `spectral_class` (kSharedClass
// in RGB): x1 and its radius, psf_radius_px pixels projected to world space at the prefix's distance.
inline void record_x1(PathRecord& rec, const X1PrefixEnd& end, uint8_t spectral_class, const RenderSettings& settings,
                      const Camera& camera, RecordAttribs* attribs) {
    const ShadingPoint& sp = end.sp;
    rec.has_vertex = true;
    rec.technique_class = technique_class(end.state.depth, spectral_class);
    rec.p = sp.hit.p;
    rec.wo = sp.wo;
    rec.ng = sp.ng;
    rec.ns = sp.backfacing ? -sp.hit.ns : sp.hit.ns;
    rec.material = sp.hit.material;
    rec.backfacing = sp.backfacing;
    if (attribs) attribs->x1 = sp.hit.attr;
    rec.radius = settings.psf_radius_px * camera.pixel_footprint(end.distance);
}

// The state of the suffix's first segment, the ray of x1's BSDF sample bs (x1 takes light_samples
// light samples and own_samples BSDF samples, combined by multi-sample MIS).
inline PathState suffix_state(const ShadingPoint& sp, const PathState& prefix, const BsdfSample& bs, int light_samples,
                              int own_samples) {
    PathState st1{prefix.depth + 1, bs.delta, bs.pdf, sp.hit.p};
    st1.light_pdf_scale = float(light_samples) / float(own_samples);
    st1.ray_flags = prefix.ray_flags;
    st1.min_ray_pdf = prefix.min_ray_pdf;
    st1.diffuse_bounces = prefix.diffuse_bounces, st1.glossy_bounces = prefix.glossy_bounces;
    st1.transmission_bounces = prefix.transmission_bounces, st1.transparent_bounces = prefix.transparent_bounces;
    // The shared suffixes walk nowhere: z1's subsurface is its diffuse fallback (Cycles' rule after a
    // diffuse bounce at x1; after a glossy one PATH would walk at z1, a bias of the PSF integrators).
    st1.diffuse_ancestor = true;
    advance_ray_type(st1, sp.bsdf, bs);
    return st1;
}

}  // namespace psf_detail
}  // namespace smis
