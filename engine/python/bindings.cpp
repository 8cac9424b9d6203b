// The Python module `smis_render._smis`: a thin layer that converts numpy arrays and dicts from the
// add-on's sync code into engine calls. No light transport here, and the GIL is released whenever
// native code runs for long.
#include <map>
#include <set>
#include <sstream>
#include <type_traits>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <tbb/global_control.h>

#include <map>

#include "film/image_io.h"
#include "render/session.h"
#include "scene/mesh_attributes.h"
#include "scene/scene.h"

namespace py = pybind11;
using namespace smis;

namespace {

template <class T, class Dict>
T get(const Dict& d, const char* key, T fallback) {
    return d.contains(key) ? d[key].template cast<T>() : fallback;
}

// The render settings' dict, remembering which keys were asked for: a key the parser never asks
// for (a misspelt or retired setting) is an error, not a silently ignored value.
class SettingsDict {
public:
    explicit SettingsDict(const py::dict& d) : dict_(d) {}
    bool contains(const char* key) const {
        asked_.insert(key);
        return dict_.contains(key);
    }
    py::object operator[](const char* key) const { return dict_[key]; }
    void reject_unknown_keys() const {
        std::string unknown;
        for (const auto& item : dict_) {
            std::string key = py::str(item.first);
            if (!asked_.count(key)) unknown += (unknown.empty() ? "'" : ", '") + key + "'";
        }
        if (!unknown.empty()) throw py::value_error("unknown render setting(s) " + unknown);
    }

    // The settings table's readers (render_settings.h, read_settings): a number within its limits
    // (NaN: none), finite; an enum by its name.
    template <class T>
    void read(const char* key, T* field, double min, double max) const {
        if (!contains(key)) return;
        if constexpr (std::is_same_v<T, bool>) {
            *field = dict_[key].template cast<bool>();
        } else {
            const double v = std::is_integral_v<T> ? double(dict_[key].template cast<long long>())
                                                   : dict_[key].template cast<double>();
            if (!std::isfinite(v) || v < min || v > max) {  // comparisons with a NaN limit are false
                std::string range = std::isnan(max) ? " or more" : std::isnan(min) ? " or less" : "";
                std::string text = std::isnan(min) && std::isnan(max) ? "finite"
                                   : std::isnan(min) || std::isnan(max)
                                       ? number(std::isnan(min) ? max : min) + range
                                       : "between " + number(min) + " and " + number(max);
                throw py::value_error(std::string(key) + " must be " + text + ", not " + number(v));
            }
            *field = static_cast<T>(v);
        }
    }
    template <class E>
    void read_enum(const char* key, E* field) const {
        if (!contains(key)) return;
        const auto name = dict_[key].template cast<std::string>();
        std::string valid;
        for (const auto& item : SettingNames<E>::items) {
            if (name == item.first) return void(*field = item.second);
            valid += (valid.empty() ? "" : ", ") + std::string(item.first);
        }
        throw py::value_error(std::string(key) + " must be one of " + valid + ", not '" + name + "'");
    }

private:
    static std::string number(double v) {
        std::ostringstream out;
        out << v;
        return out.str();
    }
    const py::dict& dict_;
    mutable std::set<std::string> asked_;
};

Color get_color(const py::dict& d, const char* key, Color fallback) {
    if (!d.contains(key)) return fallback;
    auto v = d[key].cast<std::vector<float>>();
    if (v.size() < 3) throw py::value_error(std::string(key) + " needs three components");
    return {v[0], v[1], v[2]};
}

using MatrixArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

Transform to_transform(const MatrixArray& a) {
    if (a.ndim() != 2 || a.shape(0) < 3 || a.shape(1) != 4) throw py::value_error("matrix must be 4x4");
    Transform t;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) t.m[r][c] = static_cast<float>(a.at(r, c));
    return t;
}

// Motion steps: an n x 4 x 4 (or n x 3 x 4) array of matrices, or None for none.
std::vector<Transform> to_motion(const py::object& steps) {
    std::vector<Transform> out;
    if (steps.is_none()) return out;
    auto a = steps.cast<py::array_t<double, py::array::c_style | py::array::forcecast>>();
    if (a.ndim() != 3 || a.shape(1) < 3 || a.shape(2) != 4) throw py::value_error("motion must be n x 4 x 4 matrices");
    for (py::ssize_t k = 0; k < a.shape(0); ++k) {
        Transform t;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 4; ++c) t.m[r][c] = static_cast<float>(a.at(k, r, c));
        out.push_back(t);
    }
    return out;
}

Transform get_matrix(const py::dict& d, const char* key) {
    if (!d.contains(key)) throw py::value_error(std::string("missing ") + key);
    return to_transform(d[key].cast<MatrixArray>());
}

Lobe parse_lobe(const py::dict& d) {
    Lobe l;
    auto kind = get<std::string>(d, "kind", "diffuse");
    if (!lobe_kind_from_name(kind.c_str(), &l.kind)) throw py::value_error("unknown closure kind '" + kind + "'");
    auto fresnel = get<std::string>(d, "fresnel", "none");
    if (fresnel == "none") l.fresnel = FresnelMode::None;
    else if (fresnel == "schlick") l.fresnel = FresnelMode::Schlick;
    else if (fresnel == "dielectric") l.fresnel = FresnelMode::Dielectric;
    else throw py::value_error("unknown fresnel mode '" + fresnel + "'");
    l.weight = get_color(d, "weight", Color(1.0f));
    l.f0 = get_color(d, "f0", Color(1.0f));
    float roughness = get<float>(d, "roughness", 0.5f);
    l.alpha = roughness * roughness;  // Blender's roughness is the square root of GGX alpha
    l.eta = get<float>(d, "ior", 1.5f);
    return l;
}

// A homogeneous medium from {"sigma_a": rgb, "sigma_s": rgb, "anisotropy": g}, added to the scene.
int32_t add_medium(Scene& s, const py::dict& d) {
    Medium m;
    m.sigma_a = get_color(d, "sigma_a", Color(0.0f));
    m.sigma_s = get_color(d, "sigma_s", Color(0.0f));
    m.phase = HenyeyGreenstein(get<float>(d, "anisotropy", 0.0f));
    return s.add_medium(m);
}

py::array_t<float> to_image(std::vector<float>&& pixels, int w, int h, int channels = 4) {
    auto* heap = new std::vector<float>(std::move(pixels));
    py::capsule owner(heap, [](void* p) { delete static_cast<std::vector<float>*>(p); });
    return py::array_t<float>({h, w, channels}, heap->data(), owner);
}

AuxPass parse_aux_pass(const std::string& name) {
    static const std::map<std::string, AuxPass> passes = {{"Depth", AuxPass::Depth},
                                                          {"Normal", AuxPass::Normal},
                                                          {"Albedo", AuxPass::Albedo},
                                                          {"Diagnostic", AuxPass::Diagnostic}};
    auto it = passes.find(name);
    if (it == passes.end()) throw py::value_error("unknown pass '" + name + "'");
    return it->second;
}

const float* image_data(const py::array_t<float, py::array::c_style | py::array::forcecast>& a, int* w, int* h) {
    if (a.ndim() != 3 || a.shape(2) != 4) throw py::value_error("image must be an (h, w, 4) float array");
    *h = static_cast<int>(a.shape(0));
    *w = static_cast<int>(a.shape(1));
    return a.data();
}

// Cycles' Ray Visibility as the engine's bits (scene/ray_visibility.h): a dict of booleans camera,
// diffuse, glossy, transmission, shadow, volume_scatter (absent: visible).
uint32_t parse_visibility(const py::dict& d) {
    static const std::pair<const char*, uint32_t> kinds[] = {
        {"camera", kRayCamera},     {"diffuse", kRayDiffuse}, {"glossy", kRayGlossy},
        {"transmission", kRayTransmission}, {"shadow", kRayShadow}, {"volume_scatter", kRayVolumeScatter}};
    uint32_t bits = kRayAllVisibility;
    for (const auto& [key, bit] : kinds)
        if (!get<bool>(d, key, true)) bits &= ~bit;
    return bits;
}

// Every key the settings table knows (render_settings.h); any other key is an error.
RenderSettings parse_settings(const py::dict& dict) {
    const SettingsDict d(dict);
    RenderSettings s;
    read_settings(d, &s);
    d.reject_unknown_keys();
    return s;
}

// std::invalid_argument from the engine surfaces in Python as ValueError.
template <class F>
auto value_errors(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const std::invalid_argument& e) {
        throw py::value_error(e.what());
    }
}

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;

// add_mesh/replace_mesh arguments checked and converted; the arrays stay alive as members.
struct MeshArgs {
    FloatArray vertex_array, normal_array, uv_array;
    IntArray triangle_array, index_array;
    size_t nv = 0, nt = 0;
    const float *vertices = nullptr, *normals = nullptr, *uvs = nullptr;
    const int32_t *triangles = nullptr, *material_index = nullptr;

    MeshArgs(FloatArray v, IntArray t, const py::object& corner_normals, const py::object& mat_index,
             const py::object& corner_uvs)
        : vertex_array(std::move(v)), triangle_array(std::move(t)) {
        if (vertex_array.ndim() != 2 || vertex_array.shape(1) != 3) throw py::value_error("vertices must be (N, 3)");
        if (triangle_array.ndim() != 2 || triangle_array.shape(1) != 3)
            throw py::value_error("triangles must be (M, 3)");
        nv = vertex_array.shape(0), nt = triangle_array.shape(0);
        vertices = vertex_array.data(), triangles = triangle_array.data();
        normals = optional(corner_normals, normal_array, nt * 9, "corner_normals must be (M, 3, 3)");
        uvs = optional(corner_uvs, uv_array, nt * 6, "corner_uvs must be (M, 3, 2)");
        material_index = optional(mat_index, index_array, nt, "material_index must be (M,)");
    }
    template <class A>
    static auto optional(const py::object& o, A& keep, size_t size, const char* error) -> decltype(keep.data()) {
        if (o.is_none()) return nullptr;
        keep = o.cast<A>();
        if (size_t(keep.size()) != size) throw py::value_error(error);
        return keep.data();
    }
};

// Named per-corner attributes for shader programs, {name: (M, 3, k) floats} with k = 1..4, checked
// and converted; the arrays stay alive as members.
struct MeshAttributes {
    std::vector<FloatArray> arrays;
    std::vector<AttributeInput> inputs;
    MeshAttributes(const py::dict& attributes, size_t nt) {
        for (auto item : attributes) {
            FloatArray arr = item.second.cast<FloatArray>();
            if (arr.ndim() != 3 || size_t(arr.shape(0)) != nt || arr.shape(1) != 3 || arr.shape(2) < 1 ||
                arr.shape(2) > 4)
                throw py::value_error("attribute arrays must be (M, 3, k) with k in 1..4");
            inputs.push_back({item.first.cast<std::string>(), arr.data(), int(arr.shape(2))});
            arrays.push_back(std::move(arr));
        }
    }
};

// A closure's non-constant colour: "texture" (id from add_texture), "object_color", "to_f0".
LobeInput parse_lobe_input(const Scene& s, const py::dict& d) {
    LobeInput in;
    if (d.contains("texture") && !d["texture"].is_none())
        in.texture = value_errors([&] { return s.texture(d["texture"].cast<uint32_t>()); });
    in.object_color = get<bool>(d, "object_color", false);
    in.to_f0 = get<bool>(d, "to_f0", false);
    return in;
}

// A texture from add_texture's arguments.
std::shared_ptr<Texture> make_texture(const py::array_t<float, py::array::c_style | py::array::forcecast>& rgba,
                                      const std::string& colorspace, const std::string& interpolation,
                                      const std::string& extension, const std::string& alpha_mode, bool byte_image,
                                      bool alpha_linked) {
    int w, h;
    const float* data = image_data(rgba, &w, &h);
    Texture::Options o;
    o.wrap = extension == "EXTEND" ? Texture::Wrap::Extend
             : extension == "CLIP" ? Texture::Wrap::Clip
             : extension == "MIRROR" ? Texture::Wrap::Mirror
                                      : Texture::Wrap::Repeat;
    o.interp = interpolation == "Closest" ? Texture::Interp::Closest
               : (interpolation == "Cubic" || interpolation == "Smart") ? Texture::Interp::Cubic
                                                                          : Texture::Interp::Linear;
    o.alpha_mode = alpha_mode == "STRAIGHT" ? Texture::AlphaMode::Straight
                   : alpha_mode == "PREMUL" ? Texture::AlphaMode::Premul
                   : alpha_mode == "NONE" ? Texture::AlphaMode::None
                                          : Texture::AlphaMode::ChannelPacked;
    o.byte_image = byte_image;
    o.alpha_linked = alpha_linked;
    return value_errors([&] { return std::make_shared<Texture>(data, w, h, colorspace, o); });
}

std::shared_ptr<const ShaderProgram> parse_program_with(const py::dict& d,
                                                        std::vector<std::shared_ptr<const Texture>> textures);

// A compiled node tree (addon sync/shader_compiler.py): {"registers": [float], "data": [float],
// "textures": [texture id], "ops": [(name, inputs, outputs, ints, floats, data offset)]}.
std::shared_ptr<const ShaderProgram> parse_program(const Scene& s, const py::dict& d) {
    std::vector<std::shared_ptr<const Texture>> textures;
    for (auto id : d["textures"])
        textures.push_back(value_errors([&] { return s.texture(id.cast<uint32_t>()); }));
    return parse_program_with(d, std::move(textures));
}

// The same with the program's textures given (its "textures" entry is not read).
std::shared_ptr<const ShaderProgram> parse_program_with(const py::dict& d,
                                                        std::vector<std::shared_ptr<const Texture>> textures) {
    std::vector<ShaderOp> ops;
    for (auto item : d["ops"]) {
        auto t = item.cast<py::tuple>();
        if (t.size() != 6) throw py::value_error("shader op: expected 6 fields");
        ShaderOp op;
        auto name = t[0].cast<std::string>();
        if (!ShaderProgram::op_by_name(name, &op.code)) throw py::value_error("unknown shader op '" + name + "'");
        auto fill = [&](const py::handle& h, auto* dst, size_t n, const char* what) {
            auto v = h.cast<std::vector<int64_t>>();
            if (v.size() > n) throw py::value_error(std::string("shader op '") + name + "': too many " + what);
            for (size_t k = 0; k < v.size(); ++k) {
                if (v[k] < -1 || v[k] >= int64_t(ShaderProgram::kMaxRegisters))
                    throw py::value_error(std::string("shader op '") + name + "': bad register");
                dst[k] = v[k] < 0 ? kNoReg : uint16_t(v[k]);
            }
        };
        fill(t[1], op.in, std::size(op.in), "inputs");
        fill(t[2], op.out, std::size(op.out), "outputs");
        auto ints = t[3].cast<std::vector<int32_t>>();
        auto floats = t[4].cast<std::vector<float>>();
        if (ints.size() > 5 || floats.size() > 4) throw py::value_error("shader op '" + name + "': too many parameters");
        std::copy(ints.begin(), ints.end(), op.i);
        std::copy(floats.begin(), floats.end(), op.f);
        op.data = t[5].cast<uint32_t>();
        ops.push_back(op);
    }
    auto program = value_errors([&] {
        return std::make_shared<ShaderProgram>(std::move(ops), d["registers"].cast<std::vector<float>>(),
                                               d["data"].cast<std::vector<float>>(), std::move(textures));
    });
    program->fold_constants();
    return program;
}

Material parse_material(Scene& s, const py::dict& d) {
    Material mat;
    if (d.contains("program") && !d["program"].is_none()) mat.program = parse_program(s, d["program"].cast<py::dict>());
    mat.name = get<std::string>(d, "name", "");
    bool varies = false;
    if (d.contains("closures"))
        for (auto c : d["closures"]) {
            auto cd = c.cast<py::dict>();
            mat.lobes.push_back(parse_lobe(cd));
            mat.inputs.push_back(parse_lobe_input(s, cd));
            varies = varies || mat.inputs.back().varies();
        }
    if (!varies) mat.inputs.clear();  // constant lobes: no per-hit work
    mat.emission = get_color(d, "emission", Color(0.0f));
    if (d.contains("emission_texture") && !d["emission_texture"].is_none())
        mat.emission_texture =
            value_errors([&] { return s.texture(d["emission_texture"].cast<uint32_t>()); });
    MaterialSpectral& sp = mat.spectral;
    sp.emission_spectrum = get<std::string>(d, "emission_spectrum", sp.emission_spectrum);
    sp.emission_temperature = get<float>(d, "emission_temperature", sp.emission_temperature);
    sp.metal = get<std::string>(d, "metal", sp.metal);
    sp.dispersion = get<std::string>(d, "dispersion", sp.dispersion);
    sp.abbe = get<float>(d, "abbe", sp.abbe);
    mat.pass_through = get<bool>(d, "pass_through", false);
    if (d.contains("volume") && !d["volume"].is_none())
        mat.medium = value_errors([&] { return add_medium(s, d["volume"].cast<py::dict>()); });
    if (d.contains("alpha")) {
        auto a = d["alpha"].cast<py::dict>();
        mat.alpha = get<float>(a, "value", 1.0f);
        if (a.contains("texture") && !a["texture"].is_none())
            mat.alpha_texture = value_errors([&] { return s.texture(a["texture"].cast<uint32_t>()); });
    }
    if (d.contains("normal_map")) {
        auto nm = d["normal_map"].cast<py::dict>();
        mat.normal_map = value_errors([&] { return s.texture(nm["texture"].cast<uint32_t>()); });
        mat.normal_strength = get<float>(nm, "strength", 1.0f);
    }
    return mat;
}

// The World (addon sync/world.py): {"color", "strength"} for a constant one, and optionally
// "program" (a compiled World Surface whose "textures" index "images", each add_texture's keyword
// arguments or {"missing": True}), "map_resolution": (width, height) of the importance map,
// "visible_camera", "visibility" (parse_visibility: the bounce types that see the World). The world's images live with its program (a world edit frees the old ones).
WorldDesc parse_world(const py::dict& d) {
    WorldDesc w;
    w.radiance = get_color(d, "color", Color(0.0f)) * get<float>(d, "strength", 1.0f);
    w.visible_to_camera = get<bool>(d, "visible_camera", true);
    if (d.contains("visibility")) w.visibility = parse_visibility(d["visibility"].cast<py::dict>());
    if (d.contains("map_resolution") && !d["map_resolution"].is_none()) {
        auto r = d["map_resolution"].cast<std::vector<int>>();
        if (r.size() != 2) throw py::value_error("map_resolution needs (width, height)");
        w.map_width = r[0], w.map_height = r[1];
    }
    if (d.contains("program") && !d["program"].is_none()) {
        std::vector<std::shared_ptr<const Texture>> images;
        if (d.contains("images"))
            for (auto item : d["images"]) {
                auto im = item.cast<py::dict>();
                if (get<bool>(im, "missing", false)) {
                    images.push_back(Texture::missing());
                    continue;
                }
                images.push_back(make_texture(im["rgba"].cast<FloatArray>(), get<std::string>(im, "colorspace", "linear"),
                                              get<std::string>(im, "interpolation", "Linear"),
                                              get<std::string>(im, "extension", "REPEAT"),
                                              get<std::string>(im, "alpha_mode", "STRAIGHT"),
                                              get<bool>(im, "byte_image", false), get<bool>(im, "alpha_linked", false)));
            }
        auto program = d["program"].cast<py::dict>();
        std::vector<std::shared_ptr<const Texture>> textures;
        for (auto id : program["textures"]) {
            auto i = id.cast<int64_t>();
            if (i < 0 || size_t(i) >= images.size()) throw py::value_error("world program: unknown image");
            textures.push_back(images[size_t(i)]);
        }
        w.program = parse_program_with(program, std::move(textures));
    }
    return w;
}

LightDesc parse_light(const py::dict& d) {
    LightDesc l;
    l.type = get<std::string>(d, "type", "POINT");
    l.to_world = get_matrix(d, "matrix");
    l.color = get_color(d, "color", Color(1.0f));
    l.power = get<float>(d, "power", 0.0f);
    l.strength = get<float>(d, "strength", 0.0f);
    l.shape = get<std::string>(d, "shape", "SQUARE");
    l.size = get<float>(d, "size", 1.0f);
    l.size_y = get<float>(d, "size_y", l.size);
    l.radius = get<float>(d, "radius", 0.0f);
    l.spot_size = get<float>(d, "spot_size", l.spot_size);
    l.spot_blend = get<float>(d, "spot_blend", l.spot_blend);
    l.angle = get<float>(d, "angle", 0.0f);
    l.spread = get<float>(d, "spread", l.spread);
    l.visible_to_camera = get<bool>(d, "visible_camera", true);
    l.cast_shadow = get<bool>(d, "cast_shadow", true);
    if (d.contains("visibility")) l.visibility = parse_visibility(d["visibility"].cast<py::dict>());
    l.use_mis = get<bool>(d, "use_mis", true);
    l.spectrum = get<std::string>(d, "spectrum", l.spectrum);
    l.temperature = get<float>(d, "temperature", l.temperature);
    return l;
}

}  // namespace

PYBIND11_MODULE(_smis, m) {
    m.doc() = "Native SMIS render engine (Embree path tracer with continuous/stochastic MIS)";

    py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene")
        .def(py::init<>())
        .def("add_material",
             [](Scene& s, const py::dict& d) {
                 Material mat = parse_material(s, d);
                 return value_errors([&] { return s.add_material(std::move(mat)); });
             })
        .def(
            "replace_material",
            [](Scene& s, uint32_t id, const py::dict& d) {
                Material mat = parse_material(s, d);
                return value_errors([&] { return s.replace_material(id, std::move(mat)); });
            },
            "Viewport scenes: the material `id` edited (add_material's dict); False if the scene must be "
            "rebuilt instead")
        .def(
            "replace_lights",
            [](Scene& s, const py::list& lights, const py::dict& world) {
                std::vector<LightDesc> descs;
                for (auto l : lights) descs.push_back(parse_light(l.cast<py::dict>()));
                WorldDesc w = parse_world(world);
                py::gil_scoped_release release;  // the World's importance map is built here
                return value_errors([&] { return s.replace_lights(descs, w); });
            },
            "Viewport scenes: all lamps (add_light's dicts) and the world (set_world's dict, no volume) "
            "edited; False if the scene must be rebuilt instead")
        .def(
            "add_texture",
            [](Scene& s, py::array_t<float, py::array::c_style | py::array::forcecast> rgba, const std::string& colorspace,
               const std::string& interpolation, const std::string& extension, const std::string& alpha_mode,
               bool byte_image, bool alpha_linked) {
                auto texture = make_texture(rgba, colorspace, interpolation, extension, alpha_mode, byte_image, alpha_linked);
                return value_errors([&] { return s.add_texture(texture); });
            },
            py::arg("rgba"), py::arg("colorspace"), py::arg("interpolation") = "Linear", py::arg("extension") = "REPEAT",
            py::arg("alpha_mode") = "CHANNEL_PACKED", py::arg("byte_image") = false, py::arg("alpha_linked") = false,
            "An image texture from (h, w, 4) float pixels, bottom row first (Image.pixels); returns its id")
        .def("add_missing_texture", [](Scene& s) { return s.add_texture(Texture::missing()); },
             "Cycles' stand-in for an image that cannot be loaded (magenta); returns its id")
        .def(
            "add_mesh",
            [](Scene& s, FloatArray vertices, IntArray triangles, py::object corner_normals, py::object material_index,
               std::vector<uint32_t> materials, py::object corner_uvs, py::dict attributes) {
                MeshArgs a(vertices, triangles, corner_normals, material_index, corner_uvs);
                MeshAttributes attrs(attributes, a.nt);
                py::gil_scoped_release release;
                return value_errors([&] {
                    return s.add_mesh(a.vertices, a.nv, a.triangles, a.nt, a.normals, a.material_index, materials, a.uvs,
                                      attrs.inputs);
                });
            },
            py::arg("vertices"), py::arg("triangles"), py::arg("corner_normals") = py::none(),
            py::arg("material_index") = py::none(), py::arg("materials") = std::vector<uint32_t>{},
            py::arg("corner_uvs") = py::none(), py::arg("attributes") = py::dict())
        .def(
            "set_mesh_motion",
            [](Scene& s, uint32_t mesh, FloatArray positions, py::object corner_normals) {
                if (positions.ndim() != 3 || positions.shape(2) != 3)
                    throw py::value_error("mesh motion positions must be (steps, N, 3)");
                FloatArray normal_array;
                const float* normals = nullptr;
                size_t nt = 0;
                if (!corner_normals.is_none()) {
                    normal_array = corner_normals.cast<FloatArray>();
                    if (normal_array.ndim() != 4 || normal_array.shape(0) != positions.shape(0) ||
                        normal_array.shape(2) != 3 || normal_array.shape(3) != 3)
                        throw py::value_error("mesh motion normals must be (steps, M, 3, 3)");
                    normals = normal_array.data();
                    nt = normal_array.shape(1);
                }
                value_errors([&] {
                    s.set_mesh_motion(mesh, positions.data(), positions.shape(0), positions.shape(1), normals, nt);
                });
            },
            py::arg("mesh"), py::arg("positions"), py::arg("corner_normals") = py::none(),
            "Deformation motion blur: the mesh's vertices (steps, N, 3) and corner normals (steps, M, 3, 3) or "
            "None at evenly spaced times over the shutter; ValueError (the mesh unchanged) when they do not fit")
        .def(
            "add_curves",
            [](Scene& s, FloatArray points, IntArray curve_offsets, uint32_t material, uint32_t first_curve,
               py::object uvs, py::dict attributes) {
                if (points.ndim() != 2 || points.shape(1) != 4) throw py::value_error("points must be (N, 4): x, y, z, radius");
                if (curve_offsets.ndim() != 1 || curve_offsets.shape(0) < 1)
                    throw py::value_error("curve_offsets must be (curves + 1,)");
                size_t np = points.shape(0), nc = curve_offsets.shape(0) - 1;
                FloatArray uv_array;
                if (!uvs.is_none()) {
                    uv_array = uvs.cast<FloatArray>();
                    if (uv_array.ndim() != 2 || size_t(uv_array.shape(0)) != nc || uv_array.shape(1) != 2)
                        throw py::value_error("uvs must be (curves, 2)");
                }
                std::vector<FloatArray> arrays;
                std::vector<AttributeInput> inputs;
                for (auto item : attributes) {
                    FloatArray arr = item.second.cast<FloatArray>();
                    if (arr.ndim() != 2 || size_t(arr.shape(0)) != nc || arr.shape(1) < 1 || arr.shape(1) > 4)
                        throw py::value_error("curve attribute arrays must be (curves, k) with k in 1..4");
                    inputs.push_back({item.first.cast<std::string>(), arr.data(), int(arr.shape(1))});
                    arrays.push_back(std::move(arr));
                }
                const float* uv_data = uvs.is_none() ? nullptr : uv_array.data();
                py::gil_scoped_release release;
                return value_errors([&] {
                    return s.add_curves(points.data(), np, curve_offsets.data(), nc, material, first_curve, uv_data, inputs);
                });
            },
            py::arg("points"), py::arg("curve_offsets"), py::arg("material"), py::arg("first_curve") = 0,
            py::arg("uvs") = py::none(), py::arg("attributes") = py::dict(),
            "Hair: Catmull-Rom curves through (N, 4) points (x, y, z, radius), curve c from curve_offsets[c] to "
            "curve_offsets[c + 1] - 1, all with one material; first_curve: the index of curve 0 among the "
            "object's hair (Hair Info's Random hashes first_curve + c, as Cycles); uvs: (curves, 2) each strand's "
            "UV (the render UV map at its root) or None; attributes: {name: (curves, k)} per-strand values shader "
            "programs read by name; returns a mesh id for add_instance")
        .def(
            "set_curve_ribbons",
            [](Scene& s, uint32_t mesh, uint32_t subdivisions) {
                value_errors([&] { s.set_curve_ribbons(mesh, subdivisions); });
            },
            py::arg("mesh"), py::arg("subdivisions") = 2,
            "Cycles' Rounded Ribbons for the hair mesh (add_curves): flat strips facing the ray, subdivisions + 1 "
            "quads per segment, shaded with the round tube's normal")
        .def("attribute_id", [](Scene& s, const std::string& name) { return s.attribute_id(name); },
             "The id shader programs use for a mesh attribute (UV map or colour attribute) by name")
        .def(
            "replace_mesh",
            [](Scene& s, uint32_t mesh, FloatArray vertices, IntArray triangles, py::object corner_normals,
               py::object material_index, std::vector<uint32_t> materials, py::object corner_uvs, py::dict attributes) {
                MeshArgs a(vertices, triangles, corner_normals, material_index, corner_uvs);
                MeshAttributes attrs(attributes, a.nt);
                py::gil_scoped_release release;
                return value_errors([&] {
                    return s.replace_mesh(mesh, a.vertices, a.nv, a.triangles, a.nt, a.normals, a.material_index,
                                          materials, a.uvs, attrs.inputs);
                });
            },
            py::arg("mesh"), py::arg("vertices"), py::arg("triangles"), py::arg("corner_normals") = py::none(),
            py::arg("material_index") = py::none(), py::arg("materials") = std::vector<uint32_t>{},
            py::arg("corner_uvs") = py::none(), py::arg("attributes") = py::dict(),
            "Viewport scenes: replace a committed mesh in place (same arguments as add_mesh); False if the "
            "scene must be rebuilt instead")
        .def(
            "set_instance_transforms",
            [](Scene& s, py::array_t<double, py::array::c_style | py::array::forcecast> matrices) {
                if (matrices.ndim() != 3 || matrices.shape(1) != 4 || matrices.shape(2) != 4)
                    throw py::value_error("matrices must be (N, 4, 4)");
                size_t n = matrices.shape(0);
                std::vector<float> rows(12 * n);
                auto m = matrices.unchecked<3>();
                for (size_t i = 0; i < n; ++i)
                    for (int r = 0; r < 3; ++r)
                        for (int c = 0; c < 4; ++c) rows[12 * i + 4 * r + c] = static_cast<float>(m(i, r, c));
                py::gil_scoped_release release;
                return s.set_instance_transforms(rows.data(), n);
            },
            "Viewport scenes: new matrices for every instance, in add_instance order; False if the scene must "
            "be rebuilt instead")
        .def("mesh_dropped", &Scene::mesh_dropped)
        .def("add_instance",
             [](Scene& s, uint32_t mesh, MatrixArray matrix, std::vector<float> color, float random, float pass_index,
                bool holdout, const py::object& visibility, const py::object& motion) {
                 if (color.size() < 3) throw py::value_error("color needs three components");
                 float alpha = color.size() > 3 ? color[3] : 1.0f;
                 const uint32_t bits = visibility.is_none() ? kRayAllVisibility : parse_visibility(visibility.cast<py::dict>());
                 std::vector<Transform> steps = to_motion(motion);
                 value_errors([&] {
                     s.add_instance(mesh, to_transform(matrix), {color[0], color[1], color[2]}, random, pass_index, alpha,
                                    holdout, bits, steps);
                 });
             },
             py::arg("mesh"), py::arg("matrix"), py::arg("color") = std::vector<float>{1.0f, 1.0f, 1.0f},
             py::arg("random") = 0.0f, py::arg("pass_index") = 0.0f, py::arg("holdout") = false,
             py::arg("visibility") = py::none(), py::arg("motion") = py::none(),
             "visibility: Cycles' Ray Visibility as a dict of booleans (camera, diffuse, glossy, transmission, "
             "shadow, volume_scatter; absent keys visible); motion: transform motion blur, the matrices at "
             "evenly spaced times over the shutter (n x 4 x 4)")
        .def("set_mesh_texspace",
             [](Scene& s, uint32_t mesh, std::vector<float> location, std::vector<float> size) {
                 if (location.size() != 3 || size.size() != 3) throw py::value_error("texture space needs 3 + 3 values");
                 value_errors([&] {
                     s.set_mesh_texspace(mesh, {location[0], location[1], location[2]}, {size[0], size[1], size[2]});
                 });
             })
        .def("add_light",
             [](Scene& s, const py::dict& d) {
                 LightDesc l = parse_light(d);
                 return value_errors([&] { return s.add_light(l); });
             })
        .def("set_world",
             [](Scene& s, const py::dict& d) {
                 s.set_world(parse_world(d));
                 if (d.contains("volume") && !d["volume"].is_none())
                     value_errors([&] { s.set_world_medium(add_medium(s, d["volume"].cast<py::dict>())); });
             })
        .def("set_camera",
             [](Scene& s, const py::dict& d) {
                 CameraDesc c;
                 c.orthographic = get<std::string>(d, "type", "PERSP") == "ORTHO";
                 c.to_world = get_matrix(d, "matrix");
                 c.sensor_fit = get<std::string>(d, "sensor_fit", c.sensor_fit);
                 c.sensor_width = get<float>(d, "sensor_width", c.sensor_width);
                 c.sensor_height = get<float>(d, "sensor_height", c.sensor_height);
                 c.lens = get<float>(d, "lens", c.lens);
                 c.ortho_scale = get<float>(d, "ortho_scale", c.ortho_scale);
                 c.shift_x = get<float>(d, "shift_x", 0.0f);
                 c.shift_y = get<float>(d, "shift_y", 0.0f);
                 c.clip_start = get<float>(d, "clip_start", c.clip_start);
                 c.clip_end = get<float>(d, "clip_end", c.clip_end);
                 c.width = get<int>(d, "width", c.width);
                 c.height = get<int>(d, "height", c.height);
                 c.pixel_aspect_x = get<float>(d, "pixel_aspect_x", 1.0f);
                 c.pixel_aspect_y = get<float>(d, "pixel_aspect_y", 1.0f);
                 c.fstop = get<float>(d, "fstop", c.fstop);
                 c.focus_distance = get<float>(d, "focus_distance", c.focus_distance);
                 c.aperture_blades = get<int>(d, "aperture_blades", c.aperture_blades);
                 c.aperture_rotation = get<float>(d, "aperture_rotation", c.aperture_rotation);
                 c.aperture_ratio = get<float>(d, "aperture_ratio", c.aperture_ratio);
                 if (d.contains("motion")) c.motion = to_motion(d["motion"]);
                 if (d.contains("shutter_curve")) c.shutter_curve = d["shutter_curve"].cast<std::vector<float>>();
                 if (d.contains("border")) {
                     auto b = d["border"].cast<std::vector<int>>();
                     if (b.size() != 4) throw py::value_error("border must be (x0, y0, x1, y1)");
                     for (int i = 0; i < 4; ++i) c.border[i] = b[i];
                 }
                 value_errors([&] { s.set_camera(c); });
             })
        .def("has_camera", &Scene::has_camera)
        .def("has_spectral_content", &Scene::has_spectral_content)
        .def("set_fast_build", &Scene::set_fast_build)
        .def("set_light_selection",
             [](Scene& s, const std::string& mode) {
                 if (mode != "DEFENSIVE" && mode != "CYCLES_3_4")
                     throw py::value_error("light selection must be DEFENSIVE or CYCLES_3_4, not " + mode);
                 s.set_light_selection(mode == "DEFENSIVE" ? LightSelection::Defensive : LightSelection::Cycles34);
             })
        .def("commit",
             [](Scene& s) {
                 py::gil_scoped_release release;
                 try {
                     s.commit();
                 } catch (const std::invalid_argument& e) {
                     py::gil_scoped_acquire acquire;
                     throw py::value_error(e.what());
                 }
             })
        .def("stats", [](const Scene& s) {
            const SceneStats& st = s.stats();
            py::dict d;
            d["meshes"] = st.meshes;
            d["instances"] = st.instances;
            d["embree_instances"] = st.embree_instances;
            d["triangles"] = st.triangles;
            d["dropped_triangles"] = st.dropped_triangles;
            d["lights"] = st.lights;
            d["emissive_triangles"] = st.emissive_triangles;
            d["materials"] = st.materials;
            d["has_media"] = s.has_media();
            d["has_motion"] = s.has_motion();
            d["has_subsurface"] = s.has_subsurface();
            return d;
        });

    py::class_<RenderSession>(m, "RenderSession")
        .def(py::init([](std::shared_ptr<Scene> scene, const py::dict& settings) {
                 if (!scene->has_camera()) throw py::value_error("scene has no camera");
                 RenderSettings s = parse_settings(settings);
                 return value_errors([&] { return std::make_unique<RenderSession>(scene, s); });
             }),
             py::keep_alive<1, 2>())
        .def("start", &RenderSession::start)
        .def("run",
             [](RenderSession& r) {
                 py::gil_scoped_release release;
                 r.run();
             })
        .def("wait", &RenderSession::wait, py::arg("timeout") = -1.0, py::call_guard<py::gil_scoped_release>())
        .def("cancel", &RenderSession::cancel)
        .def("error", &RenderSession::error)
        .def("progress",
             [](const RenderSession& r) {
                 RenderProgress p = r.progress();
                 py::dict d;
                 d["samples_done"] = p.samples_done;
                 d["samples_total"] = p.samples_total;
                 d["fraction"] = p.fraction;
                 d["elapsed"] = p.elapsed;
                 d["paths_per_second"] = p.paths_per_second;
                 d["finished"] = p.finished;
                 d["cancelled"] = p.cancelled;
                 return d;
             })
        .def("counters",
             [](const RenderSession& r) {
                 RenderProgress p = r.progress();
                 py::dict d;
                 d["paths"] = p.paths;
                 d["nan_caught"] = p.nan_caught;
                 d["samples_rejected"] = p.samples_rejected;
                 return d;
             })
        .def("pixels", [](const RenderSession& r) { return to_image(r.pixels(), r.width(), r.height()); })
        .def("integrator_stats", &RenderSession::integrator_stats)
        .def("skipped", &RenderSession::skipped)
        .def(
            "pass_pixels",
            [](const RenderSession& r, const std::string& name) -> py::object {
                AuxPass pass = parse_aux_pass(name);
                std::vector<float> px = r.aux_pixels(pass);
                if (px.empty()) return py::none();
                return to_image(std::move(px), r.width(), r.height(), aux_pass_channels(pass));
            },
            "An auxiliary pass (Depth, Normal, Albedo, Diagnostic) as an (h, w, channels) array, bottom row "
            "first; None unless the session was created with aux_passes");

    m.def(
        "resolve_spectral_mode",
        [](const Scene& scene, const py::dict& settings) {
            return value_errors([&] { return setting_name(resolve_spectral_mode(parse_settings(settings), scene)); });
        },
        "The spectral mode scene.smis.spectral selects for a committed scene (AUTO resolved).");

    // Blender computes split normals with parallel floating-point sums whose order varies from run
    // to run (measured: a few hundred normals differ in the last bit between two exports of the
    // same mesh). The sync layer computes them inside this guard, which limits TBB (shared with
    // Blender) to one thread, so the same scene exports the same numbers and renders the same image.
    struct SerialTbb {
        std::unique_ptr<tbb::global_control> control;
    };
    py::class_<SerialTbb>(m, "SerialTbb")
        .def(py::init<>())
        .def("__enter__",
             [](SerialTbb& s) {
                 s.control = std::make_unique<tbb::global_control>(
                     tbb::global_control::max_allowed_parallelism, 1);
                 return &s;
             })
        .def("__exit__", [](SerialTbb& s, py::args) { s.control.reset(); });

    using IntArray = py::array_t<int32_t, py::array::c_style | py::array::forcecast>;
    using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;
    m.def(
        "mesh_pointiness",
        [](FloatArray positions, FloatArray normals, IntArray edges) {
            if (positions.size() % 3 || normals.size() != positions.size() || edges.size() % 2)
                throw py::value_error("mesh_pointiness: positions and normals (n, 3), edges (m, 2)");
            std::vector<float> v = value_errors([&] {
                return mesh_pointiness(positions.data(), normals.data(), size_t(positions.size() / 3), edges.data(),
                                       size_t(edges.size() / 2));
            });
            return py::array_t<float>(py::ssize_t(v.size()), v.data());
        },
        "Cycles' Pointiness per vertex from Blender's vertex positions, vertex normals and edges");
    m.def(
        "mesh_random_per_island",
        [](size_t num_vertices, IntArray edges, IntArray triangle_vertex0) {
            if (edges.size() % 2) throw py::value_error("mesh_random_per_island: edges (m, 2)");
            std::vector<float> v = value_errors([&] {
                return mesh_random_per_island(num_vertices, edges.data(), size_t(edges.size() / 2),
                                              triangle_vertex0.data(), size_t(triangle_vertex0.size()));
            });
            return py::array_t<float>(py::ssize_t(v.size()), v.data());
        },
        "Cycles' Random Per Island per triangle from the edges and each triangle's first vertex");
    m.def("write_exr", [](const std::string& path, py::array_t<float, py::array::c_style | py::array::forcecast> img) {
        int w, h;
        const float* data = image_data(img, &w, &h);
        write_exr(path, data, w, h);
    });
    m.def(
        "read_exr",
        [](const std::string& path, const std::string& layer) {
            int w = 0, h = 0;
            std::vector<float> rgba = read_exr(path, &w, &h, layer);
            return to_image(std::move(rgba), w, h);
        },
        py::arg("path"), py::arg("layer") = "");
    m.def(
        "read_exr_channels",
        [](const std::string& path) {
            int w = 0, h = 0;
            std::map<std::string, std::vector<float>> channels = read_exr_channels(path, &w, &h);
            py::dict out;
            for (auto& [name, px] : channels) out[py::str(name)] = to_image(std::move(px), w, h, 1)[py::make_tuple(py::ellipsis(), 0)];
            return out;
        },
        "Every channel of an EXR (multilayer names such as 'ViewLayer.Depth.Z' kept) as (h, w) float arrays, "
        "bottom row first");
    m.def(
        "write_exr_channels",
        [](const std::string& path, const py::dict& channels) {
            std::map<std::string, std::vector<float>> data;
            int w = -1, h = -1;
            for (auto item : channels) {
                auto a = item.second.cast<py::array_t<float, py::array::c_style | py::array::forcecast>>();
                if (a.ndim() != 2) throw py::value_error("channels must be (h, w) arrays");
                if (w >= 0 && (a.shape(0) != h || a.shape(1) != w)) throw py::value_error("channel sizes differ");
                h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
                data[item.first.cast<std::string>()] = std::vector<float>(a.data(), a.data() + a.size());
            }
            if (data.empty()) throw py::value_error("no channels");
            write_exr_channels(path, data, w, h);
        },
        "Writes (h, w) float arrays (bottom row first) as the named channels of one EXR");
    m.def(
        "write_png",
        [](const std::string& path, py::array_t<float, py::array::c_style | py::array::forcecast> img,
           const std::string& config, const std::string& display, const std::string& view, const std::string& look,
           float exposure, float gamma) {
            int w, h;
            const float* data = image_data(img, &w, &h);
            write_png(path, data, w, h, {config, display, view, look, exposure, gamma});
        },
        py::arg("path"), py::arg("image"), py::arg("config"), py::arg("display") = "sRGB",
        py::arg("view") = "Standard", py::arg("look") = "", py::arg("exposure") = 0.0f, py::arg("gamma") = 1.0f);
}
