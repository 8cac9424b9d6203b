// The densities of path-space filtering's SMIS denominator (West et al. 2020, eq. 17):
// sum_j p(z | ybar_j), the density of technique j (prefix endpoint x1_j with its BSDF and fixed wo)
// producing the suffix vertex z, in the area measure at z: p_omega(wo_j, w) |cos theta_z| / d^2 with
// w = (z - x1_j) / d, assuming visibility (§4.3). Every gathered sample needs it over every gathered
// technique, k^2 densities per pixel, so this is the gather's inner loop.
//
// Most BSDFs are a mixture of reflection lobes that are either cosine sampled (Lambert, principled
// diffuse, sheen) or GGX visible-normal sampled, plus Dirac lobes (which have no density). Their pdf
// is then, for w on the reflection side of both normals,
//     p_omega(w) = c_cos cos_i + c_ggx D_alpha(h),   h = wo + w (local frame),
// with c_cos = sum of the cosine lobes' selection probabilities / pi and c_ggx = the GGX lobes'
// probability times G1(wo) / (4 cos_o) (Heitz 2018's visible-normal pdf after the reflection
// Jacobian), both fixed by wo. TechniqueDensity stores that model once per stored vertex (stage 1),
// and DensitySum evaluates it for all techniques at once from structure-of-arrays data the compiler
// vectorises. Techniques it cannot express (rough glass, clearcoat, GGX lobes of different alphas)
// keep their Bsdf and take Bsdf::pdf; both routes give the same values (psf_density_test).
#pragma once
#include <cassert>
#include <cmath>
#include <vector>

#include "scene/bsdf.h"

namespace smis {

struct TechniqueDensity {
    enum Kind : uint8_t { Zero, Model, General };
    Kind kind = Zero;
    Vec3 p;                   // the prefix endpoint x1
    Vec3 s, t, n;             // shading frame
    Vec3 ng;                  // geometric normal, flipped to wo's side
    Vec3 wo_local;            // wo in the shading frame
    float c_cos = 0.0f, c_ggx = 0.0f, alpha2 = 0.0f;

    // The model of `bsdf` at p seen from wo (kind General when the model cannot express it).
    static TechniqueDensity of(const Bsdf& bsdf, const Vec3& p, const Vec3& wo);
    // p(z | this technique) in the area measure at z (kind Model only).
    float area_density(const Vec3& z, const Vec3& z_ng) const;
};

inline TechniqueDensity TechniqueDensity::of(const Bsdf& bsdf, const Vec3& p, const Vec3& wo) {
    TechniqueDensity m;
    m.p = p;
    const Frame& f = bsdf.frame();
    m.s = f.s, m.t = f.t, m.n = f.n;
    m.wo_local = f.to_local(wo);
    // Lobes the model cannot express make the technique General whatever wo (rough glass has a
    // density for wo under the surface too).
    float alpha = -1.0f;
    for (int i = 0; i < bsdf.lobe_count(); ++i) {
        const Lobe& lobe = bsdf.lobe(i);
        if (lobe_is_delta(lobe)) continue;  // Dirac lobes have no density
        DensityModel model = lobe_density_model(lobe);  // the lobe's own (lobes/lobe.h)
        bool cosine = model == DensityModel::Cosine;
        bool ggx = model == DensityModel::Ggx && (alpha < 0.0f || lobe.alpha == alpha);
        if (!cosine && !ggx) {  // rough dielectric, clearcoat, GGX lobes of different roughness
            m.kind = General;
            return m;
        }
        if (ggx) alpha = lobe.alpha;
    }
    const float go = dot(wo, bsdf.ng());
    // Reflection lobes have no density when wo is in the shading plane or under it (they need
    // wo_l.z > 0), or lies in the geometric plane (Bsdf's sides_consistent).
    if (bsdf.empty() || !(m.wo_local.z > 0.0f) || !(go != 0.0f)) return m;
    m.ng = go > 0.0f ? bsdf.ng() : -bsdf.ng();
    Bsdf::FixedWo fixed = bsdf.fix_wo(wo);
    for (int i = 0; i < bsdf.lobe_count(); ++i) {
        const Lobe& lobe = bsdf.lobe(i);
        if (lobe_is_delta(lobe)) continue;
        if (lobe_density_model(lobe) == DensityModel::Ggx) m.c_ggx += fixed.probs[i] * fixed.pdf_scale[i];
        else m.c_cos += fixed.probs[i] * kInvPi;
    }
    // ggx_D clamps alpha the same way (kMinAlpha); non-Dirac lobes have alpha >= kDeltaAlpha anyway.
    m.alpha2 = alpha > 0.0f ? alpha * alpha : 0.0f;
    if (!std::isfinite(m.c_cos) || !std::isfinite(m.c_ggx)) return m;  // Zero
    m.kind = (m.c_cos > 0.0f || m.c_ggx > 0.0f) ? Model : Zero;
    return m;
}

namespace psf_detail {
// The model's area density from its parts; written on scalars so that the same expression serves the
// single evaluation and the vectorised loop of DensitySum.
inline float model_density(float dx, float dy, float dz, float sx, float sy, float sz, float tx, float ty, float tz,
                           float nx, float ny, float nz, float gx, float gy, float gz, float ox, float oy, float oz,
                           float c_cos, float c_ggx, float a2, float zx, float zy, float zz) {
    float d2 = dx * dx + dy * dy + dz * dz;
    float inv_d = 1.0f / std::sqrt(d2);
    float ci = (dx * nx + dy * ny + dz * nz) * inv_d;  // cos theta_i in the shading frame
    float gi = dx * gx + dy * gy + dz * gz;            // sign only
    float cz = std::fabs(dx * zx + dy * zy + dz * zz) * inv_d;
    // GGX term: D(h) for the unnormalised half vector h = wo + wi (local), written without
    // normalising: D = a2 L^2 / (pi (hx^2 + hy^2 + a2 hz^2)^2), L = |h|^2.
    float hx = ox + (dx * sx + dy * sy + dz * sz) * inv_d;
    float hy = oy + (dx * tx + dy * ty + dz * tz) * inv_d;
    float hz = oz + ci;
    float L = hx * hx + hy * hy + hz * hz;
    float q = hx * hx + hy * hy + a2 * hz * hz;
    float D = a2 * L * L / (kPi * q * q);
    // Masks combined with & rather than && so the loop has no branches and vectorises.
    float ggx = ((hz > 0.0f) & (L > 1e-24f) & (q > 0.0f)) ? c_ggx * D : 0.0f;
    float pdf = c_cos * ci + ggx;
    float p = pdf * cz / d2;
    return ((ci > 0.0f) & (gi > 0.0f) & (d2 > 0.0f)) ? p : 0.0f;
}
// Fields of a model in DensitySum's structure of arrays: p, s, t, n, ng, wo_local, c_cos, c_ggx, alpha2.
constexpr int kModelFields = 21;
// out[j] = model_density of technique j (fields[f][j]) for j < n. Defined in path_space_filtering.cpp,
// compiled for AVX2 and for the baseline, chosen at run time (the loop is the gather's hot spot).
void model_densities(const float* const* fields, size_t n, const Vec3& z, const Vec3& z_ng, float* out);
}  // namespace psf_detail

inline float TechniqueDensity::area_density(const Vec3& z, const Vec3& z_ng) const {
    if (kind != Model) return 0.0f;
    float v = psf_detail::model_density(z.x - p.x, z.y - p.y, z.z - p.z, s.x, s.y, s.z, t.x, t.y, t.z, n.x, n.y, n.z,
                                        ng.x, ng.y, ng.z, wo_local.x, wo_local.y, wo_local.z, c_cos, c_ggx, alpha2,
                                        z_ng.x, z_ng.y, z_ng.z);
    return std::isfinite(v) ? v : 0.0f;
}

// A technique with its full BSDF (wo fixed): the density routine of Bsdf, for the techniques the model
// cannot express and for the unbiased variant, which evaluates every density exactly.
struct BsdfTechnique {
    Vec3 p;
    Bsdf bsdf;
    Bsdf::FixedWo wo;
    BsdfTechnique(const Vec3& p_, const Bsdf& bsdf_, const Vec3& wo_) : p(p_), bsdf(bsdf_), wo(bsdf_.fix_wo(wo_)) {}
    // p(z | this technique) in the area measure at z.
    float area_density(const Vec3& z, const Vec3& z_ng) const {
        Vec3 d = z - p;
        float dist2 = length_sq(d);
        if (!(dist2 > 0.0f)) return 0.0f;
        Vec3 w = d / std::sqrt(dist2);
        return bsdf.pdf(wo, w) * absdot(w, z_ng) / dist2;
    }
};

// sum_j p(z | ybar_j) over a pixel's gathered techniques: the Model ones from structure-of-arrays
// data in one vectorised loop, the General ones through their Bsdf.
class DensitySum {
public:
    DensitySum() = default;
    DensitySum(const DensitySum&) = delete;  // fields_ points into soa_
    DensitySum& operator=(const DensitySum&) = delete;
    void reset() {
        n_ = 0;
        general_.clear();
    }
    void add(const TechniqueDensity& m) {
        if (m.kind != TechniqueDensity::Model) return;
        if (n_ == cap_) grow();
        // Straight from the model down the columns, in field order (a staging array and an indexed
        // loop cost ~130 instructions per add).
        float* c = soa_.data() + n_;
        const size_t w = cap_;
        int fields = 0;
        auto put = [&](float v) { *c = v, c += w, ++fields; };
        auto put3 = [&](const Vec3& v) { put(v.x), put(v.y), put(v.z); };
        put3(m.p), put3(m.s), put3(m.t), put3(m.n), put3(m.ng), put3(m.wo_local);
        put(m.c_cos), put(m.c_ggx), put(m.alpha2);
        assert(fields == kFields);
        ++n_;
    }
    // A technique the model cannot express: its BSDF at p, the pdf routine of Bsdf.
    void add_general(const Vec3& p, const Bsdf& bsdf, const Vec3& wo) { general_.emplace_back(p, bsdf, wo); }

    float operator()(const Vec3& z, const Vec3& z_ng) const {
        const size_t n = n_;
        float* out = out_.data();
        // Densities into a buffer first and summed afterwards: a float reduction inside the loop
        // would keep the compiler from vectorising it (it may not reorder the additions).
        psf_detail::model_densities(fields_, n, z, z_ng, out);
        // Summed in 8 interleaved partial sums, which the compiler turns into vector adds (a single
        // running sum may not be reordered); the order is fixed, so every build adds alike.
        float lanes[8] = {};
        size_t j = 0;
        for (; j + 8 <= n; j += 8)
            for (int l = 0; l < 8; ++l) lanes[l] += out[j + l];
        for (; j < n; ++j) lanes[j & 7] += out[j];
        float sum = ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
        for (const BsdfTechnique& g : general_) sum += g.area_density(z, z_ng);
        return std::isfinite(sum) ? sum : 0.0f;
    }

private:
    static constexpr int kFields = psf_detail::kModelFields;
    void grow() {
        size_t cap = cap_ ? 2 * cap_ : 32;
        std::vector<float> soa(size_t(kFields) * cap);
        for (int f = 0; f < kFields; ++f)
            for (size_t j = 0; j < n_; ++j) soa[size_t(f) * cap + j] = soa_[size_t(f) * cap_ + j];
        soa_.swap(soa);
        cap_ = cap;
        out_.resize(cap);
        for (int f = 0; f < kFields; ++f) fields_[f] = soa_.data() + size_t(f) * cap_;
    }
    std::vector<float> soa_;
    const float* fields_[kFields] = {};  // soa_'s field arrays
    mutable std::vector<float> out_;
    size_t n_ = 0, cap_ = 0;
    std::vector<BsdfTechnique> general_;
};

}  // namespace smis
