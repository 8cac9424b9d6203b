#include "spectral/spectral_scene.h"

#include <map>
#include <tuple>

namespace smis::spectral {

namespace {

SpectralMaterial make_material(const Material& m) {
    SpectralMaterial out;
    const tables::MetalTable* metal = m.spectral.metal == "NONE" ? nullptr : find_metal(m.spectral.metal);
    for (size_t i = 0; i < m.lobes.size(); ++i) {
        const Lobe& lobe = m.lobes[i];
        SpectralLobe s;
        s.weight = rgb_spectrum(lobe.weight);
        s.varies = m.program || (i < m.inputs.size() && m.inputs[i].varies());
        if (lobe_colour_f0(lobe)) s.f0 = rgb_spectrum(lobe.f0);
        if (lobe.kind == LobeKind::Subsurface) {
            s.albedo = rgb_spectrum(lobe.f0);
            s.radius = rgb_spectrum(lobe.kind_colour);
        }
        // A measured metal replaces the Fresnel of the tinted lobes that are not a dielectric layer.
        if (lobe_spectral_fresnel(lobe) == SpectralFresnel::Tinted && lobe_measured_metal(lobe)) s.metal = metal;
        // Only Dirac refraction disperses (lobes/dielectric.h).
        if (lobe_dispersive(lobe) && lobe_is_delta(lobe)) {
            if (m.spectral.dispersion == "ABBE") s.dispersion = Dispersion::abbe(lobe.eta, m.spectral.abbe);
            else if (m.spectral.dispersion != "NONE") Dispersion::sellmeier(m.spectral.dispersion, &s.dispersion);
            out.dispersive |= s.dispersion.active();
        }
        out.lobes.push_back(s);
    }
    return out;
}

}  // namespace

SpectralScene::SpectralScene(const Scene& scene) : scene_(scene) {
    // Lights sharing a spectrum (every triangle of an emissive mesh) share one EmitterSpectrum.
    std::map<std::tuple<std::string, float, float, float, float>, uint32_t> unique;
    for (uint32_t i = 0; i < scene.lights().size(); ++i) {
        const EmitterSource& src = scene.emitter_source(i);
        EmitterKind kind = EmitterKind::Rgb;
        parse_emitter_kind(src.spectrum, &kind);  // validated by the scene
        // Only an RGB spectrum depends on the colour, and only on its chromaticity.
        Color c = kind == EmitterKind::Rgb ? src.color / std::max(1e-20f, max_component(src.color)) : Color(0.0f);
        float t = kind == EmitterKind::Blackbody ? src.temperature : 0.0f;
        auto key = std::make_tuple(src.spectrum, t, c.x, c.y, c.z);
        auto it = unique.find(key);
        if (it == unique.end()) {
            it = unique.emplace(key, uint32_t(emitters_.size())).first;
            emitters_.emplace_back(kind, c, t);
        }
        light_emitter_.push_back(it->second);
    }
    for (size_t m = 0; m < scene.material_count(); ++m) materials_.push_back(make_material(scene.material(m)));
    // Emissive strands are no lights: their spectra are not in the importance mixture below (the
    // uniform part of it covers them). A spectrum, or an RGB colour the same at every hit, is
    // fitted here as the lights' are; a colour that varies is upsampled per hit (strand_emitter).
    for (size_t m = 0; m < scene.material_count(); ++m) {
        const Material& mat = scene.material(m);
        EmitterKind kind = EmitterKind::Rgb;
        parse_emitter_kind(mat.spectral.emission_spectrum, &kind);
        const bool constant_rgb = kind == EmitterKind::Rgb && !mat.program && !mat.emission_texture;
        int32_t fixed = -1;
        if (mat.emissive() && (kind != EmitterKind::Rgb || constant_rgb)) {
            fixed = int32_t(emitters_.size());
            const Color c = constant_rgb ? mat.emission / max_component(mat.emission) : Color(1.0f);
            emitters_.emplace_back(kind, c, mat.spectral.emission_temperature);
        }
        material_emitter_.push_back(fixed);
    }
    for (size_t m = 0; m < scene.medium_count(); ++m) {
        const Medium& med = scene.medium(int32_t(m));
        const Color sigma_t = med.sigma_t();
        Color albedo;
        for (int c = 0; c < 3; ++c) albedo[c] = sigma_t[c] > 0.0f ? std::min(1.0f, med.sigma_s[c] / sigma_t[c]) : 0.0f;
        media_.push_back({rgb_spectrum(sigma_t), rgb_spectrum(albedo)});
    }
}

WavelengthPdf SpectralScene::importance(float uniform_fraction) const {
    std::vector<double> emitter_weight(emitters_.size(), 0.0);
    for (uint32_t i = 0; i < light_emitter_.size(); ++i) emitter_weight[light_emitter_[i]] += scene_.light_pmf(i);
    std::vector<double> bins(WavelengthPdf::kBins, 0.0);
    double total = 0.0;
    for (int b = 0; b < WavelengthPdf::kBins; ++b) {
        float lambda = kLambdaMin + float(b) + 0.5f;
        double mixture = 0.0;
        for (size_t e = 0; e < emitters_.size(); ++e)
            if (emitter_weight[e] > 0.0) mixture += emitter_weight[e] * emitters_[e](lambda);
        if (emitters_.empty()) mixture = 1.0;
        bins[b] = mixture * double(length(rgb_response(lambda)));
        total += bins[b];
    }
    double uniform = total > 0.0 ? uniform_fraction * total / (1.0 - uniform_fraction) / WavelengthPdf::kBins : 1.0;
    for (double& v : bins) v += uniform;
    return WavelengthPdf(bins);
}

}  // namespace smis::spectral
