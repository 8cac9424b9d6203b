#include "film/image_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <OpenColorIO/OpenColorIO.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

namespace smis {

void write_exr(const std::string& path, const float* rgba, int width, int height) {
    Imf::Header header(width, height);
    const char* names[4] = {"R", "G", "B", "A"};
    for (const char* n : names) header.channels().insert(n, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    // EXR scanlines run top to bottom; ours bottom to top: point at the last row with a negative stride.
    const size_t xs = 4 * sizeof(float);
    const ptrdiff_t ys = -static_cast<ptrdiff_t>(xs * width);
    const char* top = reinterpret_cast<const char*>(rgba + size_t(4) * width * (height - 1));
    for (int c = 0; c < 4; ++c)
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, const_cast<char*>(top + c * sizeof(float)), xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(height);
}

std::vector<float> read_exr(const std::string& path, int* width, int* height, const std::string& layer) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::vector<float> rgba(size_t(4) * w * h, 0.0f);
    for (size_t i = 3; i < rgba.size(); i += 4) rgba[i] = 1.0f;
    Imf::FrameBuffer fb;
    const size_t xs = 4 * sizeof(float);
    const ptrdiff_t ys = -static_cast<ptrdiff_t>(xs * w);
    // Rows bottom to top, as everywhere in the engine; the base pointer is offset by the data window.
    char* base = reinterpret_cast<char*>(rgba.data() + size_t(4) * w * (h - 1)) - dw.min.x * ptrdiff_t(xs) -
                 dw.min.y * ys;
    const char* names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c) {
        std::string name = layer.empty() ? names[c] : layer + "." + names[c];
        if (file.header().channels().findChannel(name.c_str()))
            fb.insert(name.c_str(), Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    *width = w;
    *height = h;
    return rgba;
}

std::map<std::string, std::vector<float>> read_exr_channels(const std::string& path, int* width, int* height) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    std::map<std::string, std::vector<float>> out;
    Imf::FrameBuffer fb;
    const size_t xs = sizeof(float);
    const ptrdiff_t ys = -static_cast<ptrdiff_t>(xs * w);
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
        std::vector<float>& px = out[it.name()];
        px.assign(size_t(w) * h, 0.0f);
        // Bottom row first: start at the last row and step backwards, offset by the data window.
        char* base = reinterpret_cast<char*>(px.data() + size_t(w) * (h - 1)) - dw.min.x * ptrdiff_t(xs) - dw.min.y * ys;
        fb.insert(it.name(), Imf::Slice(Imf::FLOAT, base, xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    *width = w;
    *height = h;
    return out;
}

void write_exr_channels(const std::string& path, const std::map<std::string, std::vector<float>>& channels, int width,
                        int height) {
    Imf::Header header(width, height);
    for (const auto& [name, px] : channels) {
        if (px.size() != size_t(width) * height) throw std::invalid_argument("channel " + name + " has the wrong size");
        header.channels().insert(name.c_str(), Imf::Channel(Imf::FLOAT));
    }
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    const size_t xs = sizeof(float);
    const ptrdiff_t ys = -static_cast<ptrdiff_t>(xs * width);
    for (const auto& [name, px] : channels) {
        const char* top = reinterpret_cast<const char*>(px.data() + size_t(width) * (height - 1));
        fb.insert(name.c_str(), Imf::Slice(Imf::FLOAT, const_cast<char*>(top), xs, ys));
    }
    file.setFrameBuffer(fb);
    file.writePixels(height);
}

void write_png(const std::string& path, const float* rgba, int width, int height, const DisplaySettings& ds) {
    std::vector<float> img(rgba, rgba + size_t(4) * width * height);
    try {
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(ds.config.c_str());
        auto dvt = OCIO::DisplayViewTransform::Create();
        dvt->setSrc(OCIO::ROLE_SCENE_LINEAR);
        dvt->setDisplay(ds.display.c_str());
        dvt->setView(ds.view.c_str());
        auto pipeline = OCIO::LegacyViewingPipeline::Create();
        pipeline->setDisplayViewTransform(dvt);
        if (!ds.look.empty() && ds.look != "None") {
            pipeline->setLooksOverrideEnabled(true);
            pipeline->setLooksOverride(ds.look.c_str());
        }
        if (ds.exposure != 0.0f) {
            float gain = std::pow(2.0f, ds.exposure);
            double m44[16] = {gain, 0, 0, 0, 0, gain, 0, 0, 0, 0, gain, 0, 0, 0, 0, 1};
            auto cc = OCIO::MatrixTransform::Create();
            cc->setMatrix(m44);
            pipeline->setLinearCC(cc);
        }
        if (ds.gamma != 1.0f && ds.gamma > 0.0f) {
            auto g = OCIO::ExponentTransform::Create();
            double e = 1.0 / ds.gamma;
            double v[4] = {e, e, e, 1.0};
            g->setValue(v);
            pipeline->setDisplayCC(g);
        }
        auto processor = pipeline->getProcessor(config, config->getCurrentContext());
        OCIO::PackedImageDesc desc(img.data(), width, height, 4);
        processor->getDefaultCPUProcessor()->apply(desc);
    } catch (const OCIO::Exception& e) {
        throw std::runtime_error(std::string("OpenColorIO: ") + e.what());
    }
    std::vector<uint8_t> bytes(img.size());
    for (size_t i = 0; i < img.size(); ++i) {
        float v = std::isfinite(img[i]) ? img[i] : 0.0f;
        bytes[i] = static_cast<uint8_t>(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
    }
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    image.width = width;
    image.height = height;
    image.format = PNG_FORMAT_RGBA;
    // A negative row stride tells libpng the rows are stored bottom to top.
    if (!png_image_write_to_file(&image, path.c_str(), 0, bytes.data(), -4 * width, nullptr))
        throw std::runtime_error("could not write PNG " + path + ": " + image.message);
}

}  // namespace smis
