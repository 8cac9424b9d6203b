// The auxiliary passes (Depth, Normal, Albedo) recorded at a camera sample's first hit. Only runs
// when a pass is enabled (Film::has_aux); the integrators' camera paths record them as they pass
// their first hit (FirstHitPasses), so mostly no extra ray is traced for them either.
#pragma once
#include "integrators/integrator.h"

namespace smis {

struct ShadingPoint;

// Depth and normal of the first hit along the camera ray, as Cycles' Z and Normal passes. Albedo
// as Cycles' denoising albedo: the first hit that is not a perfect mirror or smooth glass gives its
// closures' reflectance (weights, Fresnel-scaled at normal incidence for specular layers and
// metals), times the throughput of the Dirac bounces that led there (at most
// kAuxMaxDeltaBounces, chosen with `rng`, a stream of its own so the image does not change).
constexpr int kAuxMaxDeltaBounces = 8;
AuxSample first_hit_aux(const Scene& scene, const Ray& camera_ray, Rng& rng);
// Only the depth (normal and albedo left at their background values): when no pass needs more.
AuxSample first_hit_depth(const Scene& scene, const Ray& camera_ray);

// The passes of pixel sample s of window pixel (x, y) as its camera path records them
// (path_loop.h, through LocalCounters::passes): at the camera ray's hit, which the path intersects
// and shades anyway, so the passes cost no camera ray of their own; the albedo's Dirac bounces, if
// any, draw from first_hit_aux's stream of their own. Left unrecorded (ready false) where the
// path's first hit is not the passes' (its camera ray passed a medium boundary, where the passes'
// ray stops) or the path ended before shading it (a holdout object's hole, a bounce limit):
// add_aux_sample then traces the passes' own camera ray, as before.
class FirstHitPasses {
public:
    FirstHitPasses() = default;  // records nothing until assigned one of a pixel sample
    FirstHitPasses(const RenderContext& ctx, int x, int y, uint32_t s) : ctx_(&ctx), x_(x), y_(y), s_(s) {}
    // The camera ray found `hit` (found) or nothing. Returns whether the passes still need the
    // hit's shading point (at_first_hit); else they are recorded.
    bool at_camera_ray(const Scene& scene, bool found, const SurfaceHit& hit) {
        if (found && ctx_->settings.aux_shading) return true;
        aux = AuxSample{};  // a camera ray that sees nothing: the background's passes
        if (found) aux.depth = scene.camera().view_depth(hit.p);  // Blender's default Z pass alone
        ready = true;
        return false;
    }
    void at_first_hit(const Scene& scene, const ShadingPoint& first);
    AuxSample aux;
    bool ready = false;

private:
    const RenderContext* ctx_ = nullptr;
    int x_ = 0, y_ = 0;
    uint32_t s_ = 0;
};

// Records sample `s` of window pixel (x, y) in the auxiliary passes when they are on: `recorded`'s
// when ready, else from the sample's camera ray traced here.
void add_aux_sample(RenderContext& ctx, int x, int y, uint32_t s, const FirstHitPasses& recorded,
                    float diagnostic = 0.0f);

// Makes the paths a pixel sample traces record its passes in `passes` (null: none) for as long as
// it lives: LocalCounters never points at a pixel sample's passes after the sample.
class RecordPasses {
public:
    RecordPasses(LocalCounters& counters, FirstHitPasses* passes) : counters_(counters) { counters.passes = passes; }
    ~RecordPasses() { counters_.passes = nullptr; }
    RecordPasses(const RecordPasses&) = delete;
    RecordPasses& operator=(const RecordPasses&) = delete;

private:
    LocalCounters& counters_;
};

}  // namespace smis
