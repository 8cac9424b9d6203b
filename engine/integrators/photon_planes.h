// Single scattering from rectangular area lights by photon planes (Deng et al. 2019), with the
// weightings compared in West et al. 2020, §6 (eq. 22-27, Fig. 11). Everything else in the image
// (surfaces, other lights' scattering, scattering along secondary rays) comes from the path tracer,
// so the image converges to the same result as PATH.
#pragma once
#include <atomic>
#include <chrono>
#include <vector>

#include "integrators/integrator.h"

namespace smis {

class PhotonPlaneSet;
struct PlaneLight;

enum class PlaneWeighting {
    Unweighted,  // eq. 22: one orientation, 1/|(s x w_l) . w_e| singularity
    Cmis,        // eq. 26: Deng et al.'s closed-form weighting over all orientations
    SmisCos,     // eq. 27 with cosine-only densities (SMIS_w~)
    SmisExact,   // eq. 27 with the exact densities of eq. 25, chord length included (SMIS_w.)
};

class PhotonPlanesIntegrator : public IterativeIntegrator {
public:
    explicit PhotonPlanesIntegrator(PlaneWeighting weighting) : weighting_(weighting) {}
    std::map<std::string, double> stats() const override;
    // Only SMIS with n >= 2 weighs a crossing with its partner orientations (eq. 27).
    void add_skipped(const RenderSettings& settings, std::vector<std::string>* skipped) const override {
        bool smis = weighting_ == PlaneWeighting::SmisCos || weighting_ == PlaneWeighting::SmisExact;
        if (!smis || settings.smis_planes < 2) skipped->push_back("second plane");
    }

private:
    void iteration(RenderContext& ctx, uint32_t s) override;
    // M: path samples per pixel that one plane set serves (RenderSettings::plane_surface_samples, or
    // chosen once per render from the first plane set).
    uint32_t surface_samples(const RenderContext& ctx, const PhotonPlaneSet& set, const std::vector<PlaneLight>& lights);
    // G: what gathering a camera ray costs, in path samples (the cost model that chooses M), once per render.
    double gather_cost(const RenderContext& ctx, const PhotonPlaneSet& set, const std::vector<PlaneLight>& lights);
    // K: path samples per pass of the pixels that gather no planes (RenderSettings::plane_path_pixel_samples,
    // or chosen once per render from G and M).
    uint32_t path_pixel_samples(const RenderContext& ctx, const PhotonPlaneSet& set, const std::vector<PlaneLight>& lights,
                                uint32_t M);
    // The segment partition (RenderSettings::plane_min_crossings): per pixel, the bits of
    // RayMedia::plane_segments of its camera rays, from a pilot plane set drawn once per render.
    // With plane_min_light_crossings, per (segment, plane light) too: plane_keep_.
    void partition_segments(const RenderContext& ctx, const PhotonPlaneSet& pilot, const std::vector<PlaneLight>& lights);
    // Whether window pixel i's gather can be nonzero under the partition (`lights`: the plane lights' bits).
    bool gathers(size_t i, uint32_t lights) const;
    PlaneWeighting weighting_;
    uint32_t surface_samples_ = 0, path_pixel_samples_ = 0;
    double gather_cost_ = -1.0;  // < 0: not estimated yet
    std::vector<uint8_t> plane_segments_;  // per window pixel; empty: every segment is the planes'
    std::vector<uint32_t> plane_keep_;     // RayMedia::plane_keep per window pixel (kMaxSegments each), or empty
    std::chrono::steady_clock::time_point first_iteration_start_{};
    // Measurements, summed over iterations.
    double build_seconds_ = 0, render_seconds_ = 0;
    double path_seconds_ = 0, gather_seconds_ = 0;  // thread time: path samples, plane gathering
    uint64_t iterations_ = 0, planes_ = 0, passes_ = 0;
    uint64_t path_segments_ = 0, pilot_segments_ = 0;  // the partition: segments the path tracer takes, of all
    uint64_t path_segment_lights_ = 0;                  // (segment, light) pairs the per-light partition left to it
    std::atomic<uint64_t> gathers_skipped_{0};  // camera rays whose gather the partition made 0 (gathers())
    std::atomic<uint64_t> plane_hits_{0}, shadow_rays_{0}, parallel_rejected_{0}, nonfinite_rejected_{0};
};

}  // namespace smis
