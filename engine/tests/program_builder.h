// Shader programs written by hand for tests (shader_program_test.cpp, environment_light_test.cpp):
// registers hold floats, vectors take three; the ops' fields are set directly.
#pragma once
#include <memory>
#include <vector>

#include "shading/shader_program.h"

namespace smis::testing {

struct ProgramBuilder {
    std::vector<ShaderOp> ops;
    std::vector<float> regs;
    std::vector<std::shared_ptr<const Texture>> textures;
    std::vector<float> data;  // the ops' tables (sky parameters)
    uint16_t constant(float v) {
        regs.push_back(v);
        return uint16_t(regs.size() - 1);
    }
    uint16_t constant3(const Vec3& v) {
        regs.insert(regs.end(), {v.x, v.y, v.z});
        return uint16_t(regs.size() - 3);
    }
    uint16_t alloc(int n) {
        regs.resize(regs.size() + n, 0.0f);
        return uint16_t(regs.size() - n);
    }
    ShaderOp& op(ShaderOpCode code) {
        ops.emplace_back();
        ops.back().code = code;
        return ops.back();
    }
    // Texture Coordinate's Generated output (the direction, in the World).
    uint16_t direction() {
        uint16_t v = alloc(3);
        op(ShaderOpCode::TexCoord).out[0] = v;
        return v;
    }
    uint16_t environment(uint16_t vec, std::shared_ptr<const Texture> tex, int projection = 0) {
        textures.push_back(std::move(tex));
        uint16_t c = alloc(3);
        ShaderOp& o = op(ShaderOpCode::TexEnvironment);
        o.in[0] = vec, o.out[0] = c, o.i[0] = int(textures.size() - 1), o.i[1] = projection;
        return c;
    }
    // A Nishita Sky Texture (the add-on's data layout); plain: its vector is the plain direction, so
    // an EnvironmentLight samples its sun on its own.
    uint16_t nishita_sky(uint16_t vec, const NishitaParams& p, bool plain = true) {
        uint16_t c = alloc(3);
        ShaderOp& o = op(ShaderOpCode::TexSky);
        o.in[0] = vec, o.out[0] = c, o.i[0] = 2, o.i[2] = plain ? 1 : 0;
        o.data = uint32_t(data.size());
        data.insert(data.end(), {p.sun_elevation, p.sun_rotation, p.sun_disc ? 1.0f : 0.0f, p.sun_size,
                                 p.sun_intensity, p.altitude, p.air_density, p.dust_density, p.ozone_density});
        return c;
    }
    void background(uint16_t color, float strength) {
        ShaderOp& o = op(ShaderOpCode::Background);
        o.in[1] = color, o.in[2] = constant(strength);
    }
    std::shared_ptr<const ShaderProgram> build() {
        auto p = std::make_shared<ShaderProgram>(ops, regs, data, textures);
        p->fold_constants();
        return p;
    }
};

}  // namespace smis::testing
