#include "scene/image_closure.h"

namespace smis {
namespace {

using Op = ShaderOpCode;

// Whether register `reg` is one an op writes at `out` (`width` registers: a colour or vector takes three).
bool written_at(uint16_t reg, uint16_t out, int width) {
    return reg != kNoReg && out != kNoReg && reg >= out && reg < out + width;
}

}  // namespace

std::optional<ImageClosure> lower_image_closure(const ShaderProgram& program) {
    const std::vector<uint32_t>& per_hit = program.per_hit_ops();
    const std::vector<uint32_t>& closures = program.closure_ops();
    if (program.is_constant() || per_hit.size() != 2 || closures.size() != 1) return std::nullopt;
    const ShaderOp& uv = program.ops()[per_hit[0]];
    const ShaderOp& image = program.ops()[per_hit[1]];
    const ShaderOp& closure = program.ops()[closures[0]];
    // Texture Coordinate with only its UV output: (u, v, 0) of the render UV map.
    if (uv.code != Op::TexCoord || uv.out[2] == kNoReg) return std::nullopt;
    for (int k = 0; k < 13; ++k)
        if (k != 2 && uv.out[k] != kNoReg) return std::nullopt;
    // A flat Image Texture at that vector: the texture at (u, v).
    if (image.code != Op::TexImage || image.i[1] != 0 || image.in[0] != uv.out[2] || image.out[0] == kNoReg)
        return std::nullopt;
    // The Diffuse BSDF of that Color; its Weight and Roughness read nothing the two ops write.
    if (closure.code != Op::Diffuse || closure.in[1] != image.out[0] || closure.in[3] != kNoReg) return std::nullopt;
    for (uint16_t reg : {closure.in[0], closure.in[2]})
        if (written_at(reg, uv.out[2], 3) || written_at(reg, image.out[0], 3) || written_at(reg, image.out[1], 1))
            return std::nullopt;
    const std::shared_ptr<const Texture>& texture = program.texture(image.i[0]);
    if (!texture->non_negative()) return std::nullopt;
    const std::vector<float>& r = program.initial_registers();
    const float w = closure.in[0] == kNoReg ? 1.0f : r[closure.in[0]];
    if (!(w > 0.0f) || !std::isfinite(w)) return std::nullopt;
    // The Diffuse op's lobe (ShaderProgram::run) for a white colour.
    const float rough = clampf(closure.in[2] == kNoReg ? 0.0f : r[closure.in[2]], 0.0f, 1.0f);
    ImageClosure lowered;
    lowered.lobe.kind = rough > 0.0f ? LobeKind::OrenNayar : LobeKind::Diffuse;
    lowered.lobe.fresnel = FresnelMode::None;
    lowered.lobe.weight = Color(w);
    lowered.lobe.alpha = rough;
    lowered.lobe.eta = 1.5f;
    lowered.lobe.index = uint8_t(closure.i[5]);
    lowered.texture = texture;
    return lowered;
}

}  // namespace smis
