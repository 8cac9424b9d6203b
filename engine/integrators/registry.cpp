// Maps the integrator names exposed in Blender (scene.smis.integrator) to their implementations.
#include <functional>
#include <map>
#include <stdexcept>

#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/path_space_filtering.h"
#include "integrators/photon_planes.h"
#include "integrators/spectral_path.h"
#include "integrators/restir.h"

namespace smis {

std::string resolve_spectral_mode(const RenderSettings& settings, const Scene& scene) {
    // The spectral path tracer has no medium tracking: scenes with media render in RGB under AUTO
    // (the stats line says so) and refuse an explicit spectral mode rather than lose the media.
    if (settings.spectral == "AUTO") return scene.has_spectral_content() && !scene.has_media() ? "SMIS" : "RGB";
    spectral::SpectralMode mode;
    if (!spectral::parse_spectral_mode(settings.spectral, &mode))
        throw std::invalid_argument("unknown spectral mode '" + settings.spectral + "'");
    if (settings.spectral != "RGB" && scene.has_media())
        throw std::invalid_argument("spectral rendering (" + settings.spectral +
                                    ") does not support participating media yet: set Spectral to AUTO or RGB");
    return settings.spectral;
}

namespace {

// settings.volume_estimator: PATH keeps the path tracer's own single scattering; the photon-plane
// estimators replace the camera rays' scattering from rectangular lights (West et al. 2020, §6).
std::unique_ptr<Integrator> make_volume_integrator(const RenderSettings& settings) {
    static const std::map<std::string, PlaneWeighting> planes = {
        {"PLANES_UNWEIGHTED", PlaneWeighting::Unweighted},
        {"PLANES_CMIS", PlaneWeighting::Cmis},
        {"PLANES_SMIS_COS", PlaneWeighting::SmisCos},
        {"PLANES_SMIS_EXACT", PlaneWeighting::SmisExact},
    };
    auto it = planes.find(settings.volume_estimator);
    if (it == planes.end())
        throw std::invalid_argument("unknown volume estimator '" + settings.volume_estimator + "'");
    if (settings.integrator != "PATH")
        throw std::invalid_argument("photon planes (" + settings.volume_estimator + ") need the PATH integrator");
    if (settings.smis_planes < 1 || settings.smis_planes > 64)
        throw std::invalid_argument("smis_planes must be between 1 and 64");
    return std::make_unique<PhotonPlanesIntegrator>(it->second);
}

}  // namespace

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings, const Scene& scene) {
    std::string spectral = resolve_spectral_mode(settings, scene);
    // Measurement builds without some feature (core/features.h) refuse the settings that need it.
    if (spectral != "RGB") require_feature(kWithSpectral, "spectral rendering", "spectral");
    if (settings.direct_light != DirectLightStrategy::Nee)
        require_feature(kWithResampledLights, "RIS/ReSTIR", "resampled_lights");
    if (settings.volume_estimator != "PATH") require_feature(kWithVolumes, "photon planes", "volumes");
    if (settings.stratified) require_feature(kWithStratified, "the stratified sampling pattern", "stratified");
    // RIS / ReSTIR live in the RGB path tracer: their resampling knows no spectra, so that
    // combination is refused rather than rendered wrong. (Media are supported: direct_lighting.h.)
    if (settings.direct_light != DirectLightStrategy::Nee && spectral != "RGB")
        throw std::invalid_argument("RIS/ReSTIR direct lighting does not support spectral rendering yet: use NEE "
                                    "(or set Spectral to RGB)");
    if (settings.volume_estimator != "PATH") return make_volume_integrator(settings);
    if (settings.spectral_wavelength != 0.0f) {
        if (!(settings.spectral_wavelength >= spectral::kLambdaMin && settings.spectral_wavelength <= spectral::kLambdaMax))
            throw std::invalid_argument("spectral_wavelength must lie within [360, 830] nm (or be 0: off)");
        if (settings.integrator != "PATH") throw std::invalid_argument("spectral_wavelength applies to PATH only");
        require_feature(kWithSpectral, "spectral rendering", "spectral");
        return std::make_unique<SpectralPathIntegrator>(scene, spectral::SpectralMode::Uniform, 1,
                                                        settings.spectral_wavelength);
    }
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
    // ReSTIR turns the path tracer into a multi-stage integrator (per-pixel reservoirs are reused).
    if (settings.integrator == "PATH" && settings.direct_light == DirectLightStrategy::Restir)
        return std::make_unique<RestirIntegrator>();
    auto it = factories.find(settings.integrator);
    if (it == factories.end()) throw std::invalid_argument("unknown integrator '" + settings.integrator + "'");
    return it->second();
}

}  // namespace smis
