#include "scene/material.h"

namespace smis {

float transparency_keep(const ShaderResult& res) {
    Color t = vmin(vmax(res.transparent, Color(0.0f)), Color(1.0f));
    return 1.0f - min_component(t);
}

// A program's lobe into the BSDF: a back-facing hit on glass leaves the medium (eta inverted).
static void add_program_lobe(Bsdf* bsdf, Lobe lobe, bool backfacing) {
    if (backfacing && lobe_backface_inverts_eta(lobe))
        lobe.eta = 1.0f / lobe.eta;
    bsdf->add(lobe);
}

Bsdf Material::program_bsdf(const ShaderResult& res, const Frame& frame, const Vec3& ng, bool backfacing) const {
    Bsdf bsdf(frame, ng);
    // No Transparent BSDF weight (most programs): keep is exactly 1, the weights times 1 / keep are
    // the weights unchanged and there is no straight-through rest, so the lobes go in as they are.
    if (res.transparent == Color(0.0f)) {
        for (int i = 0; i < res.count; ++i) add_program_lobe(&bsdf, res.lobes[i], backfacing);
        return bsdf;
    }
    float keep = transparency_keep(res);
    if (!(keep > 1e-6f)) return bsdf;
    float inv_keep = 1.0f / keep;
    for (int i = 0; i < res.count; ++i) {
        Lobe lobe = res.lobes[i];
        lobe.weight *= inv_keep;
        add_program_lobe(&bsdf, lobe, backfacing);
    }
    Color t = vmin(vmax(res.transparent, Color(0.0f)), Color(1.0f));
    Color rest = (t - Color(min_component(t))) * inv_keep;
    if (max_component(rest) > 0.0f) {
        Lobe straight;
        straight.kind = LobeKind::Transparent;
        straight.weight = rest;
        straight.index = program ? uint8_t(program->lobe_templates().size() - 1) : 0;
        bsdf.add(straight);
    }
    return bsdf;
}

}  // namespace smis
