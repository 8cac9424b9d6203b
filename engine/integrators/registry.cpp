// Maps the integrator names exposed in Blender (scene.smis.integrator) to their implementations.
#include <functional>
#include <map>
#include <stdexcept>

#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/path_space_filtering.h"
#include "integrators/spectral_path.h"

namespace smis {

std::string resolve_spectral_mode(const RenderSettings& settings, const Scene& scene) {
    if (settings.spectral == "AUTO") return scene.has_spectral_content() ? "SMIS" : "RGB";
    spectral::SpectralMode mode;
    if (!spectral::parse_spectral_mode(settings.spectral, &mode))
        throw std::invalid_argument("unknown spectral mode '" + settings.spectral + "'");
    return settings.spectral;
}

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings, const Scene& scene) {
    std::string spectral = resolve_spectral_mode(settings, scene);
    if (settings.integrator == "PATH" && spectral != "RGB") {
        spectral::SpectralMode mode;
        spectral::parse_spectral_mode(spectral, &mode);
        return std::make_unique<SpectralPathIntegrator>(scene, mode, settings.wavelengths);
    }
    static const std::map<std::string, std::function<std::unique_ptr<Integrator>()>> factories = {
        {"PATH", [] { return std::make_unique<PathIntegrator>(); }},
        // The path-space filtering family: PSF_PATH is the path tracer on the same two-stage paths.
        {"PSF_PATH", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Path); }},
        {"PSF_KELLER", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Keller); }},
        {"PSF_SMIS", [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::Smis); }},
        {"PSF_SMIS_UNBIASED",
         [] { return std::make_unique<PathSpaceFilteringIntegrator>(PsfWeighting::SmisUnbiased); }},
    };
    auto it = factories.find(settings.integrator);
    if (it == factories.end()) throw std::invalid_argument("unknown integrator '" + settings.integrator + "'");
    return it->second();
}

}  // namespace smis
