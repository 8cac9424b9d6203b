#pragma once
#include "integrators/integrator.h"

namespace smis {

// Unidirectional path tracer: next-event estimation and BSDF sampling combined by MIS (balance or
// power heuristic, lecture notes "MIS for direct lighting"), Russian roulette, Cycles' bounce limit.
class PathIntegrator : public PixelIntegrator {
public:
    void add_skipped(const RenderSettings& settings, std::vector<std::string>* skipped) const override {
        skipped->push_back("filtering");
        if (settings.direct_light == DirectLightStrategy::Nee) skipped->push_back("RIS/ReSTIR");
    }

protected:
    Color Li(const Scene& scene, const RenderSettings& settings, Ray ray, Sampler& sampler,
             LocalCounters& counters) const override;
};

}  // namespace smis
