#include "scene/scene.h"

#include "scene/light_selection.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "spectral/spectra.h"
#include "scene/embree_ray.h"
#include "scene/environment_light.h"
#include "core/rng.h"

namespace smis {
namespace {

// Embree reports errors through a C callback; exceptions must not cross it, so remember the first one.
void embree_error(void* user, RTCError code, const char* msg) {
    auto* first = static_cast<std::string*>(user);
    if (code != RTC_ERROR_NONE && first->empty()) *first = std::string("Embree error: ") + (msg ? msg : "unknown");
}

inline Vec3 load3(const float* p) { return {p[0], p[1], p[2]}; }

// Embree's own validity test for a ray (RayK::valid(), asserted inside rtcIntersect1/rtcOccluded1):
// every origin and direction component within FLT_LARGE = 1.844e18, tnear in [0, inf], tfar not NaN.
// Rays outside it (a camera or geometry at ~1e19 and beyond, NaN directions from degenerate input)
// abort the process on Embree's assertion (found by fuzz_test) and are undefined behaviour in builds
// without assertions, so the scene answers them itself: nothing is hit, everything is occluded.
constexpr float kEmbreeLarge = 1.844e18f;
inline bool embree_accepts(const Vec3& o, const Vec3& d, float tnear, float tfar) {
    return std::fabs(o.x) <= kEmbreeLarge && std::fabs(o.y) <= kEmbreeLarge && std::fabs(o.z) <= kEmbreeLarge &&
           std::fabs(d.x) <= kEmbreeLarge && std::fabs(d.y) <= kEmbreeLarge && std::fabs(d.z) <= kEmbreeLarge &&
           tnear >= 0.0f && tnear <= kInf && !std::isnan(tfar);
}

// Embree intersects an instanced mesh in its local space, through the inverse transform. A transform
// that is singular in float passed the old `det != 0` test (e.g. a denormal scale: det = -1.4e-45):
// its inverse is infinite or huge, the local rays fail Embree's validity assertion and abort the
// process (found by fuzz_test). Require a finite inverse whose entries stay below 1e12 (no axis
// scaled below ~1e-12), which keeps local rays well inside Embree's limit of 1.8e18.
bool invertible_in_float(const Transform& t) {
    float det = t.determinant3();
    if (!std::isfinite(det) || det == 0.0f) return false;
    Vec3 c0 = t.column(0), c1 = t.column(1), c2 = t.column(2);
    for (const Vec3& r : {cross(c1, c2), cross(c2, c0), cross(c0, c1)}) {  // rows of the inverse x det
        Vec3 inv = r / det;
        if (!is_finite(inv) || std::fabs(inv.x) > 1e12f || std::fabs(inv.y) > 1e12f || std::fabs(inv.z) > 1e12f)
            return false;
    }
    return true;
}

// The inverse of an affine transform already known to be invertible (invertible_in_float).
Transform inverse(const Transform& t) {
    float det = t.determinant3();
    Vec3 c0 = t.column(0), c1 = t.column(1), c2 = t.column(2);
    Vec3 rows[3] = {cross(c1, c2) / det, cross(c2, c0) / det, cross(c0, c1) / det};
    Transform inv;
    Vec3 o = t.column(3);
    for (int r = 0; r < 3; ++r) {
        inv.m[r][0] = rows[r].x, inv.m[r][1] = rows[r].y, inv.m[r][2] = rows[r].z;
        inv.m[r][3] = -dot(rows[r], o);
    }
    return inv;
}

struct WorldFrame {
    Vec3 p, ng, ns;
};
// A hit point and its normals on a moving instance, from its space into the world's at `time`
// (where Embree placed the instance then). Out of line: still instances do not pay for it.
[[gnu::noinline]] WorldFrame moving_to_world(RTCGeometry geometry, float time, Vec3 p, Vec3 ng, Vec3 ns) {
    Transform at;
    rtcGetGeometryTransform(geometry, time, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &at.m[0][0]);
    float sign = at.determinant3() < 0.0f ? -1.0f : 1.0f;
    return {at.point(p), at.normal(ng) * sign, at.normal(ns) * sign};
}

void check_emitter(const std::string& spectrum, float temperature, const std::string& what) {
    spectral::EmitterKind kind;
    if (!spectral::parse_emitter_kind(spectrum, &kind))
        throw std::invalid_argument(what + ": unknown emission spectrum '" + spectrum + "'");
    if (kind == spectral::EmitterKind::Blackbody && !(temperature >= 100.0f && temperature <= 1e6f))
        throw std::invalid_argument(what + ": blackbody temperature must be within 100-1e6 K");
}

// Clear errors for spectral settings the engine does not know (the add-on's enums prevent them).
void validate_spectral(const MaterialSpectral& s, const std::string& name) {
    std::string what = "material '" + name + "'";
    check_emitter(s.emission_spectrum, s.emission_temperature, what);
    if (s.metal != "NONE" && !spectral::find_metal(s.metal))
        throw std::invalid_argument(what + ": unknown metal '" + s.metal + "'");
    spectral::Dispersion d;
    if (s.dispersion == "ABBE") {
        if (!(s.abbe >= 1.0f && s.abbe <= 1000.0f))
            throw std::invalid_argument(what + ": Abbe number must be within 1-1000");
    } else if (s.dispersion != "NONE" && !spectral::Dispersion::sellmeier(s.dispersion, &d)) {
        throw std::invalid_argument(what + ": unknown glass '" + s.dispersion + "'");
    }
}

// A measurement build without some feature (core/features.h) refuses the materials that need it.
void require_features(const Material& m) {
    for (const Lobe& l : m.lobes)
        visit_lobe<false>(l.kind, [&](auto k) {
            using L = decltype(k);
            if (L::kFeature) require_feature(L::kEnabled, (std::string("the ") + L::kName + " lobe").c_str(), L::kFeature);
        });
    if (m.emission_texture) require_feature(kWithTexturedEmission, "textured emission", "textured_emission");
    if (m.cutout()) require_feature(kWithCutouts, "a cut-out (Alpha below 1)", "cutouts");
    if (m.needs_uv() || !m.inputs.empty())
        require_feature(kWithTextures, "an image texture, normal map or Object Info colour", "textures");
}

}  // namespace

Scene::Scene() {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("could not create the Embree device");
    rtcSetDeviceErrorFunction(device_, embree_error, &embree_error_);
    // A default material (neutral grey diffuse) so id 0 is always valid.
    Material grey;
    grey.name = "default grey";
    Lobe diffuse;
    diffuse.weight = Color(0.8f);
    grey.lobes.push_back(diffuse);
    materials_.push_back(grey);
}

Scene::~Scene() {
    for (Instance& inst : instances_)
        if (inst.own) rtcReleaseScene(inst.own);
    for (Mesh& m : meshes_)
        if (m.prototype) rtcReleaseScene(m.prototype);
    if (scene_) rtcReleaseScene(scene_);
    if (device_) rtcReleaseDevice(device_);
}

// Non-finite parameters would poison every pixel that sees the material: clamp them to safe values.
// Throws std::invalid_argument for inconsistent inputs or unknown spectral names.
void Scene::sanitize(Material& material) {
    material.image_closure.reset();
    if (material.program && material.program->is_constant() && !material.program->may_hold_out()) {
        // Every closure input folded: the material is its closure list, as before programs existed.
        ShaderResult res = material.program->eval_constant();
        material.program.reset();
        material.lobes.assign(res.lobes.slot, res.lobes.slot + res.count);
        float keep = transparency_keep(res);
        if (keep > 1e-6f) {
            for (Lobe& l : material.lobes) l.weight *= 1.0f / keep;
            Color t = vmin(vmax(res.transparent, Color(0.0f)), Color(1.0f));
            Color rest = (t - Color(min_component(t))) / keep;
            if (max_component(rest) > 0.0f) {
                Lobe straight;
                straight.kind = LobeKind::Transparent;
                straight.weight = rest;
                material.lobes.push_back(straight);
            }
            material.emission = res.emission / keep;
        } else {
            material.lobes.clear();
            material.emission = Color(0.0f);
        }
        material.alpha *= std::min(keep, 1.0f);
    } else if (material.program) {
        // A normal map would move the hit's shading normal away from the program's.
        if (!material.normal_map) material.image_closure = lower_image_closure(*material.program);
        material.lobes = material.program->lobe_templates();
        material.inputs.clear();
        material.emission = Color(0.0f);
    }
    for (Lobe& l : material.lobes) {
        if (!is_finite(l.weight)) l.weight = Color(0.0f);
        l.weight = vmax(l.weight, Color(0.0f));
        if (!is_finite(l.f0)) l.f0 = Color(1.0f);
        l.f0 = vmin(vmax(l.f0, Color(0.0f)), Color(1.0f));
        l.alpha = std::isfinite(l.alpha) ? clampf(l.alpha, 0.0f, 1.0f) : 1.0f;
        l.eta = (std::isfinite(l.eta) && l.eta > 0.0f) ? l.eta : 1.5f;
        l.kind_colour = is_finite(l.kind_colour) ? vmax(l.kind_colour, Color(0.0f)) : Color(0.0f);
    }
    for (size_t i = 0; i < material.lobes.size(); ++i) material.lobes[i].index = static_cast<uint8_t>(i);
    validate_spectral(material.spectral, material.name);
    if (!material.inputs.empty() && material.inputs.size() != material.lobes.size())
        throw std::invalid_argument("material inputs must be empty or one per lobe");
    if (!std::isfinite(material.normal_strength)) material.normal_strength = 0.0f;
    material.alpha = std::isfinite(material.alpha) ? clampf(material.alpha, 0.0f, 1.0f) : 1.0f;
    if (!is_finite(material.emission)) material.emission = Color(0.0f);
    material.emission = vmax(material.emission, Color(0.0f));
    require_features(material);
    material.prepare();
}

namespace {
// A material with a BSSRDF closure (for programs, their lobe templates).
bool uses_subsurface(const Material& m) {
    for (const Lobe& l : m.lobes)
        if (l.kind == LobeKind::Subsurface) return true;
    return false;
}
}  // namespace

uint32_t Scene::add_material(Material material) {
    if (committed_) throw std::logic_error("scene already committed");
    sanitize(material);
    has_subsurface_ = has_subsurface_ || uses_subsurface(material);
    varying_materials_ = varying_materials_ || !material.inputs.empty() || material.program;
    programs_ = programs_ || material.program;
    // A Holdout closure cuts the film like a holdout object (the film keeps transparency).
    has_holdout_ = has_holdout_ || (material.program && material.program->may_hold_out());
    materials_.push_back(std::move(material));
    return static_cast<uint32_t>(materials_.size() - 1);
}

bool Scene::replace_material(uint32_t id, Material material) {
    if (!committed_ || !fast_build_ || id >= materials_.size()) return false;
    sanitize(material);
    const Material& old = materials_[id];
    // What commit() baked into the geometry and the light tables must not change: cut-out filters
    // are registered per mesh, emissive triangles and media are found at commit.
    auto has_volume = [](const Material& m) { return m.medium >= 0 || m.pass_through; };
    if (old.cutout() != material.cutout() || old.emissive() != material.emissive() || has_volume(old) ||
        has_volume(material) || uses_subsurface(old) != uses_subsurface(material))
        return false;
    bool emissive = material.emissive();
    materials_[id] = std::move(material);
    varying_materials_ = varying_materials_ || !materials_[id].inputs.empty() || materials_[id].program;
    programs_ = programs_ || materials_[id].program;
    hit_ids_ = (kWithTextures && programs_) || has_subsurface_;
    has_holdout_ = has_holdout_ || (materials_[id].program && materials_[id].program->may_hold_out());
    update_skipped();
    if (emissive) rebuild_lights();  // the triangle lights carry the emission
    else update_spectral_content();
    return true;
}

uint32_t Scene::add_mesh(const float* vertices, size_t nv, const int32_t* triangles, size_t nt,
                         const float* corner_normals, const int32_t* material_index,
                         const std::vector<uint32_t>& slot_materials, const float* corner_uvs,
                         const std::vector<AttributeInput>& attributes) {
    if (committed_) throw std::logic_error("scene already committed");
    Mesh mesh = make_mesh(vertices, nv, triangles, nt, corner_normals, material_index, slot_materials, corner_uvs);
    attach_attributes(mesh, attributes);
    stats_.dropped_triangles += mesh.dropped;
    meshes_.push_back(std::move(mesh));
    return static_cast<uint32_t>(meshes_.size() - 1);
}

Scene::Mesh Scene::make_mesh(const float* vertices, size_t nv, const int32_t* triangles, size_t nt,
                             const float* corner_normals, const int32_t* material_index,
                             const std::vector<uint32_t>& slot_materials, const float* corner_uvs) const {
    Mesh mesh;
    mesh.input_triangles = nt;
    // Embree reads 16 bytes past the last vertex of shared buffers: keep one float3 of padding.
    mesh.positions.assign(vertices, vertices + 3 * nv);
    mesh.positions.resize(3 * nv + 4, 0.0f);
    mesh.indices.reserve(3 * nt);
    if (corner_normals) mesh.corner_normals.reserve(3 * nt);
    mesh.materials.reserve(nt);
    for (size_t t = 0; t < nt; ++t) {
        int32_t i0 = triangles[3 * t], i1 = triangles[3 * t + 1], i2 = triangles[3 * t + 2];
        bool in_range = i0 >= 0 && i1 >= 0 && i2 >= 0 && size_t(i0) < nv && size_t(i1) < nv && size_t(i2) < nv;
        bool ok = in_range;
        if (ok) {
            Vec3 a = load3(vertices + 3 * i0), b = load3(vertices + 3 * i1), c = load3(vertices + 3 * i2);
            Vec3 n = cross(b - a, c - a);
            float len2 = length_sq(n);
            ok = is_finite(a) && is_finite(b) && is_finite(c) && std::isfinite(len2) && len2 > 0.0f;
        }
        if (!ok) {
            ++mesh.dropped;
            continue;
        }
        mesh.indices.insert(mesh.indices.end(), {uint32_t(i0), uint32_t(i1), uint32_t(i2)});
        mesh.kept.push_back(uint32_t(t));
        if (corner_normals)
            for (int k = 0; k < 3; ++k) mesh.corner_normals.push_back(load3(corner_normals + 9 * t + 3 * k));
        if (corner_uvs)
            for (int k = 0; k < 3; ++k) {
                Point2 uv{corner_uvs[6 * t + 2 * k], corner_uvs[6 * t + 2 * k + 1]};
                mesh.uvs.push_back(std::isfinite(uv.x) && std::isfinite(uv.y) ? uv : Point2{});
            }
        uint32_t mat = 0;
        if (material_index) {
            int32_t slot = material_index[t];
            if (slot >= 0 && size_t(slot) < slot_materials.size()) mat = slot_materials[slot];
        } else if (!slot_materials.empty()) {
            mat = slot_materials[0];
        }
        mesh.materials.push_back(mat < materials_.size() ? mat : 0);
    }
    return mesh;
}

bool Scene::emissive(const Mesh& mesh) const {
    for (uint32_t m : mesh.materials)
        if (materials_[m].emissive()) return true;
    return false;
}

void Scene::build_prototype(Mesh& mesh) {
    mesh.prototype = rtcNewScene(device_);
    rtcSetSceneFlags(mesh.prototype, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(mesh.prototype, build_quality());
    build_mesh_geometry(mesh.prototype, mesh, 0);
    rtcCommitScene(mesh.prototype);
}

bool Scene::set_instance_transforms(const float* rows, size_t n) {
    // Subsurface objects' own scenes would keep the old transforms: a new scene is built.
    if (!committed_ || !fast_build_ || n != instances_.size() || has_subsurface_) return false;
    std::vector<Transform> transforms(n);
    for (size_t i = 0; i < n; ++i) {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) transforms[i].m[r][c] = rows[12 * i + 4 * r + c];
        if (instances_[i].light_base >= 0 || !transforms[i].is_finite() || !invertible_in_float(transforms[i]))
            return false;  // triangle lights are in world space; bad matrices are refused as in add_instance
    }
    for (size_t i = 0; i < n; ++i) {
        instances_[i].to_world = transforms[i];
        RTCGeometry geom = rtcGetGeometry(scene_, static_cast<unsigned>(i));  // geometry id = instance index
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &transforms[i].m[0][0]);
        rtcCommitGeometry(geom);
    }
    rtcCommitScene(scene_);  // rebuilds the top level only
    update_camera_bounds_test();
    update_boundary_planes();
    return embree_error_.empty();
}

bool Scene::replace_mesh(uint32_t id, const float* vertices, size_t nv, const int32_t* triangles, size_t nt,
                         const float* corner_normals, const int32_t* material_index,
                         const std::vector<uint32_t>& slot_materials, const float* corner_uvs,
                         const std::vector<AttributeInput>& attributes) {
    if (!committed_ || !fast_build_ || id >= meshes_.size() || !meshes_[id].prototype || has_subsurface_) return false;
    Mesh mesh = make_mesh(vertices, nv, triangles, nt, corner_normals, material_index, slot_materials, corner_uvs);
    attach_attributes(mesh, attributes);
    mesh.texspace_location = meshes_[id].texspace_location;
    mesh.texspace_size = meshes_[id].texspace_size;
    if (mesh.indices.empty() || emissive(mesh) || emissive(meshes_[id])) return false;
    mesh.users = meshes_[id].users;
    build_prototype(mesh);
    for (size_t i = 0; i < instances_.size(); ++i) {
        if (instances_[i].mesh != id) continue;
        RTCGeometry geom = rtcGetGeometry(scene_, static_cast<unsigned>(i));
        rtcSetGeometryInstancedScene(geom, mesh.prototype);
        rtcSetGeometryMask(geom, geometry_mask(mesh, instances_[i].visibility));  // its materials may differ
        rtcCommitGeometry(geom);
    }
    rtcReleaseScene(meshes_[id].prototype);
    stats_.triangles += (mesh.indices.size() / 3 - meshes_[id].indices.size() / 3) * mesh.users;
    meshes_[id] = std::move(mesh);
    rtcCommitScene(scene_);
    update_camera_bounds_test();
    update_boundary_planes();
    return embree_error_.empty();
}

void Scene::set_mesh_motion(uint32_t id, const float* positions, size_t steps, size_t nv, const float* corner_normals,
                            size_t nt) {
    if (committed_) throw std::logic_error("scene already committed");
    if (id >= meshes_.size()) throw std::invalid_argument("motion of an unknown mesh");
    Mesh& mesh = meshes_[id];
    const size_t mesh_nv = (mesh.positions.size() - 4) / 3;
    if (nv != mesh_nv)
        throw std::invalid_argument("mesh motion has " + std::to_string(nv) + " vertices, the mesh " +
                                    std::to_string(mesh_nv) + " (its topology changes over the shutter)");
    if (steps < 2) throw std::invalid_argument("mesh motion needs at least two steps");
    const size_t n = steps * 3 * nv;
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(positions[i])) throw std::invalid_argument("mesh motion vertices are not finite");
    if (corner_normals && nt != mesh.input_triangles)
        throw std::invalid_argument("mesh motion normals have " + std::to_string(nt) + " triangles, the mesh " +
                                    std::to_string(mesh.input_triangles));
    if (std::equal(positions + 3 * nv, positions + n, positions, positions + n - 3 * nv) &&
        std::equal(positions, positions + 3 * nv, positions + (steps - 1) * 3 * nv))
        return;  // every step the same vertices: nothing moves
    mesh.motion_positions.assign(positions, positions + n);
    mesh.motion_positions.resize(n + 4, 0.0f);  // Embree's padding after the last step
    mesh.motion_normals.clear();
    if (corner_normals && !mesh.corner_normals.empty()) {
        const size_t stride = 9 * nt;  // the normals of the triangles make_mesh kept
        mesh.motion_normals.reserve(steps * mesh.corner_normals.size());
        for (size_t k = 0; k < steps; ++k)
            for (size_t i = 0; i < mesh.materials.size(); ++i)
                for (int c = 0; c < 3; ++c) {
                    const size_t t = mesh.kept.empty() ? i : mesh.kept[i];
                    Vec3 nrm = load3(corner_normals + k * stride + 9 * t + 3 * c);
                    mesh.motion_normals.push_back(is_finite(nrm) ? nrm : Vec3(0.0f));
                }
    }
    mesh.motion_steps = static_cast<uint32_t>(steps);
}

void Scene::attach_attributes(Mesh& mesh, const std::vector<AttributeInput>& attributes) {
    for (const AttributeInput& a : attributes)
        if (!a.corners || a.dims < 1 || a.dims > 4) throw std::invalid_argument("mesh attribute '" + a.name + "' is malformed");
    for (const AttributeInput& a : attributes) {
        MeshAttribute attr{attribute_id(a.name), a.dims, {}};
        attr.corners.reserve(mesh.indices.size() * a.dims);
        for (uint32_t t : mesh.kept)
            for (int k = 0; k < 3 * a.dims; ++k) {
                float v = a.corners[size_t(t) * 3 * a.dims + k];
                attr.corners.push_back(std::isfinite(v) ? v : 0.0f);
            }
        mesh.attributes.push_back(std::move(attr));
    }
    // Kept for set_mesh_motion's normals only where triangles were dropped (else it is 0, 1, 2, ...).
    if (mesh.dropped == 0) {
        mesh.kept.clear();
        mesh.kept.shrink_to_fit();
    }
}

void Scene::set_mesh_texspace(uint32_t mesh, const Vec3& location, const Vec3& size) {
    if (mesh >= meshes_.size()) throw std::invalid_argument("unknown mesh");
    if (!is_finite(location) || !is_finite(size)) return;
    meshes_[mesh].texspace_location = location;
    meshes_[mesh].texspace_size = size;
}

int32_t Scene::attribute_id(const std::string& name) {
    for (size_t i = 0; i < attribute_names_.size(); ++i)
        if (attribute_names_[i] == name) return int32_t(i);
    attribute_names_.push_back(name);
    return int32_t(attribute_names_.size() - 1);
}

uint32_t Scene::mesh_dropped(uint32_t mesh) const { return mesh < meshes_.size() ? meshes_[mesh].dropped : 0; }

uint32_t Scene::add_texture(std::shared_ptr<const Texture> texture) {
    // Viewport scenes take new textures after commit, for materials replaced in place.
    if (committed_ && !fast_build_) throw std::logic_error("scene already committed");
    if (!texture) throw std::invalid_argument("null texture");
    textures_.push_back(std::move(texture));
    return static_cast<uint32_t>(textures_.size() - 1);
}

std::shared_ptr<const Texture> Scene::texture(uint32_t id) const {
    if (id >= textures_.size()) throw std::invalid_argument("unknown texture id");
    return textures_[id];
}

void Scene::add_instance(uint32_t mesh, const Transform& to_world, const Color& object_color, float random,
                         float pass_index, float object_alpha, bool holdout, uint32_t visibility,
                         const std::vector<Transform>& motion) {
    if (committed_) throw std::logic_error("scene already committed");
    if (mesh >= meshes_.size()) throw std::invalid_argument("instance of an unknown mesh");
    if (!to_world.is_finite() || !invertible_in_float(to_world))
        throw std::invalid_argument("instance transform is not finite or is singular");
    if (motion.size() == 1) throw std::invalid_argument("instance motion needs at least two steps");
    bool moves = false;
    for (const Transform& t : motion) {
        if (!t.is_finite() || !invertible_in_float(t))
            throw std::invalid_argument("instance motion transform is not finite or is singular");
        moves = moves || std::memcmp(&t, &motion[0], sizeof(Transform)) != 0;
    }
    if (meshes_[mesh].indices.empty()) return;
    Instance inst;
    inst.mesh = mesh;
    inst.to_world = to_world;
    inst.identity = false;
    inst.light_base = -1;
    inst.object_color = is_finite(object_color) ? vmax(object_color, Color(0.0f)) : Color(1.0f);
    inst.to_object = inverse(to_world);
    inst.random = std::isfinite(random) ? random : 0.0f;
    inst.pass_index = std::isfinite(pass_index) ? pass_index : 0.0f;
    inst.alpha = std::isfinite(object_alpha) ? object_alpha : 1.0f;
    inst.holdout = holdout;
    inst.visibility = visibility;
    hidden_objects_ = hidden_objects_ || visibility != kRayAllVisibility;
    has_holdout_ = has_holdout_ || holdout;
    if (moves) inst.motion = motion;
    instances_.push_back(inst);
    meshes_[mesh].users++;
}

uint32_t Scene::add_light(const LightDesc& desc) {
    if (committed_) throw std::logic_error("scene already committed");
    check_emitter(desc.spectrum, desc.temperature, "light");
    lights_.push_back(make_light(desc));
    emitter_sources_.push_back({desc.spectrum, desc.temperature, desc.color});
    light_descs_.push_back(desc);
    return static_cast<uint32_t>(lights_.size() - 1);
}

bool Scene::replace_lights(const std::vector<LightDesc>& descs, const Color& world) {
    WorldDesc w;
    w.radiance = world;
    return replace_lights(descs, w);
}

bool Scene::replace_lights(const std::vector<LightDesc>& descs, const WorldDesc& world) {
    if (!committed_ || !fast_build_ || world_medium_ >= 0) return false;
    for (const LightDesc& d : descs) {  // every light checked before anything changes
        check_emitter(d.spectrum, d.temperature, "light");
        make_light(d);
    }
    light_descs_ = descs;
    set_world(world);
    rebuild_lights();
    return true;
}

// The light table in commit()'s order: the lamps, each instance's emissive triangles (whose
// indices SurfaceHit::light refers to), the world; then the selection (scene/light_selection.h).
void Scene::rebuild_lights() {
    lights_.clear();
    emitter_sources_.clear();
    for (const LightDesc& d : light_descs_) {
        lights_.push_back(make_light(d));
        emitter_sources_.push_back({d.spectrum, d.temperature, d.color});
    }
    stats_.emissive_triangles = 0;
    for (Instance& inst : instances_)
        if (!emissive_local_[inst.mesh].empty()) add_triangle_lights(inst);
    finish_lights();
}

void Scene::update_spectral_content() {
    spectral_content_ = false;
    for (const EmitterSource& e : emitter_sources_) spectral_content_ |= e.spectrum != "RGB";
    for (const Material& m : materials_) spectral_content_ |= m.spectral.has_spectral_content();
}

void Scene::finish_lights() {
    if (world_desc_.program) {
        // A World that varies over directions; viewport scenes keep the map small (it is rebuilt
        // on every world edit).
        int w = world_desc_.map_width, h = world_desc_.map_height;
        if (fast_build_ && (w <= 0 || w > 1024 || h <= 0 || h > 512)) w = 1024, h = 512;
        auto env = std::make_unique<EnvironmentLight>(world_desc_.program, this, w, h, world_desc_.sample_sun);
        env->visible_to_camera = world_desc_.visible_to_camera;
        env->visibility = world_desc_.visibility;
        emitter_sources_.push_back({"RGB", 6500.0f, env->average()});
        lights_.push_back(std::move(env));
    } else if (max_component(world_) > 0.0f) {
        lights_.push_back(std::make_unique<WorldLight>(world_));
        lights_.back()->visible_to_camera = world_desc_.visible_to_camera;
        lights_.back()->visibility = world_desc_.visibility;
        emitter_sources_.push_back({"RGB", 6500.0f, world_});
    }
    update_spectral_content();
    std::vector<float> power;
    infinite_lights_.clear();
    hittable_lights_.clear();
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        const Light& l = *lights_[i];
        power.push_back(l.power(radius_));
        if (l.at_infinity()) infinite_lights_.push_back(i);
        else if (!l.is_delta() && !dynamic_cast<const TriangleLight*>(&l)) hittable_lights_.push_back(i);
    }
    // Each instance's emissive triangles are one emitter (named by its first light), every other
    // light its own.
    std::vector<int32_t> bases;
    for (const Instance& inst : instances_)
        if (inst.light_base >= 0) bases.push_back(inst.light_base);
    std::sort(bases.begin(), bases.end());
    std::vector<uint32_t> emitter(lights_.size());
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        auto base = std::upper_bound(bases.begin(), bases.end(), int32_t(i));
        const bool triangle = base != bases.begin() && dynamic_cast<const TriangleLight*>(lights_[i].get());
        emitter[i] = triangle ? uint32_t(*(base - 1)) : i;
        // A sun or world lights the whole scene: no uniform share (kNoEmitter); Cycles' clamped
        // images under a sun match ours only so (test_ray_visibility.py's clamp cases).
        if (lights_[i]->at_infinity()) emitter[i] = kNoEmitter;
    }
    light_powers_ = power;
    light_emitters_ = std::move(emitter);
    build_light_selection();
    light_power_ = DiscreteDistribution(power);
    // Media choose per segment (media_light_choice.h), with their own defensive floor.
    media_lights_ = MediaLightChoice(lights_, light_power_);
    find_glow_lights(light_powers_);
    hidden_lights_ = false;
    for (const auto& l : lights_)
        hidden_lights_ = hidden_lights_ || l->visibility != kRayAllVisibility || !l->visible_to_camera || !l->use_mis;
    stats_.lights = lights_.size();
    // sample_direct() returns at once on an empty light table: no shadow rays at all.
    set_skipped("NEE (no lights)", lights_.empty());
}

void Scene::find_glow_lights(const std::vector<float>& power) {
    glow_lights_.clear();
    if (!has_media()) return;
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        const Light& l = *lights_[i];
        LightPoint p;
        if (!l.point(&p) || !(l.visibility & kRayVolumeScatter) || !(power[i] > 0.0f)) continue;
        const int32_t m = medium_at(p.position);
        if (m >= 0 && media_[m].scatters()) glow_lights_.push_back({i, p.position, power[i], m});
    }
    std::stable_sort(glow_lights_.begin(), glow_lights_.end(),
                     [](const GlowLight& a, const GlowLight& b) { return a.power > b.power; });
    if (glow_lights_.size() > size_t(kMaxGlowLights)) glow_lights_.resize(kMaxGlowLights);
}

void Scene::set_light_selection(LightSelection selection) {
    light_selection_mode_ = selection;
    if (committed_) build_light_selection();
}

void Scene::build_light_selection() {
    if (light_selection_mode_ == LightSelection::Defensive) {
        light_selection_ = DiscreteDistribution(defensive_light_weights(light_powers_, light_emitters_));
        return;
    }
    // Cycles 3.4: a World of one colour is not sampled (LightManager::test_enabled_lights disables
    // background MIS without spatial variation), a World program is its background light; lamps
    // without strength are disabled (Light::has_contribution); triangles go by area.
    std::vector<CyclesLightRole> role(lights_.size(), CyclesLightRole::NotSampled);
    std::vector<float> area(lights_.size(), 0.0f);
    for (uint32_t i = 0; i < lights_.size(); ++i) {
        const Light& l = *lights_[i];
        if (auto* tri = dynamic_cast<const TriangleLight*>(&l)) {
            role[i] = CyclesLightRole::Triangle;
            area[i] = tri->area();
        } else if (!dynamic_cast<const WorldLight*>(&l) && light_powers_[i] > 0.0f) {
            role[i] = CyclesLightRole::Lamp;
        }
    }
    light_selection_ = DiscreteDistribution(cycles_light_weights(role, area));
}

void Scene::set_skipped(const char* what, bool skipped) {
    skipped_.erase(std::remove(skipped_.begin(), skipped_.end(), what), skipped_.end());
    if (skipped) skipped_.push_back(what);
}

// Constant materials build their lobes once (Material::prepare) and hits on meshes without UVs
// interpolate none; only meshes with a cut-out material run the Embree filter; a pinhole camera
// samples no lens.
void Scene::update_skipped() {
    bool textures = false, cutouts = false;
    for (const Material& m : materials_) {
        textures = textures || m.needs_uv() || !m.inputs.empty();
        cutouts = cutouts || m.cutout();
    }
    set_skipped("textures", !textures);
    set_skipped("cut-outs", !cutouts);
    set_skipped("depth of field", !camera_.has_aperture());
}

void Scene::set_world(const Color& radiance) {
    world_ = is_finite(radiance) ? vmax(radiance, Color(0.0f)) : Color(0.0f);
    world_desc_ = WorldDesc{};
    world_desc_.radiance = world_;
}

void Scene::set_world(const WorldDesc& world) {
    set_world(world.radiance);
    world_desc_ = world;
    if (world.program && world.program->is_constant()) {
        // Folded to a constant (a Background with unlinked inputs, an RGB node, ...): the cheap
        // uniform light, as Cycles disables its background map for a world without variation.
        set_world(world.program->eval_constant().emission);
        world_desc_.visible_to_camera = world.visible_to_camera;
        world_desc_.visibility = world.visibility;
    }
}

int32_t Scene::add_medium(const Medium& medium) {
    if (committed_) throw std::logic_error("scene already committed");
    auto usable = [](const Color& c) { return is_finite(c) && min_component(c) >= 0.0f; };
    if (!usable(medium.sigma_a) || !usable(medium.sigma_s) || !std::isfinite(medium.phase.g()))
        throw std::invalid_argument("medium coefficients must be finite and non-negative");
    media_.push_back(medium);
    return static_cast<int32_t>(media_.size() - 1);
}

void Scene::set_world_medium(int32_t medium) {
    if (medium >= static_cast<int32_t>(media_.size())) throw std::invalid_argument("unknown world medium");
    world_medium_ = medium < 0 ? -1 : medium;
}

int32_t Scene::medium_at(const Vec3& p) const {
    // The first boundary of a volume object met by a ray out of p tells whether p is inside it.
    Ray ray{p, normalize(Vec3(0.2113f, 0.3877f, 0.8971f)), 0.0f, kInf};
    for (int i = 0; i < 256; ++i) {
        SurfaceHit hit;
        if (!intersect(ray, &hit)) break;
        const Material& m = materials_[hit.material];
        if (m.medium >= 0 || m.pass_through) return dot(ray.d, hit.ng) > 0.0f ? m.medium : world_medium_;
        ray.o = offset_ray_origin(hit.p, dot(ray.d, hit.ng) > 0.0f ? hit.ng : -hit.ng);
    }
    return world_medium_;
}

void Scene::set_camera(const CameraDesc& desc) {
    camera_ = Camera(desc);
    has_camera_ = true;
    if (committed_) update_camera_bounds_test();  // a viewport camera moved
}

void Scene::build_mesh_geometry(RTCScene target, Mesh& mesh, unsigned id, uint32_t visibility) {
    if (mesh.curves) return build_curve_geometry(target, mesh, id, visibility);
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryMask(geom, visibility);
    size_t nv = (mesh.positions.size() - 4) / 3, nt = mesh.indices.size() / 3;
    if (mesh.motion_steps == 0) {
        rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, mesh.positions.data(), 0,
                                   3 * sizeof(float), nv);
    } else {
        // Deformation motion blur: one vertex buffer per step; Embree interpolates them linearly in
        // the ray's time, as Cycles interpolates its motion triangles.
        rtcSetGeometryTimeStepCount(geom, mesh.motion_steps);
        for (unsigned k = 0; k < mesh.motion_steps; ++k)
            rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, mesh.motion_positions.data(),
                                       k * 3 * nv * sizeof(float), 3 * sizeof(float), nv);
    }
    rtcSetSharedGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.indices.data(), 0,
                               3 * sizeof(uint32_t), nt);
    bool cutout = false;
    for (uint32_t m : mesh.materials) cutout = cutout || materials_[m].cutout();
    if (kWithCutouts && cutout) {  // only meshes with cut-out materials pay for the filter calls
        mesh.owner = this;
        rtcSetGeometryUserData(geom, &mesh);
        rtcSetGeometryIntersectFilterFunction(geom, cutout_filter);
        rtcSetGeometryOccludedFilterFunction(geom, cutout_filter);
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(target, geom, id);
    rtcReleaseGeometry(geom);
}

// Alpha cut-outs: a hit on a surface of alpha a is kept with probability a, chosen by a hash of
// the ray and the triangle. Different rays decide independently, so camera, bounce and shadow rays
// see the surface with frequency a (Cycles' stochastic transparency, in expectation), while the
// same ray always decides the same way: images stay identical for any thread count. A hit the
// filter rejects is simply not there; the ray goes on to the next surface.
void Scene::cutout_filter(const RTCFilterFunctionNArguments* args) {
    const Mesh& mesh = *static_cast<const Mesh*>(args->geometryUserPtr);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const Material& mat = mesh.owner->materials_[mesh.materials[prim]];
        if (!mat.cutout()) continue;
        Point2 uv;
        if (!mesh.uvs.empty()) {
            float u = RTCHitN_u(args->hit, args->N, i), v = RTCHitN_v(args->hit, args->N, i), w = 1.0f - u - v;
            const Point2* t = &mesh.uvs[3 * prim];
            uv = {t[0].x * w + t[1].x * u + t[2].x * v, t[0].y * w + t[1].y * u + t[2].y * v};
        }
        float alpha;
        if (mat.program) {
            unsigned top = RTCHitN_instID(args->hit, args->N, i, 0);
            if (top == RTC_INVALID_GEOMETRY_ID) top = RTCHitN_geomID(args->hit, args->N, i);
            Vec3 dir(RTCRayN_dir_x(const_cast<RTCRayN*>(args->ray), args->N, i),
                     RTCRayN_dir_y(const_cast<RTCRayN*>(args->ray), args->N, i),
                     RTCRayN_dir_z(const_cast<RTCRayN*>(args->ray), args->N, i));
            alpha = mesh.owner->program_keep(mesh.owner->geom_to_instance_[top], prim, RTCHitN_u(args->hit, args->N, i),
                                             RTCHitN_v(args->hit, args->N, i), dir);
        } else {
            alpha = mat.alpha_at(uv);
        }
        if (alpha >= 1.0f) continue;
        auto bits = [](float f) { uint32_t b; std::memcpy(&b, &f, 4); return uint64_t(b); };
        const RTCRayN* r = args->ray;
        unsigned n = args->N;
        uint64_t h = mix64(bits(RTCRayN_org_x(const_cast<RTCRayN*>(r), n, i)) << 32 |
                           bits(RTCRayN_org_y(const_cast<RTCRayN*>(r), n, i)));
        h = mix64(h ^ (bits(RTCRayN_org_z(const_cast<RTCRayN*>(r), n, i)) << 32 |
                       bits(RTCRayN_dir_x(const_cast<RTCRayN*>(r), n, i))));
        h = mix64(h ^ (bits(RTCRayN_dir_y(const_cast<RTCRayN*>(r), n, i)) << 32 |
                       bits(RTCRayN_dir_z(const_cast<RTCRayN*>(r), n, i))));
        h = mix64(h ^ (uint64_t(prim) << 32 | RTCHitN_instID(args->hit, n, i, 0)));
        float u01 = static_cast<float>(h >> 40) * 0x1p-24f;
        if (!(u01 < alpha)) args->valid[i] = 0;
    }
}

void Scene::add_triangle_lights(Instance& inst) {
    const Mesh& mesh = meshes_[inst.mesh];
    const std::vector<int32_t>& local = emissive_local_[inst.mesh];
    inst.light_base = static_cast<int32_t>(lights_.size());
    for (size_t t = 0; t < local.size(); ++t) {
        if (local[t] < 0) continue;
        Vec3 v[3];
        for (int k = 0; k < 3; ++k) {
            Vec3 p = load3(&mesh.positions[3 * mesh.indices[3 * t + k]]);
            v[k] = inst.identity ? p : inst.to_world.point(p);
        }
        const Material& mat = materials_[mesh.materials[t]];
        // A cut-out emitter is there with probability alpha for the rays that hit it; a light sample
        // on it must see it with the same probability (the constant part of alpha; an alpha
        // texture is not looked up here).
        auto light = std::make_unique<TriangleLight>(v[0], v[1], v[2], mat.emission * mat.alpha);
        if (mat.emission_texture) light->set_texture(mat.emission_texture.get(), mesh.uvs.empty() ? nullptr : &mesh.uvs[3 * t]);
        Color source = mat.emission;
        const uint32_t inst_id = uint32_t(&inst - instances_.data());
        if (mat.program) {
            Vec3 n = cross(v[1] - v[0], v[2] - v[0]);
            Color centroid = emission(inst_id, uint32_t(t), mesh.materials[t], 1.0f / 3.0f, 1.0f / 3.0f, n);
            light = std::make_unique<TriangleLight>(v[0], v[1], v[2], Color(1.0f));
            light->set_shader(this, inst_id, uint32_t(t), mesh.materials[t], centroid);
            source = centroid;
        }
        light->visibility = inst.visibility;
        if (!inst.motion.empty() || mesh.motion_steps != 0) light->set_motion(this, inst_id, uint32_t(t));
        lights_.push_back(std::move(light));
        emitter_sources_.push_back({mat.spectral.emission_spectrum, mat.spectral.emission_temperature, source});
        stats_.emissive_triangles++;
    }
}

uint32_t Scene::geometry_mask(const Mesh& mesh, uint32_t visibility) const {
    bool surface = false;
    for (uint32_t m : mesh.materials) surface = surface || !materials_[m].pass_through;
    const uint32_t rest = visibility & ~uint32_t(kRayShadowSurface);
    return surface && (visibility & kRayShadow) ? rest | kRayShadowSurface : rest;
}

void Scene::update_boundary_planes() {
    RTCBounds b;
    rtcGetSceneBounds(scene_, &b);
    float extent = 0.0f;
    for (float c : {b.lower_x, b.lower_y, b.lower_z, b.upper_x, b.upper_y, b.upper_z})
        extent = std::max(extent, std::fabs(c));
    boundary_planes_.reset(instances_.empty() ? 1.0f : extent);
    for (const Instance& inst : instances_) {
        const Mesh& mesh = meshes_[inst.mesh];
        if (mesh.curves || !(inst.visibility & kRayShadow)) continue;  // shadow rays do not see them
        for (size_t t = 0; t < mesh.materials.size(); ++t) {
            if (!materials_[mesh.materials[t]].pass_through) continue;
            if (!inst.motion.empty() || mesh.motion_steps != 0) return boundary_planes_.disable();
            Vec3 v[3];
            for (int k = 0; k < 3; ++k) {
                const Vec3 p = load3(&mesh.positions[3 * mesh.indices[3 * t + k]]);
                v[k] = inst.identity ? p : inst.to_world.point(p);
            }
            boundary_planes_.add_triangle(v[0], v[1], v[2]);
        }
    }
}

void Scene::attach_instance_geometry(RTCScene target, Instance& inst, unsigned geom_id, bool own) {
    Mesh& mesh = meshes_[inst.mesh];
    if (!mesh.prototype) {
        build_mesh_geometry(target, mesh, geom_id, own ? kRayAllVisibility : geometry_mask(mesh, inst.visibility));
        return;
    }
    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(geom, mesh.prototype);
    if (inst.motion.empty()) {
        rtcSetGeometryTransform(geom, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &inst.to_world.m[0][0]);
    } else {
        // Quaternion steps, so Embree interpolates rotations as Cycles does (scene/motion.h).
        std::vector<DecomposedTransform> steps = decompose_motion(inst.motion);
        rtcSetGeometryTimeStepCount(geom, static_cast<unsigned>(steps.size()));
        for (size_t k = 0; k < steps.size(); ++k) {
            RTCQuaternionDecomposition q = embree_decomposition(steps[k]);
            rtcSetGeometryTransformQuaternion(geom, static_cast<unsigned>(k), &q);
        }
        if (!own) {
            inst.geometry = geom;  // the scene keeps it alive
            has_motion_ = true;
        }
    }
    rtcSetGeometryMask(geom, own ? kRayAllVisibility : geometry_mask(mesh, inst.visibility));
    rtcCommitGeometry(geom);
    rtcAttachGeometryByID(target, geom, geom_id);
    rtcReleaseGeometry(geom);
    if (!own) stats_.embree_instances++;
}

void Scene::commit() {
    if (committed_) return;
    if (!has_camera_) throw std::invalid_argument("scene has no camera");
    scene_ = rtcNewScene(device_);
    // ROBUST: watertight traversal, so rays do not leak through edges shared by two triangles.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene_, build_quality());

    // Meshes used once are flattened into world space (one BVH level, as Cycles does for unique
    // objects); meshes used several times become one Embree prototype shared by Embree instances.
    // Fast-build (viewport) scenes keep every used mesh a prototype, for in-place updates.
    // A moving instance is an Embree motion instance, so its mesh is a prototype even when used once.
    std::vector<char> moving_user(meshes_.size(), 0);
    for (const Instance& inst : instances_) moving_user[inst.mesh] |= !inst.motion.empty();
    for (size_t m = 0; m < meshes_.size(); ++m)
        if (meshes_[m].users >= (fast_build_ ? 1u : 2u) || moving_user[m]) build_prototype(meshes_[m]);
    emissive_local_.assign(meshes_.size(), {});
    for (size_t m = 0; m < meshes_.size(); ++m) {
        const Mesh& mesh = meshes_[m];
        std::vector<int32_t>& local = emissive_local_[m];
        int32_t count = 0;
        if (mesh.curves) continue;  // hair is not a light (Cycles does not sample emissive curves either)
        for (uint32_t mat : mesh.materials) local.push_back(materials_[mat].emissive() ? count++ : -1);
        if (count == 0) local.clear();
    }
    Vec3 lo(kInf), hi(-kInf);
    // Materials whose volume scatters: their triangles bound the scattering region.
    std::vector<char> scattering_volume(materials_.size(), 0);
    bool any_scattering_volume = false;
    for (size_t m = 0; m < materials_.size(); ++m) {
        const int32_t medium = materials_[m].medium;
        scattering_volume[m] = medium >= 0 && media_[medium].scatters();
        any_scattering_volume = any_scattering_volume || scattering_volume[m];
    }
    scattering_ = ScatteringRegion{};
    scattering_.everywhere = world_medium_ >= 0 && media_[world_medium_].scatters();
    for (Instance& inst : instances_) {
        Mesh& mesh = meshes_[inst.mesh];
        if (!mesh.curves) stats_.triangles += mesh.indices.size() / 3;
        unsigned geom_id = static_cast<unsigned>(geom_to_instance_.size());
        if (!mesh.prototype && mesh.curves) {
            flatten_curves(mesh, inst.to_world);
            inst.identity = true;
        } else if (!mesh.prototype) {
            // Sole user: move the vertices into world space. A mirroring transform flips the winding,
            // so swap two corners to keep the geometric normal on Blender's outward side.
            for (std::vector<float>* positions : {&mesh.positions, &mesh.motion_positions})
                for (size_t i = 0; i + 4 < positions->size(); i += 3) {
                    Vec3 p = inst.to_world.point(load3(&(*positions)[i]));
                    (*positions)[i] = p.x, (*positions)[i + 1] = p.y, (*positions)[i + 2] = p.z;
                }
            float sign = inst.to_world.determinant3() < 0.0f ? -1.0f : 1.0f;
            for (Vec3& n : mesh.corner_normals) n = inst.to_world.normal(n) * sign;
            for (Vec3& n : mesh.motion_normals) n = inst.to_world.normal(n) * sign;
            if (sign < 0.0f)
                for (size_t t = 0; t < mesh.indices.size(); t += 3) {
                    std::swap(mesh.indices[t + 1], mesh.indices[t + 2]);
                    if (!mesh.corner_normals.empty()) std::swap(mesh.corner_normals[t + 1], mesh.corner_normals[t + 2]);
                    for (size_t k = 0; k < mesh.motion_normals.size(); k += mesh.corner_normals.size())
                        std::swap(mesh.motion_normals[k + t + 1], mesh.motion_normals[k + t + 2]);
                    if (!mesh.uvs.empty()) std::swap(mesh.uvs[t + 1], mesh.uvs[t + 2]);
                    for (MeshAttribute& a : mesh.attributes)
                        for (int k = 0; k < a.dims; ++k)
                            std::swap(a.corners[(t + 1) * a.dims + k], a.corners[(t + 2) * a.dims + k]);
                }
            inst.identity = true;
        }
        attach_instance_geometry(scene_, inst, geom_id, false);
        if (has_subsurface_) {
            bool walks = false;
            for (uint32_t m : mesh.materials) walks = walks || uses_subsurface(materials_[m]);
            if (walks) {
                inst.own = rtcNewScene(device_);
                rtcSetSceneFlags(inst.own, RTC_SCENE_FLAG_ROBUST);
                rtcSetSceneBuildQuality(inst.own, build_quality());
                attach_instance_geometry(inst.own, inst, geom_id, true);
                rtcCommitScene(inst.own);
            }
        }
        geom_to_instance_.push_back(static_cast<uint32_t>(&inst - instances_.data()));
        has_motion_ = has_motion_ || mesh.motion_steps > 0;
        // A deforming mesh's bounds cover every step (in world space already when flattened).
        for (size_t i = 0; i + 4 < mesh.motion_positions.size(); i += 3) {  // 4 floats of padding
            Vec3 p = load3(&mesh.motion_positions[i]);
            if (!inst.identity) p = inst.to_world.point(p);
            lo = vmin(lo, p);
            hi = vmax(hi, p);
        }
        for (size_t i = 0; mesh.curves && i < mesh.curve_points.size(); i += 4) {
            Vec3 p = load3(&mesh.curve_points[i]);
            if (!inst.identity) p = inst.to_world.point(p);
            lo = vmin(lo, p);
            hi = vmax(hi, p);
        }
        for (size_t i = 0; !mesh.curves && i < mesh.indices.size(); ++i) {
            Vec3 p = load3(&mesh.positions[3 * mesh.indices[i]]);
            for (const Transform& step : inst.motion) {
                lo = vmin(lo, step.point(p));
                hi = vmax(hi, step.point(p));
            }
            if (!inst.identity) p = inst.to_world.point(p);
            lo = vmin(lo, p);
            hi = vmax(hi, p);
            if (any_scattering_volume && scattering_volume[mesh.materials[i / 3]]) {
                scattering_.lo = vmin(scattering_.lo, p);
                scattering_.hi = vmax(scattering_.hi, p);
            }
        }
        if (!emissive_local_[inst.mesh].empty()) add_triangle_lights(inst);
    }
    rtcCommitScene(scene_);
    if (!embree_error_.empty()) throw std::runtime_error(embree_error_);
    update_boundary_planes();
    hit_ids_ = (kWithTextures && programs_) || has_subsurface_;
    has_motion_ = has_motion_ || camera_.has_motion();
    radius_ = instances_.empty() ? 1.0f : std::max(1e-3f, 0.5f * length(hi - lo));
    if (!std::isfinite(radius_)) radius_ = 1.0f;
    center_ = instances_.empty() || !is_finite(lo + hi) ? Vec3(0.0f) : (lo + hi) * 0.5f;

    for (const Material& m : materials_) has_media_ = has_media_ || m.medium >= 0 || m.pass_through;
    has_media_ = has_media_ || world_medium_ >= 0;
    if (has_media_) require_feature(kWithVolumes, "participating media", "volumes");
    if (has_media_) camera_medium_ = medium_at(camera_.generate_ray(0.5f * camera_.width(), 0.5f * camera_.height()).o);

    finish_lights();
    update_skipped();
    update_camera_bounds_test();
    stats_.meshes = meshes_.size();
    stats_.instances = instances_.size();
    stats_.materials = materials_.size();
    committed_ = true;
}

void Scene::update_camera_bounds_test() {
    RTCBounds b;
    rtcGetSceneBounds(scene_, &b);
    bounds_ = SceneBounds::padded({b.lower_x, b.lower_y, b.lower_z}, {b.upper_x, b.upper_y, b.upper_z});
    // Moving geometry: the box at one time is not the box over the shutter. No geometry: Embree's
    // miss is cheap enough.
    camera_bounds_test_ = !has_motion_ && bounds_.finite();
    if (!camera_bounds_test_ || !has_camera_ || camera_.has_aperture()) return;
    // Camera rays share one origin (or, orthographic, one direction), so those that meet the box
    // form a convex set: when the rays through the image's corners (a few pixels beyond, for the
    // pixel filter) all meet it, every camera ray does and the test would only cost.
    const float w = float(camera_.width()), h = float(camera_.height()), m = 4.0f;
    bool all_meet = true;
    for (float fx : {-m, w + m})
        for (float fy : {-m, h + m}) all_meet = all_meet && bounds_.may_meet(camera_.generate_ray(fx, fy));
    camera_bounds_test_ = !all_meet;
}

bool Scene::intersect(const Ray& ray, SurfaceHit* hit) const {
    // Camera rays that surely miss the scene's box hit nothing: no BVH query (scene_bounds.h).
    if (camera_bounds_test_ && ray.visibility == kRayCamera && !bounds_.may_meet(ray)) return false;
    if (!embree_accepts(ray.o, ray.d, ray.tmin, ray.tmax)) return false;  // see embree_accepts()
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh = embree_ray_hit(ray);
    rtcIntersect1(scene_, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    fill_hit(ray, rh, hit);
    hit->time = ray.time;
    return true;
}

void Scene::fill_hit(const Ray& ray, const RTCRayHit& rh, SurfaceHit* hit) const {
    unsigned top = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
    const Instance& inst = instances_[geom_to_instance_[top]];
    const Mesh& mesh = meshes_[inst.mesh];
    if (__builtin_expect(mesh.curves, 0)) return fill_curve_hit(ray, rh, geom_to_instance_[top], hit);
    uint32_t prim = rh.hit.primID;
    float u = rh.hit.u, v = rh.hit.v, w = 1.0f - u - v;
    Vec3 p, ng, ns;
    if (__builtin_expect(mesh.motion_steps == 0, 1)) {
        const uint32_t* idx = &mesh.indices[3 * prim];
        Vec3 a = load3(&mesh.positions[3 * idx[0]]), b = load3(&mesh.positions[3 * idx[1]]),
             c = load3(&mesh.positions[3 * idx[2]]);
        // Interpolating the vertices is more precise than o + t d for far-away or grazing hits.
        p = a * w + b * u + c * v;
        ng = cross(b - a, c - a);
        ns = ng;
        if (!mesh.corner_normals.empty()) {
            const Vec3* cn = &mesh.corner_normals[3 * prim];
            ns = cn[0] * w + cn[1] * u + cn[2] * v;
        }
    } else {
        const HitFrame d = deformed_point(mesh, prim, rh.ray.time, u, v);
        p = d.p, ng = d.ng, ns = d.ns;
    }
    if (!inst.identity) {
        if (__builtin_expect(inst.motion.empty(), 1)) {
            p = inst.to_world.point(p);
            float sign = inst.to_world.determinant3() < 0.0f ? -1.0f : 1.0f;
            ng = inst.to_world.normal(ng) * sign;
            ns = inst.to_world.normal(ns) * sign;
        } else {
            WorldFrame w = moving_to_world(inst.geometry, rh.ray.time, p, ng, ns);
            p = w.p, ng = w.ng, ns = w.ns;
        }
    }
    ng = normalize(ng);
    ns = normalize(ns);
    if (!is_finite(ns) || dot(ns, ng) == 0.0f) ns = ng;
    if (dot(ns, ng) < 0.0f) ns = -ns;  // shading normal on the geometric side (authoring errors)
    hit->t = rh.ray.tfar;
    hit->p = p;
    hit->ng = ng;
    hit->ns = ns;
    hit->material = mesh.materials[prim];
    hit->holdout = inst.holdout;
    if (kWithTextures) hit->attr.object_color = inst.object_color;
    if (hit_ids_) {
        hit->attr.instance = geom_to_instance_[top];
        hit->attr.prim = prim;
        hit->attr.bu = u;
        hit->attr.bv = v;
    }
    hit->light = -1;
    if (inst.light_base >= 0) {
        int32_t local = emissive_local_[inst.mesh][prim];
        if (local >= 0) hit->light = inst.light_base + local;
    }
    // Last and out of line: with a call in the middle, every hit paid for keeping the floats above
    // alive across it (SSE registers are caller-saved), textured or not (+1.1% instructions).
    if (kWithTextures && !mesh.uvs.empty()) fill_uv_attribs(mesh, inst, prim, u, v, hit);
}

void Scene::deformed_triangle(const Mesh& mesh, uint32_t prim, float time, Vec3 v[3], Vec3 n[3]) {
    // The step before the time and the fraction towards the next, as Embree places the triangle.
    const int last = static_cast<int>(mesh.motion_steps) - 1;
    const float x = std::clamp(time, 0.0f, 1.0f) * last;
    const int step = std::min(static_cast<int>(x), last - 1);
    const float f = x - step;
    const size_t stride = mesh.positions.size() - 4;  // floats per step
    const float* p0 = &mesh.motion_positions[step * stride];
    const uint32_t* idx = &mesh.indices[3 * prim];
    for (int k = 0; k < 3; ++k)
        v[k] = load3(p0 + 3 * idx[k]) * (1.0f - f) + load3(p0 + stride + 3 * idx[k]) * f;
    if (mesh.motion_normals.empty()) return;
    // Corner normals as Cycles' motion vertex normals: linear in time (normalised at the hit).
    const size_t per_step = mesh.corner_normals.size();
    const Vec3* n0 = &mesh.motion_normals[step * per_step + 3 * prim];
    for (int k = 0; k < 3; ++k) n[k] = n0[k] * (1.0f - f) + n0[per_step + k] * f;
}

void Scene::triangle_at(uint32_t instance, uint32_t prim, float time, Vec3 v[3]) const {
    const Instance& inst = instances_[instance];
    const Mesh& mesh = meshes_[inst.mesh];
    Vec3 normals[3];
    if (mesh.motion_steps != 0) {
        deformed_triangle(mesh, prim, time, v, normals);
    } else {
        for (int k = 0; k < 3; ++k) v[k] = load3(&mesh.positions[3 * mesh.indices[3 * prim + k]]);
    }
    if (inst.identity) return;  // flattened: world space already
    Transform at = inst.to_world;
    if (inst.geometry) rtcGetGeometryTransform(inst.geometry, time, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, &at.m[0][0]);
    for (int k = 0; k < 3; ++k) v[k] = at.point(v[k]);
}

Scene::HitFrame Scene::deformed_point(const Mesh& mesh, uint32_t prim, float time, float u, float v) {
    Vec3 c[3], n[3];
    deformed_triangle(mesh, prim, time, c, n);
    const float w = 1.0f - u - v;
    HitFrame f;
    f.p = c[0] * w + c[1] * u + c[2] * v;
    f.ng = cross(c[1] - c[0], c[2] - c[0]);
    f.ns = mesh.motion_normals.empty() ? f.ng : n[0] * w + n[1] * u + n[2] * v;
    return f;
}

void Scene::fill_uv_attribs(const Mesh& mesh, const Instance& inst, uint32_t prim, float u, float v,
                            SurfaceHit* hit) const {
    const Point2* uv = &mesh.uvs[3 * prim];
    float w = 1.0f - u - v;
    hit->attr.uv = {uv[0].x * w + uv[1].x * u + uv[2].x * v, uv[0].y * w + uv[1].y * u + uv[2].y * v};
    const Material& mat = materials_[hit->material];
    if (mat.normal_map) hit->ns = apply_normal_map(mat, mesh, inst, prim, hit->ns, hit->ng, hit->attr.uv);
}

// Blender's Normal Map node in tangent space: the tangent follows the UV map's u direction on the
// triangle, the bitangent its v direction (sign from the UV winding), blended by Strength as Cycles
// does: N = normalize(N + (N_map - N) * strength).
Vec3 Scene::apply_normal_map(const Material& mat, const Mesh& mesh, const Instance& inst, uint32_t prim,
                             const Vec3& ns, const Vec3& ng, Point2 uv) const {
    const uint32_t* idx = &mesh.indices[3 * prim];
    Vec3 a = load3(&mesh.positions[3 * idx[0]]), b = load3(&mesh.positions[3 * idx[1]]),
         c = load3(&mesh.positions[3 * idx[2]]);
    const Point2* t = &mesh.uvs[3 * prim];
    float du1 = t[1].x - t[0].x, dv1 = t[1].y - t[0].y, du2 = t[2].x - t[0].x, dv2 = t[2].y - t[0].y;
    float det = du1 * dv2 - du2 * dv1;
    if (!(std::fabs(det) > 1e-20f)) return ns;  // degenerate UVs: no tangent frame
    Vec3 dpdu = ((b - a) * dv2 - (c - a) * dv1) / det;
    if (!inst.identity) dpdu = inst.to_world.vector(dpdu);
    Vec3 tangent = dpdu - ns * dot(ns, dpdu);
    if (!(length_sq(tangent) > 0.0f)) return ns;
    tangent = normalize(tangent);
    // Mirrored UVs (negative det) and mirroring transforms flip the bitangent.
    float sign = (det < 0.0f ? -1.0f : 1.0f) * (inst.to_world.determinant3() < 0.0f && !inst.identity ? -1.0f : 1.0f);
    Vec3 bitangent = cross(ns, tangent) * sign;
    Color m = mat.normal_map->lookup(uv).rgb * 2.0f - Color(1.0f);
    Vec3 mapped = normalize(tangent * m.x + bitangent * m.y + ns * m.z);
    Vec3 n = normalize(ns + (mapped - ns) * std::max(mat.normal_strength, 0.0f));
    if (!is_finite(n)) return ns;
    return dot(n, ng) < 0.0f ? ns : n;  // never below the surface (as fill_hit's own rule)
}

bool Scene::intersect_instance(uint32_t instance, const Ray& ray, SurfaceHit* hit) const {
    if (instance >= instances_.size() || !instances_[instance].own) return false;
    if (!embree_accepts(ray.o, ray.d, ray.tmin, ray.tmax)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh = embree_ray_hit(ray);
    rh.ray.mask = kRayAllVisibility;
    rtcIntersect1(instances_[instance].own, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    fill_hit(ray, rh, hit);
    hit->time = ray.time;
    return true;
}

bool Scene::occluded(const Vec3& origin, const Vec3& dir, float tmax, float time, uint32_t visibility) const {
    if (!embree_accepts(origin, dir, 0.0f, tmax)) return true;  // see embree_accepts()
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = origin.x, r.org_y = origin.y, r.org_z = origin.z;
    r.dir_x = dir.x, r.dir_y = dir.y, r.dir_z = dir.z;
    r.tnear = 0.0f;
    r.tfar = tmax;
    r.mask = visibility;
    r.flags = 0;
    r.time = time;
    rtcOccluded1(scene_, &ctx, &r);
    return r.tfar < 0.0f;
}

}  // namespace smis
