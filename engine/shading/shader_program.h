// A material's shader node tree compiled into a register program (the add-on's sync/shader_compiler.py
// writes it; Cycles' SVM is the model): a flat list of ops over a float register file, where colours
// and vectors take three consecutive registers. Per hit, the ops run in order and the closure ops
// collect Cycles' flattened closure list (lobes with their mix weights), emission, transparency and
// the shading normal.
//
// Constant folding happens once, at load: ops that read nothing of the hit are run then and their
// results become initial register values, so per hit only the ops that depend on the surface point
// run. A program left with no such op is constant: the material turns into plain lobes and keeps the
// prepared-BSDF fast path (Material::prepare).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "scene/bsdf.h"
#include "scene/texture.h"
#include "shading/shader_context.h"
#include "shading/sky_nishita.h"

namespace smis {

// Every op the compiler may emit; the names are the compiler's (shader_compiler.py), see op_by_name.
enum class ShaderOpCode : uint16_t {
    // inputs (read the hit)
    TexCoord, UvMap, Attribute, Geometry, ObjectInfo, LightPath, Fresnel, LayerWeight, CameraData, Tangent,
    HairGeometry, HairInfo,
    // bump evaluation: the ops between Enter and Leave see the point moved by one footprint in x or y
    BumpEnter, BumpLeave, Bump, NormalMap,
    // textures
    TexImage, TexNoise, TexVoronoi, TexMusgrave, TexWave, TexMagic, TexChecker, TexBrick, TexGradient, TexWhiteNoise,
    TexEnvironment, TexSky,
    // colour
    Mix, MixFloat, MixVector, RgbCurves, VectorCurves, Invert, HueSatVal, BrightContrast, Gamma,
    // vector
    Mapping, VectorTransform, NormalNode, VectorRotate, Displacement,
    // converter
    Math, VectorMath, MapRange, MapRangeVector, Clamp, ColorRamp, SeparateColor, CombineColor, CombineXyz,
    RgbToBw, Blackbody, Wavelength, Convert, MixWeights,
    // closures
    Diffuse, Glossy, Glass, Transparent, Principled, Emission, Holdout, Velvet, Translucent, Refraction, Toon,
    Background,  // the World's Background node: colour x strength into ShaderResult::emission
    Anisotropic,
    Subsurface,  // Subsurface Scattering node (scene/subsurface_closure.h)
    Hair, PrincipledHair,
    Count
};

constexpr uint16_t kNoReg = 0xFFFF;

struct ShaderOp {
    ShaderOpCode code = ShaderOpCode::Convert;
    uint16_t in[26];    // input registers, kNoReg when the op's default applies
    uint16_t out[13];   // output registers, kNoReg when the output is unused
    int32_t i[6] = {0, 0, 0, 0, 0, 0};  // modes, texture ids, table sizes
    float f[4] = {0, 0, 0, 0};
    uint32_t data = 0;  // offset of the op's table in ShaderProgram::data (ramps, curves)
    ShaderOp() {
        for (auto& r : in) r = kNoReg;
        for (auto& r : out) r = kNoReg;
    }
};

// What a program produced at a point: Cycles' closure list and the non-BSDF outputs.
// An anisotropic closure's own tangent (world space, as its Tangent input gives it) and Rotation (turns
// about the normal), for the lobe in the same slot of ShaderResult::lobes.
struct LobeTangent {
    float x, y, z, turns;
};

struct ShaderResult {
    LobeSlots<Bsdf::kMaxLobes> lobes;  // the first `count` are set
    int count = 0;
    Color emission{0.0f};
    Color transparent{0.0f};  // Transparent BSDF weights and (1 - alpha) of Principled, summed
    Color holdout{0.0f};
    Vec3 normal;              // shading normal of the closures (the first closure's own Normal input)
    bool has_normal = false;
    Vec3 tangent;                   // the first anisotropic closure's tangent (the shading frame's s axis),
    float tangent_rotation = 0.0f;  // turned about the normal by this many turns (Cycles' Rotation)
    bool has_tangent = false;
    // Every anisotropic lobe's own (kOwnTangent kinds; read only where has_tangent, so left
    // uninitialised: materials without one pay nothing). Scene::program_bsdf turns each into the
    // lobe's tangent within the shading frame (lobe.h, lobe_detail::to_lobe_tangent).
    LobeTangent lobe_tangents[Bsdf::kMaxLobes];
    bool truncated = false;   // more lobes than a Bsdf holds: the smallest were dropped
};

// What a caller reads of a result: everything; only `transparent` (a hit's cut-out); or `emission` and
// `transparent` (a hit's emitted radiance, divided by its keep probability). The narrower ones run only
// the ops those outputs depend on (ShaderProgram::analyse), with the same arithmetic in the same order:
// their values are bit for bit those of a full evaluation.
enum class ShaderOutputs : uint8_t { All, Transparency, Emission, Count };

class ShaderProgram {
public:
    // ops as the compiler wrote them, initial register values (constants), tables, textures by id.
    ShaderProgram(std::vector<ShaderOp> ops, std::vector<float> registers, std::vector<float> data,
                  std::vector<std::shared_ptr<const Texture>> textures);
    // Folds every op that reads nothing of the hit into the initial registers (see the header).
    void fold_constants();
    bool is_constant() const { return !needs_hit_; }
    // Runs the per-hit ops, then the closure ops, into `out`; with `outputs` narrower than All, only
    // those outputs of `out` are set (the others keep their defaults).
    void eval(const ShaderContext& ctx, ShaderResult* out, ShaderOutputs outputs = ShaderOutputs::All) const;
    // Evaluates a constant program (no context needed).
    ShaderResult eval_constant() const;
    // Lobe templates: for every lobe the closure ops can produce, in Lobe::index order, its kind and
    // Fresnel mode (spectral rendering keys its per-lobe data by index).
    const std::vector<Lobe>& lobe_templates() const { return templates_; }
    // Whether any closure op may emit light / let light through (after folding: an emission whose
    // strength folded to 0 does not count).
    bool may_emit() const { return may_emit_; }
    bool may_be_transparent() const { return may_be_transparent_; }
    // A Holdout closure with a weight that is not 0: the material stays a program even when its
    // closures fold (the holdout weight is per hit, not a lobe).
    bool may_hold_out() const { return may_hold_out_; }
    size_t op_count() const { return ops_.size(); }
    // Ops that run per hit for `outputs` (the value ops that read the hit, or what it feeds, and that
    // feed the closures `outputs` read; the others are dead code and never run).
    size_t varying_op_count(ShaderOutputs outputs = ShaderOutputs::All) const {
        const Slice& s = slices_[size_t(outputs)];
        return s.needs_hit ? s.varying.size() : 0;
    }
    size_t register_count() const { return registers_.size(); }
    // Whether an evaluation for `outputs` reads the context's object, tangent or footprint fields
    // (shader_context.h), or moves the point (Bump): without, Scene::shader_context fills the basic
    // part only and eval reads the caller's context in place.
    bool needs_full_context(ShaderOutputs outputs = ShaderOutputs::All) const {
        const Slice& s = slices_[size_t(outputs)];
        return s.needs_hit && s.full_context;
    }
    // The Nishita sky whose sun Cycles would sample on its own (one Nishita Sky Texture with its disc
    // above the horizon, reading the unmodified direction), else null (environment_light.h).
    const NishitaSky* sampled_sun() const;
    // Parses an op name as the compiler writes it; false for unknown names.
    static bool op_by_name(const std::string& name, ShaderOpCode* code);
    static constexpr size_t kMaxRegisters = 4096;

    // Read access for passes that recognise a whole program (scene/image_closure.h): the ops, the
    // initial register values (after folding), the ops a full evaluation runs per hit and its closure
    // ops (indices into ops()), and the textures by the ops' ids.
    const std::vector<ShaderOp>& ops() const { return ops_; }
    const std::vector<float>& initial_registers() const { return registers_; }
    const std::vector<uint32_t>& per_hit_ops() const { return slices_[size_t(ShaderOutputs::All)].varying; }
    const std::vector<uint32_t>& closure_ops() const { return slices_[size_t(ShaderOutputs::All)].closures; }
    const std::shared_ptr<const Texture>& texture(int32_t id) const { return textures_[size_t(id)]; }

private:
    // Context ops read (and the bump ops move) *ctx; it is null for folding and for closures.
    void run(const ShaderOp& op, ShaderContext* ctx, float* r, ShaderResult* out) const;
    // A closure's part that `outputs` (narrower than All) reads.
    void run_part(const ShaderOp& op, float* r, ShaderOutputs outputs, ShaderResult* out) const;
    void analyse();
    void slice(ShaderOutputs outputs, const std::vector<bool>& varying);
    // The ops one kind of evaluation runs: per hit, then the closures; needs_hit: some of those
    // closures read a value that varies over the surface (else the per-hit ops are skipped).
    struct Slice {
        std::vector<uint32_t> varying, closures;
        bool needs_hit = false;
        bool full_context = false;  // some per-hit op reads more of the hit than ShaderContext's basic part
    };
    std::vector<ShaderOp> ops_;
    std::vector<uint32_t> varying_;  // indices of the ops that vary per hit (inputs and what they feed)
    std::vector<uint32_t> closures_; // closure ops (run last, after every value op)
    Slice slices_[size_t(ShaderOutputs::Count)];
    std::vector<float> registers_;
    std::vector<float> data_;
    std::vector<std::shared_ptr<const Texture>> textures_;
    std::vector<std::shared_ptr<const NishitaSky>> skies_;  // the Nishita Sky Textures' tables (op.i[1])
    std::vector<Lobe> templates_;
    bool may_emit_ = false, may_be_transparent_ = false, may_hold_out_ = false;
    bool needs_hit_ = false;  // some closure reads a value that varies over the surface
};

}  // namespace smis
