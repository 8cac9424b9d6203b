// Maps the integrator names exposed in Blender (scene.smis.integrator) to their implementations.
#include <functional>
#include <map>
#include <stdexcept>

#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/path_space_filtering.h"
#include "integrators/restir.h"

namespace smis {

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings) {
    static const std::map<std::string, std::function<std::unique_ptr<Integrator>()>> factories = {
        {"PATH", [] { return std::make_unique<PathIntegrator>(); }},
        // The path-space filtering family: PSF_PATH is the path tracer on the same two-stage paths.
        {"PSF_PATH", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Path); }},
        {"PSF_KELLER", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Keller); }},
        {"PSF_SMIS", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Smis); }},
        {"PSF_SMIS_UNBIASED",
         [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::SmisUnbiased); }},
    };
    // ReSTIR turns the path tracer into a multi-stage integrator (per-pixel reservoirs are reused).
    if (settings.integrator == "PATH" && settings.direct_light == DirectLightStrategy::Restir)
        return std::make_unique<RestirIntegrator>();
    auto it = factories.find(settings.integrator);
    if (it == factories.end()) throw std::invalid_argument("unknown integrator '" + settings.integrator + "'");
    return it->second();
}

}  // namespace smis
