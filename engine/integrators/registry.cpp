// Maps the integrator names exposed in Blender (scene.smis.integrator) to their implementations.
#include <stdexcept>

#include "integrators/integrator.h"
#include "integrators/path.h"
#include "integrators/path_space_filtering.h"
#include "integrators/psf_spectral.h"
#include "integrators/photon_planes.h"
#include "integrators/spectral_path.h"
#include "integrators/restir.h"

namespace smis {

SpectralSetting resolve_spectral_mode(const RenderSettings& settings, const Scene& scene) {
    // Photon planes (volume estimators other than PATH) are RGB estimators: AUTO renders them in RGB
    // and an explicit spectral mode is refused (make_integrator).
    if (settings.spectral == SpectralSetting::Auto)
        return scene.has_spectral_content() && settings.volume_estimator == VolumeEstimator::Path ? SpectralSetting::Smis
                                                                                                 : SpectralSetting::Rgb;
    return settings.spectral;
}

namespace {

spectral::SpectralMode spectral_mode(SpectralSetting s) {
    switch (s) {
        case SpectralSetting::Uniform: return spectral::SpectralMode::Uniform;
        case SpectralSetting::SpectralIs: return spectral::SpectralMode::SpectralIs;
        case SpectralSetting::Hero: return spectral::SpectralMode::Hero;
        case SpectralSetting::Smis: return spectral::SpectralMode::Smis;
        case SpectralSetting::SmisIndependent: return spectral::SpectralMode::SmisIndependent;
        case SpectralSetting::BruteForce: return spectral::SpectralMode::BruteForce;
        case SpectralSetting::Auto:
        case SpectralSetting::Rgb: break;
    }
    return spectral::SpectralMode::Rgb;
}

// settings.volume_estimator: PATH keeps the path tracer's own single scattering; the photon-plane
// estimators replace the camera rays' scattering from rectangular lights (West et al. 2020, §6).
std::unique_ptr<Integrator> make_volume_integrator(const RenderSettings& settings) {
    if (settings.integrator != IntegratorKind::Path)
        throw std::invalid_argument(std::string("photon planes (") + setting_name(settings.volume_estimator) +
                                    ") need the PATH integrator");
    if (settings.smis_planes < 1 || settings.smis_planes > 64)
        throw std::invalid_argument("smis_planes must be between 1 and 64");
    switch (settings.volume_estimator) {
        case VolumeEstimator::PlanesUnweighted: return std::make_unique<PhotonPlanesIntegrator>(PlaneWeighting::Unweighted);
        case VolumeEstimator::PlanesCmis: return std::make_unique<PhotonPlanesIntegrator>(PlaneWeighting::Cmis);
        case VolumeEstimator::PlanesSmisCos: return std::make_unique<PhotonPlanesIntegrator>(PlaneWeighting::SmisCos);
        case VolumeEstimator::PlanesSmisExact: return std::make_unique<PhotonPlanesIntegrator>(PlaneWeighting::SmisExact);
        case VolumeEstimator::Path: break;
    }
    throw std::invalid_argument("the path tracer's single scattering is no photon-plane estimator");
}

// The weighting of a path-space filtering integrator.
PsfWeighting psf_weighting(IntegratorKind kind) {
    switch (kind) {
        case IntegratorKind::PsfPath: return PsfWeighting::Path;
        case IntegratorKind::PsfKeller: return PsfWeighting::Keller;
        case IntegratorKind::PsfSmis: return PsfWeighting::Smis;
        case IntegratorKind::PsfSmisUnbiased: return PsfWeighting::SmisUnbiased;
        default: break;  // the other integrators (a new one needs no line here)
    }
    throw std::invalid_argument("not a path-space filtering integrator");
}

// Adding an integrator: its folder or file, an item in the settings table's INTEGRATOR enum
// (addon/smis_render/settings_schema.py) and its line here.
std::unique_ptr<Integrator> make_surface_integrator(IntegratorKind kind) {
    switch (kind) {
        case IntegratorKind::Path: return std::make_unique<PathIntegrator>();
        // The path-space filtering family: PSF_PATH is the path tracer on the same two-stage paths.
        case IntegratorKind::PsfPath:
        case IntegratorKind::PsfKeller:
        case IntegratorKind::PsfSmis:
        case IntegratorKind::PsfSmisUnbiased: return std::make_unique<PathSpaceFilteringIntegrator>(psf_weighting(kind));
    }
    throw std::invalid_argument("unknown integrator");
}

}  // namespace

std::unique_ptr<Integrator> make_integrator(const RenderSettings& settings, const Scene& scene) {
    const SpectralSetting spectral = resolve_spectral_mode(settings, scene);
    const bool path = settings.integrator == IntegratorKind::Path;
    // Measurement builds without some feature (core/features.h) refuse the settings that need it.
    if (spectral != SpectralSetting::Rgb) require_feature(kWithSpectral, "spectral rendering", "spectral");
    if (settings.direct_light != DirectLightStrategy::Nee)
        require_feature(kWithResampledLights, "RIS/ReSTIR", "resampled_lights");
    if (settings.volume_estimator != VolumeEstimator::Path) require_feature(kWithVolumes, "photon planes", "volumes");
    if (settings.sampling_pattern == SamplingPattern::Stratified)
        require_feature(kWithStratified, "the stratified sampling pattern", "stratified");
    if (settings.volume_estimator != VolumeEstimator::Path &&
        (spectral != SpectralSetting::Rgb || settings.spectral_wavelength != 0.0f))
        throw std::invalid_argument(std::string("photon planes (") + setting_name(settings.volume_estimator) +
                                    ") render in RGB only: set Spectral to RGB or AUTO, or the volume estimator to PATH");
    if (settings.volume_estimator != VolumeEstimator::Path) return make_volume_integrator(settings);
    // ReSTIR turns the path tracer into a multi-stage integrator (per-pixel reservoirs are reused).
    // RIS and ReSTIR resample with RGB targets and shade the chosen sample at a spectral path's
    // wavelengths (direct_lighting.h, resampled_weight).
    const bool restir = path && settings.direct_light == DirectLightStrategy::Restir;
    if (settings.spectral_wavelength != 0.0f) {
        if (!(settings.spectral_wavelength >= spectral::kLambdaMin && settings.spectral_wavelength <= spectral::kLambdaMax))
            throw std::invalid_argument("spectral_wavelength must lie within [360, 830] nm (or be 0: off)");
        if (!path) throw std::invalid_argument("spectral_wavelength applies to PATH only");
        require_feature(kWithSpectral, "spectral rendering", "spectral");
        if (restir)
            return std::make_unique<RestirIntegrator>(scene, spectral::SpectralMode::Uniform, 1,
                                                      settings.spectral_wavelength);
        return std::make_unique<SpectralPathIntegrator>(scene, spectral::SpectralMode::Uniform, 1,
                                                        settings.spectral_wavelength);
    }
    if (restir && spectral != SpectralSetting::Rgb)
        return std::make_unique<RestirIntegrator>(scene, spectral_mode(spectral), settings.wavelengths, 0.0f);
    if (path && spectral != SpectralSetting::Rgb)
        return std::make_unique<SpectralPathIntegrator>(scene, spectral_mode(spectral), settings.wavelengths);
    if (spectral != SpectralSetting::Rgb)  // path-space filtering at one wavelength set per iteration
        return std::make_unique<PathSpaceFilteringIntegrator>(
            psf_weighting(settings.integrator),
            std::make_unique<PsfSpectrum>(scene, spectral_mode(spectral), settings.wavelengths));
    if (restir) return std::make_unique<RestirIntegrator>();
    return make_surface_integrator(settings.integrator);
}

}  // namespace smis
