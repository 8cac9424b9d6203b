// Compile-time feature switches, for measuring what a feature costs a scene that does not use it.
//
// The product is always built with every feature. bench/skip_bench.py --per-feature also builds the
// engine with some left out (cmake -DSMIS_WITHOUT="textures;stratified", engine/CMakeLists.txt), and
// compares the instructions both builds execute on the same scene. Each feature's checks on the
// per-sample, per-vertex and per-ray paths are written `kWithX && ...`, so in a build without it the
// compiler drops its code; a scene or setting that needs an absent feature is refused with a clear
// error (require_feature) instead of rendering wrong.
#pragma once
#include <stdexcept>
#include <string>

#ifndef SMIS_WITH_VOLUMES
#error "engine/CMakeLists.txt defines SMIS_WITH_<feature> (0 or 1) for every feature of SMIS_FEATURES"
#endif

namespace smis {

inline constexpr bool kWithVolumes = SMIS_WITH_VOLUMES;                  // media, single scattering, photon planes
inline constexpr bool kWithSpectral = SMIS_WITH_SPECTRAL;                // the spectral path tracer
inline constexpr bool kWithResampledLights = SMIS_WITH_RESAMPLED_LIGHTS;  // RIS and ReSTIR direct light
inline constexpr bool kWithTextures = SMIS_WITH_TEXTURES;                // image textures, normal maps, object colour
inline constexpr bool kWithTexturedEmission = SMIS_WITH_TEXTURED_EMISSION;
inline constexpr bool kWithCutouts = SMIS_WITH_CUTOUTS;                  // Principled Alpha < 1
inline constexpr bool kWithPrincipledExtras = SMIS_WITH_PRINCIPLED_EXTRAS;  // clearcoat, sheen, Burley, Transparent
inline constexpr bool kWithClosures = SMIS_WITH_CLOSURES;                // Oren-Nayar, Velvet, Translucent, Refraction, Beckmann, Toon, multiscatter GGX, anisotropic
inline constexpr bool kWithDepthOfField = SMIS_WITH_DEPTH_OF_FIELD;
inline constexpr bool kWithAuxPasses = SMIS_WITH_AUX_PASSES;             // Depth/Normal/Albedo/diagnostic passes
inline constexpr bool kWithStratified = SMIS_WITH_STRATIFIED;            // the stratified sampling pattern

// Refuses what needs a feature this build was configured without (`name` as SMIS_WITHOUT spells it).
inline void require_feature(bool present, const char* what, const char* name) {
    if (!present)
        throw std::invalid_argument(std::string(what) + " is not in this build (configured with SMIS_WITHOUT=" + name +
                                    ")");
}

}  // namespace smis
