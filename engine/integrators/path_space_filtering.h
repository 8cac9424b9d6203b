// Path-space filtering with stochastic MIS (West et al. 2020, §4), with Keller et al. 2014's
// weighting and plain path tracing on the same paths as baselines.
#pragma once
#include <atomic>
#include <memory>

#include "integrators/integrator.h"

namespace smis {

class PsfSpectrum;

enum class PsfWeighting {
    Path,          // no reuse: the path tracer on the stage-1 paths
    Keller,        // binary acceptance by surface similarity, normalised over accepted samples
    Smis,          // balance-heuristic SMIS over the gathered techniques, eq. (17), practical (§4.3)
    SmisUnbiased,  // eq. (17) with every connection and density evaluated exactly (§4.2)
};

class PathSpaceFilteringIntegrator : public IterativeIntegrator {
public:
    // spectrum: render at one wavelength set per iteration (psf_spectral.h); null: RGB.
    explicit PathSpaceFilteringIntegrator(PsfWeighting weighting, std::unique_ptr<PsfSpectrum> spectrum = nullptr);
    ~PathSpaceFilteringIntegrator() override;
    std::map<std::string, double> stats() const override;
    void add_skipped(const RenderSettings&, std::vector<std::string>* skipped) const override {
        if (weighting_ == PsfWeighting::Path) skipped->push_back("filtering");  // no grid, no gather
    }

private:
    void iteration(RenderContext& ctx, uint32_t s) override;
    // The iteration with the weighting as a type (psf_weighting.h).
    template <class W>
    void iterate(RenderContext& ctx, uint32_t s);
    PsfWeighting weighting_;
    std::unique_ptr<PsfSpectrum> spectrum_;
    // Records, technique models and the grid, kept across iterations (path_space_filtering.cpp).
    struct IterationBuffers;
    std::unique_ptr<IterationBuffers> buffers_;
    // Measurements, summed over iterations.
    double stage1_seconds_ = 0, grid_seconds_ = 0, gather_seconds_ = 0;
    uint64_t iterations_ = 0, stored_vertices_ = 0, gathered_ = 0, accepted_ = 0, extra_paths_ = 0, pixels_ = 0;
    uint64_t groups_ = 0, grouped_pixels_ = 0;  // technique sets of stage 2 and the pixels sharing them
    uint64_t visibility_rays_ = 0;              // shadow rays of the unbiased variant's gather
    double bytes_per_vertex_ = 0;
};

}  // namespace smis
