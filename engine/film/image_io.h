// Writing images outside Blender: scene-linear EXR (OpenEXR) and display-referred PNG through
// OpenColorIO with Blender's own configuration, so previews look like Blender's.
#pragma once
#include <map>
#include <string>
#include <vector>

namespace smis {

// rgba: width x height x 4 floats, rows bottom to top (Blender's order).
void write_exr(const std::string& path, const float* rgba, int width, int height);

// Reads R, G, B (and A when present) of the first layer of an EXR; missing channels read as 0 (A as 1).
// Channel names may carry a layer prefix ("ViewLayer.Combined.R") as in Blender's multilayer files.
std::vector<float> read_exr(const std::string& path, int* width, int* height, const std::string& layer = "");

// Every channel by its full name (e.g. "ViewLayer.Depth.Z"), width x height floats each, rows
// bottom to top; and the inverse. Multilayer EXRs from Blender are single-part files, so this reads
// every pass of them.
std::map<std::string, std::vector<float>> read_exr_channels(const std::string& path, int* width, int* height);
void write_exr_channels(const std::string& path, const std::map<std::string, std::vector<float>>& channels, int width,
                        int height);

struct DisplaySettings {
    std::string config;  // path to an OCIO config (Blender's datafiles/colormanagement/config.ocio)
    std::string display = "sRGB", view = "Standard", look;
    float exposure = 0.0f, gamma = 1.0f;
};
void write_png(const std::string& path, const float* rgba, int width, int height, const DisplaySettings& display);

}  // namespace smis
