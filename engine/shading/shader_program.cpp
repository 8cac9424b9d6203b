#include "shading/shader_program.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <unordered_map>

#include "scene/environment_light.h"
#include "scene/scene.h"
#include "scene/subsurface_closure.h"
#include "shading/image_projection.h"
#include "shading/node_math.h"
#include "shading/normals.h"
#include "shading/procedural_cells.h"
#include "shading/procedural_noise.h"
#include "spectral/color.h"

namespace smis {
namespace {

using Op = ShaderOpCode;
using namespace shading;

// Input slots of the closure ops (the compiler writes them in this order; in[0] is the mix weight).
namespace principled_in {
enum : int {
    Weight, BaseColor, Subsurface, SubsurfaceRadius, SubsurfaceColor, SubsurfaceIor, SubsurfaceAnisotropy,
    Metallic, Specular, SpecularTint, Roughness, Anisotropic, AnisotropicRotation, Sheen, SheenTint, Clearcoat,
    ClearcoatRoughness, Ior, Transmission, TransmissionRoughness, Emission, EmissionStrength, Alpha, Normal,
    ClearcoatNormal, Tangent
};
}

constexpr struct {
    const char* name;
    Op code;
} kOpNames[] = {
    {"texcoord", Op::TexCoord}, {"uvmap", Op::UvMap}, {"attribute", Op::Attribute}, {"geometry", Op::Geometry},
    {"object_info", Op::ObjectInfo}, {"light_path", Op::LightPath}, {"fresnel", Op::Fresnel},
    {"layer_weight", Op::LayerWeight}, {"camera_data", Op::CameraData}, {"tangent", Op::Tangent},
    {"bump_enter", Op::BumpEnter}, {"bump_leave", Op::BumpLeave}, {"bump", Op::Bump}, {"normal_map", Op::NormalMap},
    {"tex_image", Op::TexImage}, {"tex_noise", Op::TexNoise}, {"tex_voronoi", Op::TexVoronoi},
    {"tex_musgrave", Op::TexMusgrave}, {"tex_wave", Op::TexWave}, {"tex_magic", Op::TexMagic},
    {"tex_checker", Op::TexChecker}, {"tex_brick", Op::TexBrick}, {"tex_gradient", Op::TexGradient},
    {"tex_white_noise", Op::TexWhiteNoise}, {"mix", Op::Mix}, {"mix_float", Op::MixFloat},
    {"mix_vector", Op::MixVector}, {"rgb_curves", Op::RgbCurves}, {"vector_curves", Op::VectorCurves},
    {"invert", Op::Invert}, {"hue_sat_val", Op::HueSatVal}, {"bright_contrast", Op::BrightContrast},
    {"gamma", Op::Gamma}, {"mapping", Op::Mapping}, {"vector_transform", Op::VectorTransform},
    {"normal", Op::NormalNode}, {"vector_rotate", Op::VectorRotate}, {"displacement", Op::Displacement},
    {"math", Op::Math}, {"vector_math", Op::VectorMath}, {"map_range", Op::MapRange},
    {"map_range_vector", Op::MapRangeVector}, {"clamp", Op::Clamp}, {"color_ramp", Op::ColorRamp},
    {"separate_color", Op::SeparateColor}, {"combine_color", Op::CombineColor}, {"combine_xyz", Op::CombineXyz},
    {"rgb_to_bw", Op::RgbToBw}, {"blackbody", Op::Blackbody}, {"wavelength", Op::Wavelength},
    {"convert", Op::Convert}, {"mix_weights", Op::MixWeights}, {"diffuse", Op::Diffuse}, {"glossy", Op::Glossy},
    {"glass", Op::Glass}, {"transparent", Op::Transparent}, {"principled", Op::Principled},
    {"emission", Op::Emission}, {"holdout", Op::Holdout}, {"velvet", Op::Velvet}, {"translucent", Op::Translucent},
    {"refraction", Op::Refraction}, {"toon", Op::Toon}, {"tex_environment", Op::TexEnvironment},
    {"tex_sky", Op::TexSky},
    {"background", Op::Background}, {"anisotropic", Op::Anisotropic}, {"subsurface", Op::Subsurface},
    {"hair", Op::Hair}, {"principled_hair", Op::PrincipledHair}, {"hair_geometry", Op::HairGeometry},
    {"hair_info", Op::HairInfo},
};

bool is_closure(Op code) { return code >= Op::Diffuse; }
// Ops that read the hit (their outputs vary over surfaces whatever their inputs). A box-projected
// image reads the surface normal to blend its three projections.
bool reads_context(const ShaderOp& op) {
    if (op.code == Op::TexImage && op.i[1] == 1) return true;
    switch (op.code) {
        case Op::TexCoord: case Op::UvMap: case Op::Attribute: case Op::Geometry: case Op::ObjectInfo:
        case Op::LightPath: case Op::Fresnel: case Op::LayerWeight: case Op::CameraData: case Op::Tangent:
        case Op::HairGeometry: case Op::HairInfo: case Op::BumpEnter: case Op::BumpLeave: case Op::Bump: case Op::NormalMap: case Op::VectorTransform:
        case Op::Displacement:
            return true;
        default: return false;
    }
}

// Context ops that read only ShaderContext's basic part (hit point, normals, view, facing, UV, the
// triangle and its barycentrics, the ray): every other context op (and any added later) gets the
// whole context.
bool reads_basic_context_only(const ShaderOp& op) {
    // Texture Coordinate's UV, Camera, Window and Reflection outputs, and Object from a chosen object.
    if (op.code == Op::TexCoord)
        return op.out[0] == kNoReg && op.out[1] == kNoReg && (op.out[3] == kNoReg || op.i[0] == 1);
    switch (op.code) {
        case Op::UvMap: case Op::Attribute: case Op::LightPath: case Op::Fresnel: case Op::LayerWeight:
        case Op::CameraData:
            return true;
        default: return false;
    }
}

inline Vec3 load3(const float* r, uint16_t i, const Vec3& fallback) {
    return i == kNoReg ? fallback : Vec3(r[i], r[i + 1], r[i + 2]);
}
inline float load1(const float* r, uint16_t i, float fallback) { return i == kNoReg ? fallback : r[i]; }
inline void store3(float* r, uint16_t i, const Vec3& v) {
    if (i == kNoReg) return;
    r[i] = v.x, r[i + 1] = v.y, r[i + 2] = v.z;
}
inline void store1(float* r, uint16_t i, float v) {
    if (i != kNoReg) r[i] = v;
}
inline float clamp01(float v) { return clampf(v, 0.0f, 1.0f); }

// The commonest value ops of real node trees (the glTF importer's groups are mostly Math nodes and
// shader mixes), which ShaderProgram::eval runs inline: the call into run()'s big switch cost more
// than these ops themselves.
inline void math_node(const ShaderOp& op, float* r) {
    float v = math_op(MathOp(op.i[0]), load1(r, op.in[0], 0.5f), load1(r, op.in[1], 0.5f), load1(r, op.in[2], 0.5f));
    if (op.i[1]) v = clamp01(v);
    store1(r, op.out[0], v);
}
inline void mix_weights_node(const ShaderOp& op, float* r) {
    float w = load1(r, op.in[0], 1.0f), f = clamp01(load1(r, op.in[1], 0.5f));
    store1(r, op.out[0], w * (1.0f - f));
    store1(r, op.out[1], w * f);
}
inline Vec3 safe_normalize(const Vec3& v, const Vec3& fallback) {
    float l = length(v);
    return l > 0.0f && std::isfinite(l) ? v / l : fallback;
}

Transform transform_from(const float* m) {
    Transform t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = m[4 * r + c];
    return t;
}

// Cycles' Mapping node: point = T R S v, texture = (T R S)^-1 v, vector = R S v, normal = normalize((R S)^-T v).
Vec3 rotate_euler_xyz(const Vec3& v, const Vec3& e, bool inverse) {
    float cx = std::cos(e.x), sx = std::sin(e.x), cy = std::cos(e.y), sy = std::sin(e.y), cz = std::cos(e.z),
          sz = std::sin(e.z);
    // R = Rz Ry Rx (Blender's XYZ Euler)
    float m[3][3] = {{cy * cz, sy * sx * cz - cx * sz, sy * cx * cz + sx * sz},
                     {cy * sz, sy * sx * sz + cx * cz, sy * cx * sz - sx * cz},
                     {-sy, cy * sx, cy * cx}};
    if (!inverse)
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    return {m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z, m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
            m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z};
}
inline Vec3 safe_divide(const Vec3& a, const Vec3& b) {
    return {b.x != 0.0f ? a.x / b.x : 0.0f, b.y != 0.0f ? a.y / b.y : 0.0f, b.z != 0.0f ? a.z / b.z : 0.0f};
}
// Cycles' object_normal_transform: the inverse transpose, which keeps a normal's direction under a
// mirroring transform (Transform::normal is the cofactor matrix, det times that: flipped there).
inline Vec3 object_normal_to_world(const ShaderContext& c, const Vec3& n) {
    const Vec3 v = c.to_world.normal(n);
    return c.to_world.determinant3() < 0.0f ? -v : v;
}
// Cycles' tangents are made perpendicular to the shading normal: N x normalize(t x N).
inline Vec3 tangent_about_normal(const ShaderContext& c, const Vec3& t) {
    return cross(c.N, safe_normalize(cross(t, c.N), Vec3(0.0f)));
}
// The radial tangent around the object's X, Y or Z axis through the texture space's centre
// (Generated coordinates - 0.5), turned into world space as Cycles does (a normal transform).
inline Vec3 radial_tangent(const ShaderContext& c, int axis) {
    const Vec3 g = safe_divide(c.to_object.point(c.P) - c.texspace_location, c.texspace_size * 2.0f);
    const Vec3 d = axis == 0 ? Vec3(0.0f, -g.z, g.y) : axis == 1 ? Vec3(-g.z, 0.0f, g.x) : Vec3(-g.y, g.x, 0.0f);
    return tangent_about_normal(c, object_normal_to_world(c, d));
}
Vec3 mapping(int type, const Vec3& v, const Vec3& loc, const Vec3& rot, const Vec3& scale) {
    switch (type) {
        case 0: return rotate_euler_xyz(v * scale, rot, false) + loc;                    // POINT
        case 1: return safe_divide(rotate_euler_xyz(v - loc, rot, true), scale);         // TEXTURE
        case 2: return rotate_euler_xyz(v * scale, rot, false);                          // VECTOR
        default: return safe_normalize(rotate_euler_xyz(safe_divide(v, scale), rot, false), Vec3(0.0f));  // NORMAL
    }
}

// Cycles' fresnel_dielectric_cos: unpolarised Fresnel reflectance, 1 under total internal reflection.
float fresnel_dielectric_cos(float cosi, float eta) {
    float c = std::fabs(cosi);
    float g = eta * eta - 1.0f + c * c;
    if (g <= 0.0f) return 1.0f;
    g = std::sqrt(g);
    float a = (g - c) / (g + c), b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    return 0.5f * a * a * (1.0f + b * b);
}

// Camera space as Cycles' shaders see it: x right, y up, z forward (into the view).
Vec3 to_camera_space(const Camera& cam, const Vec3& p, bool point) {
    Vec3 d = point ? p - cam.origin() : p;
    return {dot(d, cam.right_axis()), dot(d, cam.up_axis()), dot(d, cam.forward_axis())};
}

// Texture Coordinate in the World (Cycles' svm_node_tex_coord with no object): Generated, Object
// and Position are the direction D, Normal -D, UV 0, Reflection the incoming I = -D, Camera D in
// camera axes (the point at distance 1 along D from the camera), Window that point's projection.
// The Sky Texture's Preetham model (Cycles 3.4 svm/sky.h, "A Practical Analytic Model for Daylight").
// data: the sun's polar angle and azimuth (atan2(x, y), Cycles' spherical convention), a pad, the
// zenith Y, x, y normalised by the Perez function at the zenith, and the Perez coefficients A..E of
// Y, x and y, as the add-on's shader_compiler._sky_preetham computes them from turbidity and sun.
// Sky Texture models (op.i[0]) and the floats each reads at op.data.
enum SkyModel : int32_t { kSkyPreetham = 0, kSkyHosek = 1, kSkyNishita = 2 };
constexpr size_t kSkyDataSize[3] = {21, 32, 9};
float sky_perez(const float* lam, float theta, float gamma) {
    float cg = std::cos(gamma);
    return (1.0f + lam[0] * std::exp(lam[1] / std::cos(theta))) * (1.0f + lam[2] * std::exp(lam[3] * gamma) + lam[4] * cg * cg);
}
Color sky_preetham(const float* d, const Vec3& dir) {
    float theta = std::acos(clampf(dir.z, -1.0f, 1.0f)), phi = std::atan2(dir.x, dir.y);
    float sun_theta = d[0], sun_phi = d[1];
    float cospsi = std::sin(theta) * std::sin(sun_theta) * std::cos(sun_phi - phi) + std::cos(theta) * std::cos(sun_theta);
    float gamma = std::acos(clampf(cospsi, -1.0f, 1.0f));
    theta = std::min(theta, 0.5f * kPi - 0.001f);  // the ground repeats the horizon
    float x = d[4] * sky_perez(d + 11, theta, gamma), y = d[5] * sky_perez(d + 16, theta, gamma);
    float Y = d[3] * sky_perez(d + 6, theta, gamma);
    Vec3 xyz(y != 0.0f ? x / y * Y : 0.0f, Y, y != 0.0f && Y != 0.0f ? (1.0f - x - y) / y * Y : 0.0f);
    return spectral::xyz_to_rgb(xyz);
}

// Hosek and Wilkie 2012, "An Analytic Model for Full Spectral Sky-Dome Radiance", in CIE XYZ as
// Cycles 3.4 uses it: data = the sun's polar angle and azimuth, the three channels' radiance scales
// and nine configuration values each (eq. 9's A..I), cooked by the add-on from turbidity, ground
// albedo and the sun's elevation (shader_compiler._sky_hosek).
float hosek_channel(const float* c, float theta, float gamma) {
    const float cos_theta = std::cos(theta), cos_gamma = std::cos(gamma);
    const float chi = (1.0f + cos_gamma * cos_gamma) / std::pow(1.0f + c[8] * c[8] - 2.0f * c[8] * cos_gamma, 1.5f);
    return (1.0f + c[0] * std::exp(c[1] / (cos_theta + 0.01f))) *
           (c[2] + c[3] * std::exp(c[4] * gamma) + c[5] * cos_gamma * cos_gamma + c[6] * chi + c[7] * std::sqrt(cos_theta));
}
Color sky_hosek(const float* d, const Vec3& dir) {
    float theta = std::acos(clampf(dir.z, -1.0f, 1.0f)), phi = std::atan2(dir.x, dir.y);
    float cospsi = std::sin(theta) * std::sin(d[0]) * std::cos(d[1] - phi) + std::cos(theta) * std::cos(d[0]);
    float gamma = std::acos(clampf(cospsi, -1.0f, 1.0f));
    theta = std::min(theta, 0.5f * kPi - 0.001f);
    Vec3 xyz(hosek_channel(d + 5, theta, gamma) * d[2], hosek_channel(d + 14, theta, gamma) * d[3],
             hosek_channel(d + 23, theta, gamma) * d[4]);
    // The model's XYZ is in luminous units: Cycles scales it by 2 pi / 683.
    return vmax(spectral::xyz_to_rgb(xyz), Color(0.0f)) * (2.0f * kPi / 683.0f);
}

// object_tfm: the node's Object (world -> object rows), or null.
void tex_coord_background(const ShaderOp& op, const ShaderContext& c, const float* object_tfm, float* r) {
    store3(r, op.out[0], c.P);
    store3(r, op.out[1], c.N);
    store3(r, op.out[2], Vec3(0.0f));
    if (op.out[3] != kNoReg) store3(r, op.out[3], object_tfm ? transform_from(object_tfm).point(c.P) : c.P);
    if ((op.out[4] != kNoReg || op.out[5] != kNoReg) && c.scene) {
        const Camera& cam = c.scene->camera();
        store3(r, op.out[4], to_camera_space(cam, c.P, false));
        store3(r, op.out[5], cam.window_coordinates(cam.origin() + c.P));
    }
    store3(r, op.out[6], c.I);
}

// The lobe kind of a Glossy op's distribution (i[0]: 0 sharp, 1 GGX, 2 Beckmann, 3 multiscatter GGX,
// 4 Ashikhmin-Shirley) and of an Anisotropic op's (1 GGX, 2 Beckmann, 3 Ashikhmin-Shirley,
// 4 multiscatter GGX: its single scattering, the first of its two lobes).
LobeKind glossy_kind(int32_t mode) {
    switch (mode) {
        case 2: return LobeKind::Beckmann;
        case 3: return LobeKind::MultiGgx;
        case 4: return LobeKind::AshikhminShirley;
        default: return LobeKind::Microfacet;
    }
}
LobeKind anisotropic_kind(int32_t mode) {
    switch (mode) {
        case 2: return LobeKind::AnisoBeckmann;
        case 3: return LobeKind::AshikhminShirley;
        case 4: return LobeKind::MultiAnisoGgx;
        default: return LobeKind::AnisoGgx;
    }
}

}  // namespace

bool ShaderProgram::op_by_name(const std::string& name, ShaderOpCode* code) {
    for (const auto& e : kOpNames)
        if (name == e.name) {
            *code = e.code;
            return true;
        }
    return false;
}

ShaderProgram::ShaderProgram(std::vector<ShaderOp> ops, std::vector<float> registers, std::vector<float> data,
                             std::vector<std::shared_ptr<const Texture>> textures)
    : ops_(std::move(ops)), registers_(std::move(registers)), data_(std::move(data)), textures_(std::move(textures)) {
    if (registers_.size() > kMaxRegisters) throw std::invalid_argument("shader program: too many registers");
    // Every register reference must be inside the file; a vector read at the last float stays
    // inside thanks to two floats of padding.
    const size_t n = registers_.size();
    auto check = [&](uint16_t r) {
        if (r != kNoReg && size_t(r) >= n) throw std::invalid_argument("shader program: register out of range");
    };
    registers_.resize(n + 2, 0.0f);
    for (float& v : registers_)
        if (!std::isfinite(v)) v = 0.0f;  // NaN socket values: Blender would not render them either
    for (const ShaderOp& op : ops_) {
        for (uint16_t r : op.in) check(r);
        for (uint16_t r : op.out) check(r);
        if ((op.code == Op::TexImage || op.code == Op::TexEnvironment) &&
            (op.i[0] < 0 || size_t(op.i[0]) >= textures_.size()))
            throw std::invalid_argument("shader program: unknown texture");
        if (op.code == Op::ColorRamp || op.code == Op::RgbCurves || op.code == Op::VectorCurves) {
            if (op.i[0] < 1 || size_t(op.data) + size_t(op.i[0]) * 4 > data_.size())
                throw std::invalid_argument("shader program: table out of range");
        }
        if (op.code == Op::TexSky && (op.i[0] < kSkyPreetham || op.i[0] > kSkyNishita ||
                                      size_t(op.data) + kSkyDataSize[op.i[0]] > data_.size()))
            throw std::invalid_argument("shader program: sky data out of range");
        if (op.code == Op::TexCoord && op.i[0] == 1 && size_t(op.data) + 12 > data_.size())
            throw std::invalid_argument("shader program: object transform out of range");
        if (op.code >= Op::Count) throw std::invalid_argument("shader program: unknown op");
    }
    for (ShaderOp& op : ops_) {
        if (op.code != Op::TexSky || op.i[0] != kSkyNishita) continue;
        const float* d = &data_[op.data];
        NishitaParams p;
        p.sun_elevation = d[0];
        p.sun_rotation = d[1];
        p.sun_disc = d[2] != 0.0f;
        p.sun_size = d[3];
        p.sun_intensity = d[4];
        p.altitude = d[5];
        p.air_density = d[6];
        p.dust_density = d[7];
        p.ozone_density = d[8];
        for (float v : {p.sun_elevation, p.sun_rotation, p.sun_size, p.sun_intensity, p.altitude, p.air_density,
                        p.dust_density, p.ozone_density})
            if (!std::isfinite(v)) throw std::invalid_argument("shader program: Nishita sky parameters must be finite");
        op.i[1] = int32_t(skies_.size());
        skies_.push_back(std::make_shared<const NishitaSky>(p));
    }
    analyse();
}

const NishitaSky* ShaderProgram::sampled_sun() const {
    const ShaderOp* found = nullptr;
    for (const ShaderOp& op : ops_) {
        if (op.code != Op::TexSky || op.i[0] != kSkyNishita || !skies_[op.i[1]]->has_sun()) continue;
        if (found || op.i[2] != 1) return nullptr;  // several suns, or a transformed direction
        found = &op;
    }
    return found ? skies_[found->i[1]].get() : nullptr;
}

void ShaderProgram::analyse() {
    std::vector<bool> varying(registers_.size() + 3, false);
    varying_.clear();
    closures_.clear();
    templates_.clear();
    auto reads_varying = [&](const ShaderOp& op) {
        for (uint16_t r : op.in)
            if (r != kNoReg && (varying[r] || varying[r + 1] || varying[r + 2])) return true;
        return false;
    };
    for (uint32_t k = 0; k < ops_.size(); ++k) {
        ShaderOp& op = ops_[k];
        if (is_closure(op.code)) {
            op.i[5] = int32_t(templates_.size());
            closures_.push_back(k);
            Lobe l;
            switch (op.code) {
                case Op::Diffuse: {  // Oren-Nayar where the roughness may be above 0 (a measurement build refuses it)
                    uint16_t rough = op.in[2];
                    if (rough != kNoReg && (varying[rough] || registers_[rough] > 0.0f)) l.kind = LobeKind::OrenNayar;
                    templates_.push_back(l);
                    break;
                }
                case Op::Glossy:  // i[0]: 0 sharp, 1 GGX, 2 Beckmann, 3 multiscatter GGX (two lobes), 4 Ashikhmin-Shirley
                    l.kind = glossy_kind(op.i[0]);
                    templates_.push_back(l);
                    if (op.i[0] == 3) {
                        l.kind = LobeKind::GgxMultiple;
                        templates_.push_back(l);
                    }
                    break;
                case Op::Anisotropic:  // i[0]: 1 GGX, 2 Beckmann, 3 Ashikhmin-Shirley, 4 multiscatter GGX (two lobes)
                    l.kind = anisotropic_kind(op.i[0]);
                    templates_.push_back(l);
                    if (op.i[0] == 4) {
                        l.kind = LobeKind::AnisoGgxMultiple;
                        templates_.push_back(l);
                    }
                    break;
                case Op::Hair:  // i[0]: 0 reflection, 1 transmission
                    l.kind = op.i[0] == 1 ? LobeKind::HairTransmission : LobeKind::HairReflection;
                    templates_.push_back(l);
                    break;
                case Op::PrincipledHair:  // R, TT, TRT, TRRT+
                    for (int p = 0; p < 4; ++p) {
                        l.kind = LobeKind(int(LobeKind::PrincipledHairR) + p);
                        templates_.push_back(l);
                    }
                    break;
                case Op::Glass:  // i[0]: 0 sharp, 1 GGX, 2 Beckmann, 3 multiscatter GGX (two lobes)
                    l.kind = op.i[0] == 3 ? LobeKind::MultiGlass : LobeKind::Dielectric;
                    templates_.push_back(l);
                    if (op.i[0] == 3) {
                        l.kind = LobeKind::GlassMultiple;
                        templates_.push_back(l);
                    }
                    break;
                case Op::Velvet: l.kind = LobeKind::Velvet; templates_.push_back(l); break;
                case Op::Translucent: l.kind = LobeKind::Translucent; templates_.push_back(l); break;
                case Op::Refraction: l.kind = LobeKind::Refraction; templates_.push_back(l); break;
                case Op::Toon:  // i[0]: 0 diffuse, 1 glossy
                    l.kind = op.i[0] == 1 ? LobeKind::ToonGlossy : LobeKind::ToonDiffuse;
                    templates_.push_back(l);
                    break;
                case Op::Principled: {
                    Lobe d; d.kind = LobeKind::PrincipledDiffuse;
                    Lobe s; s.kind = LobeKind::Microfacet; s.fresnel = FresnelMode::Dielectric;
                    Lobe m; m.kind = LobeKind::Microfacet; m.fresnel = FresnelMode::Schlick;
                    Lobe t; t.kind = LobeKind::PrincipledGlass;
                    Lobe sh; sh.kind = LobeKind::Sheen;
                    Lobe c; c.kind = LobeKind::Clearcoat;
                    Lobe ms; ms.kind = LobeKind::GgxMultiple;  // the metal's multiple scattering (Multiscatter GGX)
                    Lobe gms; gms.kind = LobeKind::GlassMultiple;  // the glass' multiple scattering (Multiscatter GGX)
                    for (const Lobe& x : {d, s, m, t, sh, c, ms, gms}) templates_.push_back(x);
                    // Subsurface (where it may be above 0): its walk's entry and the retro-reflection.
                    uint16_t sss = op.in[principled_in::Subsurface];
                    if (sss != kNoReg && (varying[sss] || registers_[sss] > 0.0f)) {
                        Lobe entry; entry.kind = LobeKind::Subsurface;
                        Lobe retro; retro.kind = LobeKind::PrincipledPart;
                        templates_.push_back(entry);
                        templates_.push_back(retro);
                    }
                    break;
                }
                case Op::Subsurface: {
                    Lobe entry; entry.kind = LobeKind::Subsurface;
                    templates_.push_back(entry);
                    break;
                }
                default: break;
            }
            for (size_t t = op.i[5]; t < templates_.size(); ++t) templates_[t].index = uint8_t(std::min<size_t>(t, 255));
            continue;
        }
        // An image of one texel (Cycles' magenta stand-in for a missing file) looks the same from
        // everywhere: its lookup folds whatever its vector.
        bool single_texel = ((op.code == Op::TexImage && op.i[1] != 1) || op.code == Op::TexEnvironment) &&
                            textures_[op.i[0]]->constant();
        if (!single_texel && (reads_context(op) || reads_varying(op))) {
            varying_.push_back(k);
            for (uint16_t r : op.out)
                if (r != kNoReg) varying[r] = varying[r + 1] = varying[r + 2] = true;
        }
    }
    // The straight-through lobe Material::program_bsdf adds for coloured transparency.
    Lobe straight;
    straight.kind = LobeKind::Transparent;
    straight.index = uint8_t(std::min<size_t>(templates_.size(), 255));
    templates_.push_back(straight);
    bool varying_closure = false;
    may_emit_ = may_be_transparent_ = may_hold_out_ = false;
    // Whether a float (varies1) or a colour (varies3) input is written per hit.
    auto varies1 = [&](uint16_t reg) { return reg != kNoReg && varying[reg]; };
    auto varies3 = [&](uint16_t reg) { return reg != kNoReg && (varying[reg] || varying[reg + 1] || varying[reg + 2]); };
    const float* r = registers_.data();
    for (uint32_t k : closures_) {
        const ShaderOp& op = ops_[k];
        varying_closure = varying_closure || reads_varying(op);
        // Only the inputs that decide it: a textured base colour does not make a material emissive.
        bool weight_zero = !varies1(op.in[0]) && !(load1(r, op.in[0], 1.0f) != 0.0f);
        if (op.code == Op::Emission) {
            bool varying_e = varies1(op.in[0]) || varies3(op.in[1]) || varies1(op.in[2]);
            bool zero = !varying_e && (weight_zero || is_black(load3(r, op.in[1], Color(1.0f)) * load1(r, op.in[2], 1.0f)));
            may_emit_ = may_emit_ || !zero;
        }
        if (op.code == Op::Principled) {
            using namespace principled_in;
            bool varying_e = varies1(op.in[Weight]) || varies3(op.in[Emission]) || varies1(op.in[EmissionStrength]);
            bool zero = !varying_e && (weight_zero || is_black(load3(r, op.in[Emission], Color(0.0f)) *
                                                                load1(r, op.in[EmissionStrength], 0.0f)));
            may_emit_ = may_emit_ || !zero;
            bool opaque = !varies1(op.in[Alpha]) && (weight_zero || load1(r, op.in[Alpha], 1.0f) >= 1.0f);
            may_be_transparent_ = may_be_transparent_ || !opaque;
        }
        if (op.code == Op::Transparent) may_be_transparent_ = may_be_transparent_ || !weight_zero;
        if (op.code == Op::Holdout) may_hold_out_ = may_hold_out_ || !weight_zero;
    }
    // Values that vary but feed no closure (a texture into nothing, or into an input that folded) make
    // no difference per hit: the program is constant, and those ops are never run.
    needs_hit_ = varying_closure;
    for (size_t o = 0; o < size_t(ShaderOutputs::Count); ++o) slice(ShaderOutputs(o), varying);
}

namespace {
// Calls f(register) for every input of closure `op` that `outputs` depends on; false where the
// closure adds nothing to those outputs.
template <class F>
bool closure_inputs(const ShaderOp& op, ShaderOutputs outputs, F&& f) {
    using namespace principled_in;
    auto each = [&](std::initializer_list<int> slots) {
        for (int k : slots) f(op.in[k]);
        return true;
    };
    if (outputs == ShaderOutputs::All) {
        for (uint16_t reg : op.in) f(reg);
        return true;
    }
    const bool emission = outputs == ShaderOutputs::Emission;
    switch (op.code) {
        case Op::Transparent: return each({0, 1});
        case Op::Principled:
            return emission ? each({Weight, Alpha, Emission, EmissionStrength}) : each({Weight, Alpha});
        case Op::Emission: case Op::Background: return emission && each({0, 1, 2});
        default: return false;
    }
}
}  // namespace

// The ops an evaluation for `outputs` needs: the closures that write those outputs, and backwards from
// their inputs every per-hit op whose result they read, directly or not (dead-code elimination: an op
// nothing needed reads never runs). An input names the first register of the value it reads, which is
// where its op wrote it, or one of the two after a vector output (the compiler's Separate XYZ/Color
// read components in place); the program does not say which outputs are vectors, so an op counts as
// writing the two registers after an output unless another op's output starts there: in doubt an op
// is kept. The bump ops, which move the point for the ops between them, are always kept.
void ShaderProgram::slice(ShaderOutputs outputs, const std::vector<bool>& varying) {
    Slice& s = slices_[size_t(outputs)];
    s = Slice();
    std::vector<bool> needed(registers_.size() + 3, false), starts(registers_.size() + 3, false),
        live(ops_.size(), false);
    for (const ShaderOp& op : ops_)
        for (uint16_t reg : op.out)
            if (reg != kNoReg) starts[reg] = true;
    auto need = [&](uint16_t reg) {
        if (reg != kNoReg) needed[reg] = true;
    };
    auto writes_needed = [&](uint16_t reg) {
        if (reg == kNoReg) return false;
        if (needed[reg]) return true;
        if (starts[reg + 1]) return false;
        return needed[reg + 1] || (!starts[reg + 2] && needed[reg + 2]);
    };
    for (uint32_t k : closures_) {
        bool reads_varying = false;
        auto input = [&](uint16_t reg) {
            need(reg);
            reads_varying = reads_varying || (reg != kNoReg && (varying[reg] || varying[reg + 1] || varying[reg + 2]));
        };
        if (!closure_inputs(ops_[k], outputs, input)) continue;
        s.closures.push_back(k);
        s.needs_hit = s.needs_hit || reads_varying;
    }
    for (size_t k = ops_.size(); k-- > 0;) {
        const ShaderOp& op = ops_[k];
        if (is_closure(op.code)) continue;
        bool keep = op.code == Op::BumpEnter || op.code == Op::BumpLeave;
        for (uint16_t reg : op.out) keep = keep || writes_needed(reg);
        if (!keep) continue;
        live[k] = true;
        for (uint16_t reg : op.in) need(reg);
    }
    for (uint32_t k : varying_)
        if (live[k]) {
            s.varying.push_back(k);
            s.full_context = s.full_context || (reads_context(ops_[k]) && !reads_basic_context_only(ops_[k]));
        }
}

void ShaderProgram::fold_constants() {
    size_t v = 0;
    for (uint32_t k = 0; k < ops_.size(); ++k) {
        if (is_closure(ops_[k].code)) continue;
        if (v < varying_.size() && varying_[v] == k) {
            ++v;
            continue;
        }
        run(ops_[k], nullptr, registers_.data(), nullptr);  // constant: result into the initial registers
    }
    for (float& x : registers_)
        if (!std::isfinite(x)) x = 0.0f;
    analyse();
}

ShaderResult ShaderProgram::eval_constant() const {
    ShaderResult out;
    std::vector<float> r = registers_;
    for (uint32_t k : closures_) run(ops_[k], nullptr, r.data(), &out);
    return out;
}

void ShaderProgram::eval(const ShaderContext& ctx_in, ShaderResult* out, ShaderOutputs outputs) const {
    const Slice& s = slices_[size_t(outputs)];
    float r[kMaxRegisters + 3];
    std::memcpy(r, registers_.data(), registers_.size() * sizeof(float));
    auto run_varying = [&](ShaderContext* ctx) {
        for (uint32_t k : s.varying) {
            const ShaderOp& op = ops_[k];
            if (op.code == Op::Math) math_node(op, r);
            else if (op.code == Op::MixWeights) mix_weights_node(op, r);
            else run(op, ctx, r, out);
        }
    };
    if (s.needs_hit) {
        if (s.full_context) {
            ShaderContext ctx = ctx_in;  // bump evaluation moves the point
            run_varying(&ctx);
        } else {
            // Only the bump ops write the context, and they need the full one: read in place.
            run_varying(const_cast<ShaderContext*>(&ctx_in));
        }
    }
    // Closures read registers only.
    if (outputs == ShaderOutputs::All)
        for (uint32_t k : s.closures) run(ops_[k], nullptr, r, out);
    else
        for (uint32_t k : s.closures) run_part(ops_[k], r, outputs, out);
}

namespace {

// Adds a lobe, keeping the heaviest ones when a mix has more lobes than a Bsdf holds; returns its slot
// in out->lobes, or -1 where it was left out.
int push_lobe(ShaderResult* out, const Lobe& lobe) {
    if (!(average(lobe.weight) > 0.0f) || !is_finite(lobe.weight)) return -1;
    if (out->count < Bsdf::kMaxLobes) {
        out->lobes[out->count] = lobe;
        return out->count++;
    }
    out->truncated = true;
    int smallest = 0;
    for (int i = 1; i < out->count; ++i)
        if (average(out->lobes[i].weight) < average(out->lobes[smallest].weight)) smallest = i;
    if (!(average(out->lobes[smallest].weight) < average(lobe.weight))) return -1;
    out->lobes[smallest] = lobe;
    return smallest;
}

void set_normal(ShaderResult* out, const float* r, uint16_t reg) {
    if (reg == kNoReg || out->has_normal) return;
    Vec3 n = load3(r, reg, Vec3(0.0f));
    if (!is_finite(n) || !(length_sq(n) > 0.0f)) return;
    out->normal = normalize(n);
    out->has_normal = true;
}

// The first anisotropic (or hair) closure's tangent and rotation (in turns about the normal) become the
// shading frame's s axis (Scene::program_bsdf); anisotropic lobes turn from it to their own
// (push_anisotropic_lobe), hair lobes keep it.
void set_tangent(ShaderResult* out, const float* r, uint16_t reg, float rotation) {
    if (reg == kNoReg || out->has_tangent) return;
    Vec3 t = load3(r, reg, Vec3(0.0f));
    if (!is_finite(t) || !(length_sq(t) > 0.0f) || !std::isfinite(rotation)) return;
    out->tangent = t;
    out->tangent_rotation = rotation;
    out->has_tangent = true;
}

// An anisotropic closure's lobe about its own Tangent (register) and Rotation (turns), as Cycles gives
// each closure its own (svm/closure.h); the first one's is also the shading frame's s axis. An unusable
// tangent leaves the lobe about the frame's.
void push_anisotropic_lobe(ShaderResult* out, const Lobe& lobe, const float* r, uint16_t tangent, float rotation) {
    set_tangent(out, r, tangent, rotation);
    int slot = push_lobe(out, lobe);
    if (slot < 0) return;
    Vec3 t = load3(r, tangent, Vec3(0.0f));
    bool usable = is_finite(t) && std::isfinite(rotation);
    out->lobe_tangents[slot] = usable ? LobeTangent{t.x, t.y, t.z, rotation} : LobeTangent{0.0f, 0.0f, 0.0f, 0.0f};
}

// Cycles' alpha_x, alpha_y of the Anisotropic BSDF (svm/closure.h): alpha = roughness^2 stretched along
// the tangent for anisotropy > 0 and across it for anisotropy < 0, |anisotropy| <= 0.99; each at most 1.
void anisotropic_alphas(float roughness, float anisotropy, Lobe* lobe) {
    float alpha = sqr(clamp01(std::isfinite(roughness) ? roughness : 0.0f));
    float a = clampf(std::isfinite(anisotropy) ? anisotropy : 0.0f, -0.99f, 0.99f);
    float ax = a < 0.0f ? alpha / (1.0f + a) : alpha * (1.0f - a);
    float ay = a < 0.0f ? alpha * (1.0f + a) : alpha / (1.0f - a);
    lobe->alpha = std::min(ax, 1.0f);
    lobe->alpha_y = std::min(ay, 1.0f);
}

Lobe make_lobe(LobeKind kind, FresnelMode fresnel, const Color& weight, float roughness, float ior, uint8_t index) {
    Lobe l;
    l.kind = kind;
    l.fresnel = fresnel;
    l.weight = vmax(weight, Color(0.0f));
    float rough = clamp01(std::isfinite(roughness) ? roughness : 0.0f);
    l.alpha = rough * rough;  // Blender's roughness is the square root of GGX alpha
    l.eta = std::isfinite(ior) && ior > 0.0f ? ior : 1.5f;
    l.index = index;
    return l;
}

// Cycles' Principled Hair closure (svm/closure.h, bsdf_principled_hair_setup) as four lobes
// (lobes/principled_hair.h) whose weights carry A_p at the hit's wo. in: weight, colour, melanin,
// melanin redness, tint, absorption coefficient, roughness, radial roughness, coat, IOR, offset,
// tangent, sin theta_o, |h|, Cycles' per-bounce LCG numbers (the hair_geometry op), Random (the
// node's, or Hair Info's per-strand one: the hair_info op), Random Color, Random Roughness; i[0]: 0
// absorption coefficient, 1 melanin concentration, 2 direct colouring.
float hair_albedo_roughness_scale(float x) {
    return (((((0.245f * x) + 5.574f) * x - 10.73f) * x + 2.532f) * x - 0.215f) * x + 5.969f;
}
Color hair_sigma_from_reflectance(const Color& c, float radial_roughness) {
    float scale = hair_albedo_roughness_scale(radial_roughness);
    Color s;
    for (int k = 0; k < 3; ++k) s[k] = sqr(std::log(std::max(c[k], 1e-6f)) / scale);
    return s;
}
float hair_remap_roughness(float v) {
    float v2 = v * v, v4 = v2 * v2, v20 = v4 * v4 * v4 * v4 * v4;
    return sqr(0.726f * v + 0.812f * v2 + 3.700f * v20);
}
void principled_hair_closure(const ShaderOp& op, const float* r, ShaderResult* out) {
    float w = load1(r, op.in[0], 1.0f);
    set_tangent(out, r, op.in[11], 0.0f);
    // Per-strand variation, Cycles 3.4's (svm/closure.h, CLOSURE_BSDF_HAIR_PRINCIPLED_ID): factors
    // 1 + 2 (random - 0.5) x amount, the roughness's on both roughnesses before they are clamped
    // (so the Color parametrisation's sigma sees the varied radial roughness too), Random Color's
    // (clamped to [0, 1]) on the Melanin input before its -log(1 - m) remap.
    const float random = load1(r, op.in[16], 0.0f);
    const float random_color = clamp01(load1(r, op.in[17], 0.0f)), random_roughness = load1(r, op.in[18], 0.0f);
    const float roughness_factor = 1.0f + 2.0f * (random - 0.5f) * random_roughness;
    float roughness = load1(r, op.in[6], 0.3f) * roughness_factor, radial = load1(r, op.in[7], 0.3f) * roughness_factor;
    float coat = clamp01(load1(r, op.in[8], 0.0f));
    float eta = load1(r, op.in[9], 1.55f), alpha = load1(r, op.in[10], 0.0349f);
    if (!std::isfinite(eta) || !(eta > 1e-3f)) eta = 1.55f;
    if (!std::isfinite(alpha)) alpha = 0.0f;
    Color sigma;
    if (op.i[0] == 0) {
        sigma = vmax(load3(r, op.in[5], Color(0.245531f, 0.52f, 1.365f)), Color(0.0f));
    } else if (op.i[0] == 1) {
        float melanin = load1(r, op.in[2], 0.8f) * (1.0f + 2.0f * (random - 0.5f) * random_color);
        melanin = -std::log(std::max(1.0f - melanin, 0.0001f));
        float redness = load1(r, op.in[3], 1.0f);
        float eu = melanin * (1.0f - redness), pheo = melanin * redness;
        sigma = Color(0.506f, 0.841f, 1.653f) * eu + Color(0.343f, 0.733f, 1.924f) * pheo +
                hair_sigma_from_reflectance(load3(r, op.in[4], Color(1.0f)), radial);
    } else {
        sigma = hair_sigma_from_reflectance(load3(r, op.in[1], Color(0.017513f, 0.005763f, 0.002059f)), radial);
    }
    float v = clampf(std::isfinite(roughness) ? roughness : 0.3f, 1e-3f, 1.0f);
    float s = clampf(std::isfinite(radial) ? radial : 0.3f, 1e-3f, 1.0f);
    float m0 = clampf((1.0f - coat) * v, 1e-3f, 1.0f);
    float v_r = hair_remap_roughness(v), m0_r = hair_remap_roughness(m0);
    float s2 = s * s, s4 = s2 * s2, s22 = s4 * s4 * s4 * s4 * s4 * s2;
    float s_r = (0.265f * s + 1.194f * s2 + 5.372f * s22) * std::sqrt(kPi / 8.0f);
    // A_p at wo (the hair_geometry op's sin theta_o and |h|).
    float sin_o = clampf(load1(r, op.in[12], 0.0f), -1.0f, 1.0f), abs_h = clamp01(load1(r, op.in[13], 0.0f));
    principled_hair::Attenuation at = principled_hair::attenuation(sin_o, abs_h, eta, sigma);
    const float v_p[4] = {m0_r, 0.25f * v_r, 4.0f * v_r, 4.0f * v_r};
    const float tilt[4] = {-2.0f * alpha, alpha, 4.0f * alpha, 0.0f};
    const float lcg0 = load1(r, op.in[14], -1.0f), lcg1 = load1(r, op.in[15], -1.0f);
    const bool with_lcg = lcg0 >= 0.0f && lcg1 >= 0.0f;
    for (int p = 0; p < 4; ++p) {
        if (!is_finite(at.a[p])) continue;
        Lobe l = make_lobe(LobeKind(int(LobeKind::PrincipledHairR) + p), FresnelMode::None, at.a[p] * w, 0.0f, eta,
                           uint8_t(op.i[5] + p));
        l.alpha = v_p[p];
        l.alpha_y = s_r;
        l.f0 = Color(tilt[p], 0.0f, 0.0f);
        if (with_lcg) {
            l.variant = PrincipledHairRLobe::kBounceLcg;
            l.kind_colour = Color(lcg0, lcg1, 0.0f);
        }
        push_lobe(out, l);
    }
}

// Multiscatter GGX of colour c (lobes/multiscatter_ggx.h): the height-correlated single scattering,
// and the energy of the multiple scattering in its own lobe, weighted by its share 1 - E_avg and the
// colour of Cycles' further bounces; none where there is next to none (smooth, or nearly).
void multiscatter_ggx(const Color& c, float w, float roughness, uint8_t index, ShaderResult* out) {
    Lobe single = make_lobe(LobeKind::MultiGgx, FresnelMode::None, c * w, roughness, 1.5f, index), multiple;
    mark_cycles_walkable(&single, c);
    push_lobe(out, single);
    if (multiple_scattering_lobe(single, c, &multiple)) push_lobe(out, multiple);
}

// Anisotropic Multiscatter GGX of colour c (lobes/multiscatter_aniso_ggx.h), `single` its single
// scattering, about the Tangent register `tangent` turned by `rotation`: the multiple scattering in the
// next lobe; at alpha_x = alpha_y (Anisotropy 0) the isotropic pair, as Cycles walks the isotropic
// microsurface there.
void multiscatter_aniso_ggx(Lobe single, const Color& c, const float* r, uint16_t tangent, float rotation,
                            ShaderResult* out) {
    Lobe multiple;
    mark_cycles_walkable(&single, c);
    if (single.alpha == single.alpha_y) {
        Lobe iso = single;
        iso.kind = LobeKind::MultiGgx;
        push_lobe(out, iso);
        if (multiple_scattering_lobe(iso, c, &multiple)) push_lobe(out, multiple);
        return;
    }
    push_anisotropic_lobe(out, single, r, tangent, rotation);
    if (aniso_multiple_scattering_lobe(single, c, &multiple)) push_anisotropic_lobe(out, multiple, r, tangent, rotation);
}

// Multiscatter GGX glass (lobes/multi_glass.h, glass_multiple.h) of weight w, walk colour c (colour
// model `variant`), Specular Tint `spec_tint` of its reflection: the single scattering at `index`, the
// multiple scattering at `multiple_index` where there is any to speak of. The Glass BSDF's colour is
// in w (its refraction white); the Principled's base colours the refraction.
void multiscatter_glass(const Color& w, const Color& c, float roughness, float ior, float spec_tint, uint8_t variant,
                        uint8_t index, uint8_t multiple_index, ShaderResult* out) {
    Lobe single = make_lobe(LobeKind::MultiGlass, FresnelMode::None, w, roughness, ior, index), multiple;
    single.f0 = variant == GlassMultipleLobe::kPerRefraction ? vmin(c, Color(1.0f)) : Color(1.0f);
    single.kind_colour.x = spec_tint;
    single.variant = variant;  // unused by MultiGlass; the colour model of Cycles' estimator (multi_glass_walk.h)
    push_lobe(out, single);
    if (glass_multiple_lobe(single, vmin(c, Color(1.0f)), variant, &multiple)) {
        multiple.index = multiple_index;
        push_lobe(out, multiple);
    }
}

// The Principled BSDF's transmission of weight g (lobes/principled_glass.h), as Cycles 3.4's
// svm/closure.h sets it up: the reflection at the roughness, the refraction for GGX at
// 1 - (1 - roughness)(1 - Transmission Roughness); the Multiscatter GGX distribution refracts at the
// roughness (Cycles ignores Transmission Roughness there).
void principled_glass(const Color& base, float g, float rough, float transmission_rough, float spec_tint, float ior,
                      bool multiscatter, uint8_t index, ShaderResult* out) {
    if (multiscatter && rough > 0.05f) {  // Cycles' one multiscatter glass closure (its Fresnel colours)
        multiscatter_glass(Color(g), base, rough, ior, spec_tint, GlassMultipleLobe::kPerRefraction, index,
                           uint8_t(index + 4), out);
        return;
    }
    Lobe l = make_lobe(LobeKind::PrincipledGlass, FresnelMode::None, Color(g), rough, ior, index);
    l.f0 = base;
    l.kind_colour.x = spec_tint;
    float rt = clamp01(std::isfinite(transmission_rough) ? transmission_rough : 0.0f);
    float refraction_rough = multiscatter ? std::sqrt(l.alpha) : 1.0f - (1.0f - std::sqrt(l.alpha)) * (1.0f - rt);
    l.alpha_y = refraction_rough * refraction_rough;
    push_lobe(out, l);
}

// The multiple scattering of the Principled metal with Multiscatter GGX (its MultiGgx lobe `metal`, Schlick
// f0 = base): Cycles' walk colours every bounce by the Fresnel colour at its microfacet; here every
// bounce by one effective colour, the cosine-weighted hemispherical average of Schlick's,
// f0 + (1 - f0) / 21, through multiscatter_tint (lobes/multiscatter_ggx.h). The dielectric layer's
// multiple scattering (F^2, under 1% of its light) is left out.
// An anisotropic metal (MultiAnisoGgx) has the anisotropic multiple scattering. False where there is
// next to none.
bool metal_multiple_scattering(const Lobe& metal, uint8_t index, Lobe* multiple) {
    Color c = metal.f0 + (Color(1.0f) - metal.f0) * (1.0f / 21.0f);
    bool made = metal.kind == LobeKind::MultiAnisoGgx ? aniso_multiple_scattering_lobe(metal, c, multiple)
                                                      : multiple_scattering_lobe(metal, c, multiple);
    if (!made) return false;
    multiple->weight *= c;  // the first bounce's colour (the Glossy BSDF's is in its weight)
    multiple->fresnel = FresnelMode::None;
    multiple->index = index;
    return true;
}

// Cycles' CLOSURE_WEIGHT_CUTOFF on Principled's Subsurface: below, the principled diffuse.
constexpr float kSubsurfaceCutoff = 1e-5f;

void push_subsurface(const SubsurfaceClosure& c, ShaderResult* out) {
    Lobe lobes[3];
    int n = subsurface_lobes(c, lobes);
    for (int k = 0; k < n; ++k) push_lobe(out, lobes[k]);
}

// Principled's subsurface (svm/closure.h): weight mixed x share, radius Subsurface Radius x Subsurface,
// the retro-reflection of Roughness at the entry; its templates follow the eight of analyse().
void principled_subsurface(const ShaderOp& op, const float* r, const Color& mixed, float share, float subsurface,
                           float roughness, ShaderResult* out) {
    using namespace principled_in;
    SubsurfaceClosure c;
    c.weight = mixed * share;
    c.albedo = mixed;
    c.radius = load3(r, op.in[SubsurfaceRadius], Color(1.0f)) * subsurface;
    c.ior = load1(r, op.in[SubsurfaceIor], 1.4f);
    c.anisotropy = load1(r, op.in[SubsurfaceAnisotropy], 0.0f);
    c.method = SubsurfaceMethod(clampf(float(op.i[1]), 0.0f, 2.0f));
    c.principled = true;
    c.roughness = roughness;
    c.index = uint8_t(op.i[5] + 8);
    push_subsurface(c, out);
}

// Blender 3.4's Principled BSDF as the engine's lobes (the translation materials.py did on constants):
// with m = metallic and t = transmission (1 - m): Cycles' principled diffuse base (1-m)(1-t), the
// dielectric specular layer (IOR from Specular: f0 = 0.08 specular, tinted by Specular Tint),
// the metal (Schlick, f0 = base), the glass base t, sheen and clearcoat; emission; alpha mixes in a
// transparent closure as Cycles does.
// Principled's weight: false where it is not above 0 (the closure adds nothing); else *w is the
// weight times Alpha, and the weight times 1 - Alpha goes to the transparency.
bool principled_weight(const ShaderOp& op, const float* r, ShaderResult* out, float* w) {
    using namespace principled_in;
    *w = std::max(load1(r, op.in[Weight], 1.0f), 0.0f);
    if (!(*w > 0.0f)) return false;
    float alpha = clamp01(load1(r, op.in[Alpha], 1.0f));
    if (alpha < 1.0f) out->transparent += Color(*w * (1.0f - alpha));
    *w *= alpha;
    return true;
}

// Principled's emission of (alpha-scaled) weight w.
void principled_emission(const ShaderOp& op, const float* r, float w, ShaderResult* out) {
    using namespace principled_in;
    Color e = load3(r, op.in[Emission], Color(0.0f)) * load1(r, op.in[EmissionStrength], 1.0f);
    if (is_finite(e)) out->emission += vmax(e, Color(0.0f)) * w;  // alpha-scaled, as Cycles' expansion
}

void principled(const ShaderOp& op, const float* r, ShaderResult* out) {
    using namespace principled_in;
    float w;
    if (!principled_weight(op, r, out, &w)) return;
    Color base = vmax(load3(r, op.in[BaseColor], Color(0.8f)), Color(0.0f));
    float subsurface = clamp01(load1(r, op.in[Subsurface], 0.0f));
    // Cycles' diffuse (or subsurface) colour: Base Color mixed towards Subsurface Color by Subsurface.
    Color mixed = subsurface > 0.0f
                      ? lerp(subsurface, base, vmax(load3(r, op.in[SubsurfaceColor], Color(0.8f)), Color(0.0f)))
                      : base;
    float m = clamp01(load1(r, op.in[Metallic], 0.0f));
    float t = clamp01(load1(r, op.in[Transmission], 0.0f)) * (1.0f - m);
    float rough = clamp01(load1(r, op.in[Roughness], 0.5f));
    float specular = std::max(load1(r, op.in[Specular], 0.5f), 0.0f);
    float spec_tint = clamp01(load1(r, op.in[SpecularTint], 0.0f));
    float ior = load1(r, op.in[Ior], 1.45f);
    uint8_t idx = uint8_t(op.i[5]);
    float dielectric = (1.0f - m) * (1.0f - t);
    set_normal(out, r, op.in[Normal]);
    float lum = luminance(base);
    Color tint = lum > 0.0f ? base / lum : Color(1.0f);
    if (subsurface > kSubsurfaceCutoff) principled_subsurface(op, r, mixed, w * dielectric, subsurface, rough, out);
    else push_lobe(out, make_lobe(LobeKind::PrincipledDiffuse, FresnelMode::None, mixed * (w * dielectric), rough, 1.5f, idx));
    // Anisotropic: Cycles' alpha_x = alpha / aspect, alpha_y = alpha aspect, aspect = sqrt(1 - 0.9 anisotropic),
    // about the Tangent turned by Anisotropic Rotation; 0 is the isotropic lobe.
    float anisotropic = load1(r, op.in[Anisotropic], 0.0f);
    bool aniso = anisotropic != 0.0f && std::isfinite(anisotropic);
    // Multiscatter GGX above roughness 0.075 (Cycles' threshold), isotropic or anisotropic
    // (lobes/multiscatter_ggx.h, multiscatter_aniso_ggx.h).
    bool multiscatter = op.i[0] == 1;
    bool multi_reflection = multiscatter && rough > 0.075f;
    LobeKind spec_kind = aniso ? (multi_reflection ? LobeKind::MultiAnisoGgx : LobeKind::AnisoGgx)
                               : multi_reflection ? LobeKind::MultiGgx : LobeKind::Microfacet;
    auto stretch = [&](Lobe* l) {
        if (!aniso) return;
        float aspect = std::max(safe_sqrt(1.0f - 0.9f * anisotropic), 1e-3f);
        l->alpha_y = std::min(l->alpha * aspect, 1.0f);
        l->alpha = std::min(l->alpha / aspect, 1.0f);
    };
    float rotation = aniso ? load1(r, op.in[AnisotropicRotation], 0.0f) : 0.0f;
    auto push_specular = [&](const Lobe& l) {
        if (aniso) push_anisotropic_lobe(out, l, r, op.in[Tangent], rotation);
        else push_lobe(out, l);
    };
    float f0 = std::min(0.08f * specular, 0.99f);
    // With Multiscatter GGX, Cycles' one reflection closure (multiscatter_walk.h, mark_cycles_principled):
    // weight w (1 - t), cspec0 = 0.08 Specular x tint colour x (1 - m) + base m, marked on the specular
    // layer or on a Metallic 1 metal for the setting multiscatter_cycles_walk.
    const float cycles_weight = w * (1.0f - t);
    bool carried = false;
    if (f0 > 0.0f) {
        float spec_ior = 2.0f / (1.0f - std::sqrt(f0)) - 1.0f;
        Color spec_color = lerp(spec_tint, Color(1.0f), tint);
        Lobe s = make_lobe(spec_kind, FresnelMode::Dielectric, spec_color * (w * dielectric), rough, spec_ior,
                           uint8_t(idx + 1));
        s.f0 = Color(f0);
        stretch(&s);
        if (multi_reflection && average(s.weight) > 0.0f) {
            Color tmp = Color(1.0f - spec_tint) + tint * spec_tint;
            mark_cycles_principled(&s, tmp * (specular * 0.08f) * (1.0f - m) + base * m, cycles_weight);
            carried = true;
        }
        push_specular(s);
    }
    Lobe metal = make_lobe(spec_kind, FresnelMode::Schlick, Color(w * m), rough, 1.5f, uint8_t(idx + 2));
    metal.f0 = vmin(base, Color(1.0f));
    stretch(&metal);
    if (multi_reflection && carried) {
        metal.variant = kCyclesPrincipledPart;
    } else if (multi_reflection && m == 1.0f) {  // the metal alone: cspec0 = base = its f0
        metal.eta = 2.0f / (1.0f - std::sqrt(f0)) - 1.0f;  // unused by its Schlick Fresnel
        mark_cycles_principled(&metal, metal.f0, cycles_weight);
        carried = true;
    }
    push_specular(metal);
    Lobe metal_multiple;
    if (multi_reflection && metal_multiple_scattering(metal, uint8_t(idx + 6), &metal_multiple)) {
        metal_multiple.variant = carried ? kCyclesPrincipledPart : 0;
        push_specular(metal_multiple);
    }
    if (t > 0.0f) principled_glass(base, w * t, rough, load1(r, op.in[TransmissionRoughness], 0.0f), spec_tint, ior,
                                   multiscatter, uint8_t(idx + 3), out);
    float sheen = std::max(load1(r, op.in[Sheen], 0.0f), 0.0f);
    if (sheen > 0.0f) {
        float st = clamp01(load1(r, op.in[SheenTint], 0.5f));
        Color c = lerp(st, Color(1.0f), tint);
        push_lobe(out, make_lobe(LobeKind::Sheen, FresnelMode::None, c * (w * dielectric * sheen), 0.0f, 1.5f,
                                 uint8_t(idx + 4)));
    }
    float coat = std::max(load1(r, op.in[Clearcoat], 0.0f), 0.0f);
    if (coat > 0.0f)
        push_lobe(out, make_lobe(LobeKind::Clearcoat, FresnelMode::None, Color(0.25f * coat * w),
                                 load1(r, op.in[ClearcoatRoughness], 0.03f), 1.5f, uint8_t(idx + 5)));
    principled_emission(op, r, w, out);
}

}  // namespace

// The part of a closure an evaluation for `outputs` (not All) reads: the Principled's transparency
// (and emission), the other closures of the slice whole (they write nothing else).
void ShaderProgram::run_part(const ShaderOp& op, float* r, ShaderOutputs outputs, ShaderResult* out) const {
    if (op.code != Op::Principled) {
        run(op, nullptr, r, out);
        return;
    }
    float w;
    if (principled_weight(op, r, out, &w) && outputs == ShaderOutputs::Emission) principled_emission(op, r, w, out);
}

void ShaderProgram::run(const ShaderOp& op, ShaderContext* ctxp, float* r, ShaderResult* out) const {
    const Vec3 zero(0.0f);
    // Context ops never run without a context (they are never folded).
    switch (op.code) {
        case Op::TexCoord: {
            const ShaderContext& c = *ctxp;
            if (c.background) {
                tex_coord_background(op, c, op.i[0] == 1 ? &data_[op.data] : nullptr, r);
                break;
            }
            Vec3 obj = c.to_object.point(c.P);
            if (op.out[0] != kNoReg)  // Generated: the object's texture space box mapped to [0, 1]
                store3(r, op.out[0], safe_divide(obj - c.texspace_location, c.texspace_size * 2.0f) + Vec3(0.5f));
            if (op.out[1] != kNoReg) store3(r, op.out[1], safe_normalize(c.to_world.normal_to_object(c.N), c.N));
            store3(r, op.out[2], Vec3(c.uv.x, c.uv.y, 0.0f));
            if (op.out[3] != kNoReg)
                store3(r, op.out[3], op.i[0] == 1 ? transform_from(&data_[op.data]).point(c.P) : obj);
            if ((op.out[4] != kNoReg || op.out[5] != kNoReg) && c.scene) {
                const Camera& cam = c.scene->camera();
                Vec3 cs = to_camera_space(cam, c.P, true);
                store3(r, op.out[4], cs);
                store3(r, op.out[5], cam.window_coordinates(c.P));
            }
            store3(r, op.out[6], reflect(c.I, c.N));
            break;
        }
        case Op::UvMap: {
            const ShaderContext& c = *ctxp;
            float a[4] = {c.uv.x, c.uv.y, 0.0f, 0.0f};
            if (op.i[0] >= 0 && c.scene) c.scene->attribute(c, op.i[0], a);
            store3(r, op.out[0], Vec3(a[0], a[1], 0.0f));
            break;
        }
        case Op::Attribute: {
            const ShaderContext& c = *ctxp;
            float a[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            bool found = c.scene && op.i[0] >= 0 && c.scene->attribute(c, op.i[0], a);
            if (!found) a[3] = 0.0f;
            Vec3 v(a[0], a[1], a[2]);
            store3(r, op.out[0], v);
            store3(r, op.out[1], v);
            store1(r, op.out[2], op.i[1] == 2 ? a[0] : (a[0] + a[1] + a[2]) / 3.0f);  // i1 == 2: a float attribute
            store1(r, op.out[3], found ? a[3] : 0.0f);
            break;
        }
        case Op::Geometry: {
            const ShaderContext& c = *ctxp;
            store3(r, op.out[0], c.P);
            store3(r, op.out[1], c.N);
            // Cycles' Geometry > Tangent: the radial tangent around the object's Z axis.
            if (op.out[2] != kNoReg) store3(r, op.out[2], radial_tangent(c, 2));
            store3(r, op.out[3], c.Ng);
            store3(r, op.out[4], c.I);
            store3(r, op.out[5], Vec3(1.0f - c.bu - c.bv, c.bu, 0.0f));
            store1(r, op.out[6], c.backfacing ? 1.0f : 0.0f);
            // Pointiness and Random Per Island: attributes the mesh export derived (i0, i1; -1 when
            // the output is unlinked), 0 where a mesh lacks them as in Cycles.
            for (int k = 0; k < 2; ++k) {
                float a[4] = {0.0f, 0.0f, 0.0f, 0.0f};
                if (op.out[7 + k] == kNoReg) continue;
                if (op.i[k] >= 0 && c.scene) c.scene->attribute(c, op.i[k], a);
                store1(r, op.out[7 + k], a[0]);
            }
            break;
        }
        case Op::ObjectInfo: {
            const ShaderContext& c = *ctxp;
            store3(r, op.out[0], c.object_location);
            store3(r, op.out[1], c.object_color);
            store1(r, op.out[2], c.object_alpha);
            store1(r, op.out[3], c.object_index);
            store1(r, op.out[4], c.material_index);
            store1(r, op.out[5], c.object_random);
            break;
        }
        case Op::LightPath: {
            const ShaderRay& ray = ctxp->ray;
            const float v[13] = {float(ray.camera),       float(ray.shadow),        float(ray.diffuse),
                                 float(ray.glossy),       float(ray.singular),      float(ray.reflection),
                                 float(ray.transmission), ray.length,               float(ray.depth),
                                 float(ray.diffuse_depth), float(ray.glossy_depth), float(ray.transparent_depth),
                                 float(ray.transmission_depth)};
            for (int k = 0; k < 13; ++k) store1(r, op.out[k], v[k]);
            break;
        }
        case Op::Fresnel: {
            const ShaderContext& c = *ctxp;
            Vec3 n = load3(r, op.in[1], c.N);
            float eta = std::max(load1(r, op.in[0], 1.45f), 1e-5f);
            eta = c.backfacing ? 1.0f / eta : eta;
            store1(r, op.out[0], fresnel_dielectric_cos(dot(c.I, n), eta));
            break;
        }
        case Op::LayerWeight: {
            const ShaderContext& c = *ctxp;
            Vec3 n = load3(r, op.in[1], c.N);
            float blend = load1(r, op.in[0], 0.5f);
            float eta = std::max(1.0f - blend, 1e-5f);
            eta = c.backfacing ? eta : 1.0f / eta;
            store1(r, op.out[0], fresnel_dielectric_cos(dot(c.I, n), eta));
            float f = std::fabs(dot(c.I, n));
            if (blend != 0.5f) {
                blend = clampf(blend, 0.0f, 1.0f - 1e-5f);
                blend = blend < 0.5f ? 2.0f * blend : 0.5f / (1.0f - blend);
                f = std::pow(f, blend);
            }
            store1(r, op.out[1], 1.0f - f);
            break;
        }
        case Op::CameraData: {
            const ShaderContext& c = *ctxp;
            if (!c.scene) break;
            const Camera& cam = c.scene->camera();
            Vec3 cs = to_camera_space(cam, c.P, true);
            store3(r, op.out[0], safe_normalize(cs, Vec3(0, 0, 1)));
            store1(r, op.out[1], cs.z);
            store1(r, op.out[2], length(c.P - cam.origin()));
            break;
        }
        case Op::Tangent: {
            const ShaderContext& c = *ctxp;
            if (op.i[0] == 2) {  // a hair closure's default: the curve's tangent (the mesh's dPdu elsewhere)
                store3(r, op.out[0], c.dPdu);
            } else if (op.i[0] == 1) {  // the UV map's MikkTSpace tangent; none without the map, as Cycles
                float a[4];
                const bool found = op.i[2] >= 0 && c.scene && c.scene->attribute(c, op.i[2], a);
                // Without exported tangents (a mesh with n-gons) the triangle's UV derivative.
                const Vec3 t = found ? object_normal_to_world(c, Vec3(a[0], a[1], a[2])) : c.dPdu;
                store3(r, op.out[0], length_sq(t) > 0.0f ? tangent_about_normal(c, t) : Vec3(0.0f));
            } else {
                store3(r, op.out[0], radial_tangent(c, op.i[1]));
            }
            break;
        }
        case Op::HairGeometry: {  // in: tangent; out: sin theta_o and |h| of wo in the hair frame, the LCG numbers
            // (Scene::program_bsdf's: x the tangent made normal to N, z = N)
            const ShaderContext& c = *ctxp;
            Vec3 t = load3(r, op.in[0], c.dPdu);
            Vec3 x = t - c.N * dot(c.N, t);
            float sin_o = 0.0f, abs_h = 0.0f;
            if (length_sq(x) > 1e-12f && is_finite(x)) {
                x = normalize(x);
                float wy = dot(c.I, cross(c.N, x)), wz = dot(c.I, c.N);
                float l = std::sqrt(wy * wy + wz * wz);
                sin_o = dot(c.I, x);
                abs_h = l > 0.0f ? std::fabs(wy) / l : 0.0f;
            }
            store1(r, op.out[0], sin_o);
            store1(r, op.out[1], abs_h);
            // Cycles' per-bounce LCG numbers of the path (-1: none, the path's own numbers apply).
            Point2 lcg{-1.0f, -1.0f};
            if (c.ray.path_key != 0) lcg = principled_hair::cycles_bounce_lcg(c.ray.path_key, c.ray.depth);
            store1(r, op.out[2], lcg.x);
            store1(r, op.out[3], lcg.y);
            break;
        }
        case Op::HairInfo: {  // in: the Random off hair; out: Is Strand, Random (Cycles' per-curve hash),
                              // Intercept, Length, Thickness, Tangent Normal (0 off hair, as Cycles)
            const ShaderContext& c = *ctxp;
            store1(r, op.out[0], c.curve ? 1.0f : 0.0f);
            store1(r, op.out[1], c.curve ? c.curve_random : load1(r, op.in[0], 0.0f));
            store1(r, op.out[2], c.curve_intercept);
            store1(r, op.out[3], c.curve_length);
            store1(r, op.out[4], c.curve_thickness);
            if (op.out[5] != kNoReg) {
                // Cycles' curve_tangent_normal: the view direction I without its part along the
                // tangent, normalised.
                Vec3 tn(0.0f);
                float t2 = length_sq(c.dPdu);
                if (c.curve && t2 > 0.0f) tn = safe_normalize(c.I - c.dPdu * (dot(c.dPdu, c.I) / t2), Vec3(0.0f));
                store3(r, op.out[5], tn);
            }
            break;
        }
        case Op::BumpEnter: {
            ShaderContext& c = *ctxp;
            if (op.i[0] == 0) {
                c.P += c.dPdx;
                c.uv = {c.uv.x + c.duvdx.x, c.uv.y + c.duvdx.y};
            } else {
                c.P += c.dPdy;
                c.uv = {c.uv.x + c.duvdy.x, c.uv.y + c.duvdy.y};
            }
            break;
        }
        case Op::BumpLeave: {
            // Restores the point (the caller's context copy is the unshifted one).
            ShaderContext& c = *ctxp;
            if (op.i[0] == 0) {
                c.P -= c.dPdx;
                c.uv = {c.uv.x - c.duvdx.x, c.uv.y - c.duvdx.y};
            } else {
                c.P -= c.dPdy;
                c.uv = {c.uv.x - c.duvdy.x, c.uv.y - c.duvdy.y};
            }
            break;
        }
        case Op::Bump: {
            // Cycles' svm_node_bump: the height's finite differences over the footprint give the
            // surface gradient; N' = normalize(|det| N - dist sign(det) grad), blended by Strength.
            const ShaderContext& c = *ctxp;
            Vec3 n = load3(r, op.in[5], c.N);
            float strength = std::max(load1(r, op.in[0], 1.0f), 0.0f);
            float dist = load1(r, op.in[1], 1.0f);
            float hc = load1(r, op.in[2], 0.0f), hx = load1(r, op.in[3], hc), hy = load1(r, op.in[4], hc);
            if (op.i[0]) dist = -dist;
            Vec3 rx = cross(c.dPdy, n), ry = cross(n, c.dPdx);
            float det = dot(c.dPdx, rx);
            Vec3 grad = rx * (hx - hc) + ry * (hy - hc);
            float absdet = std::fabs(det);
            Vec3 bumped = safe_normalize(n * absdet - grad * (dist * (det < 0.0f ? -1.0f : 1.0f)), n);
            Vec3 res = safe_normalize(bumped * strength + n * (1.0f - strength), n);
            store3(r, op.out[0], ensure_valid_reflection(c.Ng, c.I, res));
            break;
        }
        case Op::NormalMap: {
            const ShaderContext& c = *ctxp;
            Color col = load3(r, op.in[1], Color(0.5f, 0.5f, 1.0f));
            float strength = std::max(load1(r, op.in[0], 1.0f), 0.0f);
            Vec3 m = col * 2.0f - Vec3(1.0f);
            Vec3 n;
            // Cycles forms the map's normal in object space (the tangent frame of the object's own
            // mesh, the smooth normal unflipped) and turns it into world space as a normal, so a
            // non-uniformly scaled object bends it as Cycles does.
            Vec3 front = c.backfacing ? -c.N : c.N;
            Vec3 n_obj = safe_normalize(c.to_world.normal_to_object(front), front);
            switch (op.i[0]) {
                case 0: {  // tangent space: the UV map's MikkTSpace frame, as Cycles (unnormalised, interpolated)
                    float a[4];
                    if (op.i[1] >= 0 && c.scene && c.scene->attribute(c, op.i[1], a)) {
                        const Vec3 t(a[0], a[1], a[2]), normal = c.N_object;
                        const Vec3 b = cross(normal, t) * (a[3] < 0.0f ? -1.0f : 1.0f);
                        n = safe_normalize(object_normal_to_world(c, t * m.x + b * m.y + normal * m.z), front);
                        break;
                    }
                    // No exported tangents (a mesh with n-gons): the triangle's UV derivative.
                    Vec3 t = c.to_object.vector(c.dPdu);
                    t = t - n_obj * dot(n_obj, t);
                    if (!(length_sq(t) > 0.0f)) {
                        n = front;
                        break;
                    }
                    t = normalize(t);
                    Vec3 b = cross(n_obj, t) * (c.tangent_sign < 0.0f ? -1.0f : 1.0f);
                    n = safe_normalize(object_normal_to_world(c, t * m.x + b * m.y + n_obj * m.z), front);
                    break;
                }
                case 1: n = safe_normalize(object_normal_to_world(c, m), front); break;    // object space
                case 2: n = safe_normalize(m, front); break;                        // world space
                case 3: n = safe_normalize(object_normal_to_world(c, Vec3(m.x, m.y, -m.z)), front); break;  // Blender object
                default: n = safe_normalize(Vec3(m.x, m.y, -m.z), front); break;   // Blender world
            }
            if (c.backfacing) n = -n;
            // Cycles 3.4 bends the mapped normal back above the horizon only where a closure uses it
            // (Scene::program_bsdf), not in the node: a Normal Map read as a colour is unclamped.
            if (strength != 1.0f) n = safe_normalize(c.N + (n - c.N) * strength, c.N);
            store3(r, op.out[0], n);
            break;
        }
        case Op::TexImage: {
            const Texture& tex = *textures_[op.i[0]];
            Vec3 co = load3(r, op.in[0], zero);
            TextureSample s;
            switch (op.i[1]) {
                case 1: {  // BOX: up to three lookups blended by the object-space normal
                    const ShaderContext& c = *ctxp;  // box projection reads the hit (reads_context)
                    Vec3 n_obj = safe_normalize(c.to_world.normal_to_object(c.N), c.N);
                    BoxWeights bw = project_box(co, n_obj, op.f[0]);
                    for (int k = 0; k < 3; ++k)
                        if (bw.w[k] > 0.0f) {
                            TextureSample t = tex.lookup(bw.uv[k]);
                            s.rgb += t.rgb * bw.w[k];
                            s.alpha += t.alpha * bw.w[k];
                        }
                    break;
                }
                case 2: s = tex.lookup(project_sphere(co)); break;
                case 3: s = tex.lookup(project_tube(co)); break;
                default: s = tex.lookup(project_flat(co)); break;
            }
            store3(r, op.out[0], s.rgb);
            store1(r, op.out[1], s.alpha);
            break;
        }
        case Op::TexNoise: {
            TextureOut t = noise_texture(op.i[0], load3(r, op.in[0], zero), load1(r, op.in[1], 0.0f),
                                         load1(r, op.in[2], 5.0f), load1(r, op.in[3], 2.0f), load1(r, op.in[4], 0.5f),
                                         load1(r, op.in[5], 0.0f), op.out[1] != kNoReg);
            store1(r, op.out[0], t.fac);
            store3(r, op.out[1], t.color);
            break;
        }
        case Op::TexVoronoi: {
            VoronoiOut v = voronoi_texture(op.i[0], VoronoiFeature(op.i[1]), VoronoiMetric(op.i[2]),
                                           load3(r, op.in[0], zero), load1(r, op.in[1], 0.0f), load1(r, op.in[2], 5.0f),
                                           load1(r, op.in[3], 1.0f), load1(r, op.in[4], 0.5f), load1(r, op.in[5], 1.0f));
            store1(r, op.out[0], v.distance);
            store3(r, op.out[1], v.color);
            store3(r, op.out[2], v.position);
            store1(r, op.out[3], v.w);
            store1(r, op.out[4], v.radius);
            break;
        }
        case Op::TexMusgrave: {
            float f = musgrave_texture(op.i[0], MusgraveType(op.i[1]), load3(r, op.in[0], zero), load1(r, op.in[1], 0.0f),
                                       load1(r, op.in[2], 5.0f), load1(r, op.in[3], 2.0f), load1(r, op.in[4], 2.0f),
                                       load1(r, op.in[5], 2.0f), load1(r, op.in[6], 0.0f), load1(r, op.in[7], 1.0f));
            store1(r, op.out[0], f);
            break;
        }
        case Op::TexWave: {
            TextureOut t = wave_texture(WaveType(op.i[0]), WaveDirection(op.i[1]), WaveProfile(op.i[2]),
                                        load3(r, op.in[0], zero), load1(r, op.in[1], 5.0f), load1(r, op.in[2], 0.0f),
                                        load1(r, op.in[3], 2.0f), load1(r, op.in[4], 1.0f), load1(r, op.in[5], 0.5f),
                                        load1(r, op.in[6], 0.0f));
            store3(r, op.out[0], t.color);
            store1(r, op.out[1], t.fac);
            break;
        }
        case Op::TexMagic: {
            TextureOut t = magic_texture(op.i[0], load3(r, op.in[0], zero), load1(r, op.in[1], 5.0f), load1(r, op.in[2], 1.0f));
            store3(r, op.out[0], t.color);
            store1(r, op.out[1], t.fac);
            break;
        }
        case Op::TexChecker: {
            TextureOut t = checker_texture(load3(r, op.in[0], zero), load3(r, op.in[1], Color(0.8f)),
                                           load3(r, op.in[2], Color(0.2f)), load1(r, op.in[3], 5.0f));
            store3(r, op.out[0], t.color);
            store1(r, op.out[1], t.fac);
            break;
        }
        case Op::TexBrick: {
            BrickOut b = brick_texture(load3(r, op.in[0], zero), load3(r, op.in[1], Color(0.8f)), load3(r, op.in[2], Color(0.2f)),
                                       load3(r, op.in[3], Color(0.0f)), load1(r, op.in[4], 5.0f), load1(r, op.in[5], 0.02f),
                                       load1(r, op.in[6], 0.1f), load1(r, op.in[7], 0.0f), load1(r, op.in[8], 0.5f),
                                       load1(r, op.in[9], 0.25f), op.f[0], op.i[0], op.f[1], op.i[1]);
            store3(r, op.out[0], b.color);
            store1(r, op.out[1], b.fac);
            break;
        }
        case Op::TexGradient: {
            TextureOut t = gradient_texture(GradientType(op.i[0]), load3(r, op.in[0], zero));
            store3(r, op.out[0], t.color);
            store1(r, op.out[1], t.fac);
            break;
        }
        case Op::TexWhiteNoise: {
            TextureOut t = white_noise_texture(op.i[0], load3(r, op.in[0], zero), load1(r, op.in[1], 0.0f));
            store1(r, op.out[0], t.fac);
            store3(r, op.out[1], t.color);
            break;
        }
        case Op::TexSky: {
            const Vec3 dir = load3(r, op.in[0], zero);
            const float* d = &data_[op.data];
            store3(r, op.out[0], op.i[0] == kSkyNishita ? skies_[op.i[1]]->radiance(dir)
                                 : op.i[0] == kSkyHosek ? sky_hosek(d, dir)
                                                        : sky_preetham(d, dir));
            break;
        }
        case Op::TexEnvironment: {
            // Cycles' Environment Texture: the vector's direction projected onto the image,
            // equirectangular (i1 = 0) or mirror ball (1); the image's own interpolation.
            Vec3 d = safe_normalize(load3(r, op.in[0], zero), zero);
            Point2 uv = op.i[1] == 1 ? direction_to_mirrorball(d) : direction_to_equirectangular(d);
            TextureSample s = textures_[op.i[0]]->lookup(uv);
            store3(r, op.out[0], s.rgb);
            store1(r, op.out[1], s.alpha);
            break;
        }
        case Op::Mix: {
            float fac = load1(r, op.in[0], 0.5f);
            if (op.i[1]) fac = clamp01(fac);
            Color c = mix_blend(MixBlend(op.i[0]), fac, load3(r, op.in[1], zero), load3(r, op.in[2], zero));
            if (op.i[2]) c = vmin(vmax(c, zero), Color(1.0f));
            store3(r, op.out[0], c);
            break;
        }
        case Op::MixFloat: {
            float fac = load1(r, op.in[0], 0.5f);
            if (op.i[0]) fac = clamp01(fac);
            float a = load1(r, op.in[1], 0.0f), b = load1(r, op.in[2], 0.0f);
            store1(r, op.out[0], a + (b - a) * fac);
            break;
        }
        case Op::MixVector: {
            Vec3 fac = op.i[1] ? load3(r, op.in[0], Vec3(0.5f)) : Vec3(load1(r, op.in[0], 0.5f));
            if (op.i[0]) fac = vmin(vmax(fac, zero), Vec3(1.0f));
            Vec3 a = load3(r, op.in[1], zero), b = load3(r, op.in[2], zero);
            store3(r, op.out[0], a + (b - a) * fac);
            break;
        }
        case Op::RgbCurves: {
            const Rgba* table = reinterpret_cast<const Rgba*>(&data_[op.data]);
            store3(r, op.out[0], rgb_curves(table, op.i[0], op.f[0], op.f[1], load1(r, op.in[0], 1.0f), load3(r, op.in[1], zero), op.i[1] != 0));
            break;
        }
        case Op::VectorCurves: {
            const Rgba* table = reinterpret_cast<const Rgba*>(&data_[op.data]);
            store3(r, op.out[0], vector_curves(table, op.i[0], op.f[0], op.f[1], load1(r, op.in[0], 1.0f), load3(r, op.in[1], zero), op.i[1] != 0));
            break;
        }
        case Op::Invert: store3(r, op.out[0], invert_node(load1(r, op.in[0], 1.0f), load3(r, op.in[1], zero))); break;
        case Op::HueSatVal:
            store3(r, op.out[0], hue_saturation_value(load1(r, op.in[0], 0.5f), load1(r, op.in[1], 1.0f),
                                                      load1(r, op.in[2], 1.0f), load1(r, op.in[3], 1.0f),
                                                      load3(r, op.in[4], zero)));
            break;
        case Op::BrightContrast:
            store3(r, op.out[0], bright_contrast(load3(r, op.in[0], zero), load1(r, op.in[1], 0.0f), load1(r, op.in[2], 0.0f)));
            break;
        case Op::Gamma: store3(r, op.out[0], gamma_node(load3(r, op.in[0], zero), load1(r, op.in[1], 1.0f))); break;
        case Op::Mapping:
            store3(r, op.out[0], mapping(op.i[0], load3(r, op.in[0], zero), load3(r, op.in[1], zero), load3(r, op.in[2], zero),
                                         load3(r, op.in[3], Vec3(1.0f))));
            break;
        case Op::VectorTransform: {
            // i0: POINT / VECTOR / NORMAL, i1 from, i2 to: WORLD / OBJECT / CAMERA
            const ShaderContext& c = *ctxp;
            Vec3 v = load3(r, op.in[0], zero);
            int type = op.i[0];
            auto to_world = [&](const Vec3& x, int space) -> Vec3 {
                if (space == 1) return type == 0 ? c.to_world.point(x) : type == 1 ? c.to_world.vector(x) : object_normal_to_world(c, x);
                if (space == 2 && c.scene) {
                    const Camera& cam = c.scene->camera();
                    Vec3 w = cam.right_axis() * x.x + cam.up_axis() * x.y + cam.forward_axis() * x.z;
                    return type == 0 ? w + cam.origin() : w;
                }
                return x;
            };
            auto from_world = [&](const Vec3& x, int space) -> Vec3 {
                if (space == 1) return type == 0 ? c.to_object.point(x) : type == 1 ? c.to_object.vector(x) : c.to_object.normal(x);
                if (space == 2 && c.scene) return to_camera_space(c.scene->camera(), x, type == 0);
                return x;
            };
            Vec3 res = from_world(to_world(v, op.i[1]), op.i[2]);
            if (type == 2) res = safe_normalize(res, res);
            store3(r, op.out[0], res);
            break;
        }
        case Op::NormalNode: {
            Vec3 dir = Vec3(op.f[0], op.f[1], op.f[2]);
            Vec3 n = load3(r, op.in[0], zero);
            store3(r, op.out[0], dir);
            store1(r, op.out[1], dot(safe_normalize(dir, dir), safe_normalize(n, n)));
            break;
        }
        case Op::VectorRotate: {
            // i0: AXIS_ANGLE, X, Y, Z, EULER_XYZ; i1 invert. in: vector, center, axis, angle, rotation
            Vec3 v = load3(r, op.in[0], zero), center = load3(r, op.in[1], zero);
            Vec3 p = v - center;
            float sign = op.i[1] ? -1.0f : 1.0f;
            Vec3 res;
            if (op.i[0] == 4) {
                res = rotate_euler_xyz(p, load3(r, op.in[4], zero), op.i[1] != 0);
            } else {
                Vec3 axis = op.i[0] == 1 ? Vec3(1, 0, 0) : op.i[0] == 2 ? Vec3(0, 1, 0) : op.i[0] == 3 ? Vec3(0, 0, 1)
                                                                                                  : safe_normalize(load3(r, op.in[2], Vec3(0, 0, 1)), zero);
                float a = sign * load1(r, op.in[3], 0.0f);
                float ca = std::cos(a), sa = std::sin(a);
                // Rodrigues' rotation
                res = length_sq(axis) > 0.0f ? p * ca + cross(axis, p) * sa + axis * (dot(axis, p) * (1.0f - ca)) : p;
            }
            store3(r, op.out[0], res + center);
            break;
        }
        case Op::Displacement: {
            const ShaderContext& c = *ctxp;
            float h = load1(r, op.in[0], 0.0f), mid = load1(r, op.in[1], 0.5f), scale = load1(r, op.in[2], 1.0f);
            Vec3 n = load3(r, op.in[3], c.N);
            float amount = (h - mid) * scale;
            // Object space: the displacement is scaled with the object, as Cycles does.
            Vec3 d = op.i[0] == 0 ? c.to_world.vector(safe_normalize(c.to_world.normal_to_object(n), n) * amount)
                                  : n * amount;
            store3(r, op.out[0], d);
            break;
        }
        case Op::Math: math_node(op, r); break;
        case Op::VectorMath: {
            Vec3 vec(0.0f);
            float val = 0.0f;
            vector_math_op(VectorMathOp(op.i[0]), load3(r, op.in[0], zero), load3(r, op.in[1], zero),
                           load3(r, op.in[2], zero), load1(r, op.in[3], 1.0f), &vec, &val);
            store3(r, op.out[0], vec);
            store1(r, op.out[1], val);
            break;
        }
        case Op::MapRange:
            store1(r, op.out[0], map_range(MapRangeType(op.i[0]), load1(r, op.in[0], 1.0f), load1(r, op.in[1], 0.0f),
                                           load1(r, op.in[2], 1.0f), load1(r, op.in[3], 0.0f), load1(r, op.in[4], 1.0f),
                                           load1(r, op.in[5], 4.0f), op.i[1] != 0));
            break;
        case Op::MapRangeVector:
            store3(r, op.out[0], map_range_vector(MapRangeType(op.i[0]), load3(r, op.in[0], zero), load3(r, op.in[1], zero),
                                                  load3(r, op.in[2], Vec3(1.0f)), load3(r, op.in[3], zero),
                                                  load3(r, op.in[4], Vec3(1.0f)), load3(r, op.in[5], Vec3(4.0f)), op.i[1] != 0));
            break;
        case Op::Clamp:
            store1(r, op.out[0], clamp_node(op.i[0] == 1, load1(r, op.in[0], 1.0f), load1(r, op.in[1], 0.0f), load1(r, op.in[2], 1.0f)));
            break;
        case Op::ColorRamp: {
            const Rgba* table = reinterpret_cast<const Rgba*>(&data_[op.data]);
            Rgba c = ramp_lookup(table, op.i[0], load1(r, op.in[0], 0.5f), op.i[1] != 0, false);
            store3(r, op.out[0], c.rgb);
            store1(r, op.out[1], c.a);
            break;
        }
        case Op::SeparateColor: {
            Color c = load3(r, op.in[0], zero);
            store3(r, op.out[0], op.i[0] == 1 ? rgb_to_hsv(c) : op.i[0] == 2 ? rgb_to_hsl(c) : c);
            break;
        }
        case Op::CombineColor: {
            Color c(load1(r, op.in[0], 0.0f), load1(r, op.in[1], 0.0f), load1(r, op.in[2], 0.0f));
            store3(r, op.out[0], op.i[0] == 1 ? hsv_to_rgb(c) : op.i[0] == 2 ? hsl_to_rgb(c) : c);
            break;
        }
        case Op::CombineXyz:
            store3(r, op.out[0], Vec3(load1(r, op.in[0], 0.0f), load1(r, op.in[1], 0.0f), load1(r, op.in[2], 0.0f)));
            break;
        case Op::RgbToBw: store1(r, op.out[0], rgb_to_bw(load3(r, op.in[0], zero))); break;
        case Op::Blackbody: store3(r, op.out[0], blackbody(load1(r, op.in[0], 1500.0f))); break;
        case Op::Wavelength: store3(r, op.out[0], wavelength_to_rgb(load1(r, op.in[0], 500.0f))); break;
        case Op::Convert:
            // Implicit socket conversions as Blender's: float -> colour/vector broadcast, colour -> float
            // its luminance, vector -> float the average of its components.
            switch (op.i[0]) {
                case 0: store3(r, op.out[0], Vec3(load1(r, op.in[0], 0.0f))); break;
                case 1: store1(r, op.out[0], rgb_to_bw(load3(r, op.in[0], zero))); break;
                case 2: store1(r, op.out[0], average(load3(r, op.in[0], zero))); break;
                default: store3(r, op.out[0], load3(r, op.in[0], zero)); break;
            }
            break;
        case Op::MixWeights: mix_weights_node(op, r); break;
        // Closures (out is never null for them).
        case Op::Diffuse: {
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[3]);
            Color c = load3(r, op.in[1], Color(0.8f)) * w;
            // Cycles: Lambert at Roughness 0, Oren-Nayar with sigma = Roughness (not squared) above.
            float rough = clamp01(load1(r, op.in[2], 0.0f));
            Lobe l = make_lobe(rough > 0.0f ? LobeKind::OrenNayar : LobeKind::Diffuse, FresnelMode::None, c, 0.0f, 1.5f,
                               uint8_t(op.i[5]));
            l.alpha = rough;
            push_lobe(out, l);
            break;
        }
        case Op::Velvet: {  // sigma kept as is in alpha (lobes/velvet.h)
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[3]);
            Lobe l = make_lobe(LobeKind::Velvet, FresnelMode::None, load3(r, op.in[1], Color(0.8f)) * w, 0.0f, 1.5f,
                               uint8_t(op.i[5]));
            l.alpha = clamp01(load1(r, op.in[2], 1.0f));
            push_lobe(out, l);
            break;
        }
        case Op::Translucent: {
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[3]);
            push_lobe(out, make_lobe(LobeKind::Translucent, FresnelMode::None, load3(r, op.in[1], Color(0.8f)) * w, 0.0f,
                                     1.5f, uint8_t(op.i[5])));
            break;
        }
        case Op::Toon: {  // Size in alpha, Smooth in f0.x (lobes/toon_diffuse.h)
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[4]);
            Lobe l = make_lobe(op.i[0] == 1 ? LobeKind::ToonGlossy : LobeKind::ToonDiffuse, FresnelMode::None,
                               load3(r, op.in[1], Color(0.8f)) * w, 0.0f, 1.5f, uint8_t(op.i[5]));
            l.alpha = clamp01(load1(r, op.in[2], 0.5f));
            l.f0 = Color(clamp01(load1(r, op.in[3], 0.0f)), 0.0f, 0.0f);
            push_lobe(out, l);
            break;
        }
        case Op::Refraction: {
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[4]);
            float rough = op.i[0] == 0 ? 0.0f : load1(r, op.in[2], 0.0f);
            Lobe l = make_lobe(LobeKind::Refraction, FresnelMode::None, load3(r, op.in[1], Color(1.0f)) * w, rough,
                               load1(r, op.in[3], 1.45f), uint8_t(op.i[5]));
            l.variant = op.i[0] == 2 ? kBeckmannDistribution : kGgxDistribution;  // i[0]: 0 sharp, 1 GGX, 2 Beckmann
            push_lobe(out, l);
            break;
        }
        case Op::Glossy: {
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[3]);
            float rough = op.i[0] == 0 ? 0.0f : load1(r, op.in[2], 0.5f);
            Color c = load3(r, op.in[1], Color(0.8f));
            if (op.i[0] == 3) {
                multiscatter_ggx(c, w, rough, uint8_t(op.i[5]), out);
                break;
            }
            Lobe l = make_lobe(glossy_kind(op.i[0]), FresnelMode::None, c * w, rough, 1.5f, uint8_t(op.i[5]));
            l.alpha_y = l.alpha;  // isotropic (read by the Ashikhmin-Shirley lobe only)
            push_lobe(out, l);
            break;
        }
        case Op::Anisotropic: {  // in: weight, colour, roughness, anisotropy, rotation, normal, tangent
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[5]);
            Lobe l = make_lobe(anisotropic_kind(op.i[0]), FresnelMode::None, load3(r, op.in[1], Color(0.8f)) * w, 0.0f,
                               1.5f, uint8_t(op.i[5]));
            anisotropic_alphas(load1(r, op.in[2], 0.5f), load1(r, op.in[3], 0.5f), &l);
            if (op.i[0] == 4) {
                multiscatter_aniso_ggx(l, load3(r, op.in[1], Color(0.8f)), r, op.in[6], load1(r, op.in[4], 0.0f), out);
                break;
            }
            push_anisotropic_lobe(out, l, r, op.in[6], load1(r, op.in[4], 0.0f));
            break;
        }
        case Op::Hair: {  // in: weight, colour, offset (radians), roughness U, roughness V, tangent, Cycles' sampler flag (lobes/hair.h)
            float w = load1(r, op.in[0], 1.0f);
            set_tangent(out, r, op.in[5], 0.0f);
            Lobe l = make_lobe(op.i[0] == 1 ? LobeKind::HairTransmission : LobeKind::HairReflection, FresnelMode::None,
                               load3(r, op.in[1], Color(0.8f)) * w, 0.0f, 1.5f, uint8_t(op.i[5]));
            l.alpha = load1(r, op.in[3], 0.1f);
            l.alpha_y = load1(r, op.in[4], 1.0f);
            float offset = -load1(r, op.in[2], 0.0f);  // Cycles' closure tilts by minus the node's Offset
            l.f0 = Color(std::isfinite(offset) ? offset : 0.0f, 0.0f, 0.0f);
            // in[6]: the hair_geometry op's first LCG number, >= 0 only with hair_cycles_sampling (the
            // path's key is set only then): Cycles' biased sampler.
            if (load1(r, op.in[6], -1.0f) >= 0.0f) l.variant = HairReflectionLobe::kCyclesSampler;
            push_lobe(out, l);
            break;
        }
        case Op::PrincipledHair: principled_hair_closure(op, r, out); break;
        case Op::Glass: {
            float w = load1(r, op.in[0], 1.0f);
            set_normal(out, r, op.in[4]);
            float rough = op.i[0] == 0 ? 0.0f : load1(r, op.in[2], 0.0f);
            Color c = load3(r, op.in[1], Color(1.0f));
            if (op.i[0] == 3) {
                multiscatter_glass(c * w, c, rough, load1(r, op.in[3], 1.45f), 0.0f, GlassMultipleLobe::kPerBounce,
                                   uint8_t(op.i[5]), uint8_t(op.i[5] + 1), out);
                break;
            }
            Lobe l = make_lobe(LobeKind::Dielectric, FresnelMode::None, c * w, rough, load1(r, op.in[3], 1.45f),
                               uint8_t(op.i[5]));
            l.variant = op.i[0] == 2 ? kBeckmannDistribution : kGgxDistribution;  // i[0]: 0 sharp, 1 GGX, 2 Beckmann
            push_lobe(out, l);
            break;
        }
        case Op::Transparent:
            out->transparent += vmax(load3(r, op.in[1], Color(1.0f)), zero) * std::max(load1(r, op.in[0], 1.0f), 0.0f);
            break;
        case Op::Emission: {
            Color e = load3(r, op.in[1], Color(1.0f)) * (load1(r, op.in[2], 1.0f) * load1(r, op.in[0], 1.0f));
            if (is_finite(e)) out->emission += vmax(e, zero);
            break;
        }
        case Op::Holdout: out->holdout += Color(std::max(load1(r, op.in[0], 1.0f), 0.0f)); break;
        case Op::Background: {  // the World's Background node: as an Emission
            Color e = load3(r, op.in[1], Color(0.8f)) * (load1(r, op.in[2], 1.0f) * load1(r, op.in[0], 1.0f));
            if (is_finite(e)) out->emission += vmax(e, zero);
            break;
        }
        case Op::Principled: principled(op, r, out); break;
        case Op::Subsurface: {  // in: weight, colour, scale, radius, IOR, anisotropy, normal; i[0] the method
            float w = std::max(load1(r, op.in[0], 1.0f), 0.0f);
            set_normal(out, r, op.in[6]);
            SubsurfaceClosure c;
            c.albedo = vmax(load3(r, op.in[1], Color(0.8f)), zero);
            c.weight = c.albedo * w;
            c.radius = load3(r, op.in[3], Color(1.0f)) * load1(r, op.in[2], 1.0f);
            c.ior = load1(r, op.in[4], 1.4f);
            c.anisotropy = load1(r, op.in[5], 0.0f);
            c.method = SubsurfaceMethod(clampf(float(op.i[0]), 0.0f, 2.0f));
            c.index = uint8_t(op.i[5]);
            push_subsurface(c, out);
            break;
        }
        case Op::Count: break;
    }
}

}  // namespace smis
