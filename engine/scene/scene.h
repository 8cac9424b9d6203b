// The Scene owns geometry (Embree), materials, lights and the camera. It is built once through the
// add_* calls (the add-on's sync layer, or tests), frozen by commit(), then only read while rendering.
#pragma once
#include <embree3/rtcore.h>

#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "core/distribution.h"
#include "scene/boundary_planes.h"
#include "scene/camera.h"
#include "scene/glow_lights.h"
#include "scene/light_selection.h"
#include "scene/lights.h"
#include "scene/material.h"
#include "scene/media_light_choice.h"
#include "scene/medium.h"
#include "scene/scene_bounds.h"
#include "shading/shader_context.h"

namespace smis {

// SurfaceHit::light of a hit on an emissive strand (hair curves): it emits but is no light, so no
// light sample can reach it (Cycles 3.4 makes lights of mesh triangles only, and weighs a curve's
// emission by 1: integrate_surface_emission's MIS is for PRIMITIVE_TRIANGLE).
constexpr int32_t kStrandEmission = -2;

struct SurfaceHit {
    float t = kInf;
    Vec3 p;               // world position
    Vec3 ng;              // unit geometric normal (triangle winding: Blender's outward side)
    Vec3 ns;              // unit shading normal, on the same side as ng
    uint32_t material = 0;
    int32_t light = -1;   // index into Scene::lights() when the triangle emits, kStrandEmission, else -1
    bool holdout = false; // the instance is a holdout (Object > Visibility > Holdout)
    SurfaceAttribs attr;  // UV and object colour, for textured materials
    float time = kShutterCentre;  // the time of the ray that found it (rays leaving it keep it)
};

struct SceneStats {
    uint64_t meshes = 0, instances = 0, embree_instances = 0, triangles = 0, dropped_triangles = 0, lights = 0,
             emissive_triangles = 0, materials = 0;
};

// Where a light's emission spectrum comes from (spectral rendering): its spectrum name and
// temperature, and the RGB colour it was given (light colour, emission colour or world colour).
struct EmitterSource {
    std::string spectrum = "RGB";
    float temperature = 6500.0f;
    Color color{1.0f};
};

// The World's Surface: a constant radiance, or a shader program evaluated per direction (the
// add-on's compile_world), importance-sampled by an EnvironmentLight whose map has
// map_width x map_height cells (0: 1024 x 512; viewport scenes cap it at 1024 x 512).
struct WorldDesc {
    Color radiance{0.0f};                          // used when there is no program
    std::shared_ptr<const ShaderProgram> program;  // null: the constant radiance
    int map_width = 0, map_height = 0;
    bool visible_to_camera = true;
    // World > Ray Visibility (Cycles' world.cycles_visibility) beyond Camera: the bounce types that
    // see it and whose lobes its light samples light (Light::visibility of its light).
    uint32_t visibility = kRayAllVisibility;
    bool sample_sun = true;  // false: a Nishita sun is left to the map (comparisons only)
};

// A per-corner mesh attribute (UV maps by name, colour attributes) as the add-on exports it:
// nt x 3 x dims floats, triangle order as given to add_mesh.
struct AttributeInput {
    std::string name;
    const float* corners = nullptr;
    int dims = 2;
};

class Scene : public SurfaceEmission, public MovingTriangles {
public:
    Scene();
    ~Scene();
    Scene(const Scene&) = delete;
    Scene& operator=(const Scene&) = delete;

    // --- building ---------------------------------------------------------------------------------
    uint32_t add_material(Material material);
    // Image textures, referenced by materials through Material::inputs / normal_map.
    uint32_t add_texture(std::shared_ptr<const Texture> texture);
    std::shared_ptr<const Texture> texture(uint32_t id) const;
    // vertices: nv x 3, triangles: nt x 3 indices, corner_normals: nt x 3 x 3 or null, material_index: nt
    // (slot numbers) or null, slot_materials: engine material per slot, corner_uvs: nt x 3 x 2 or null
    // (only textured materials need them). Degenerate triangles, triangles
    // with out-of-range indices and non-finite vertices are dropped and counted (mesh_dropped()).
    uint32_t add_mesh(const float* vertices, size_t nv, const int32_t* triangles, size_t nt,
                      const float* corner_normals, const int32_t* material_index,
                      const std::vector<uint32_t>& slot_materials, const float* corner_uvs = nullptr,
                      const std::vector<AttributeInput>& attributes = {});
    // Deformation motion blur: the mesh's vertices (object space) at `steps` evenly spaced times over
    // the shutter (steps x nv x 3, nv as given to add_mesh), and optionally its corner normals there
    // (steps x nt x 3 x 3, nt and the triangle order as given to add_mesh). Rays see the vertices and normals
    // interpolated linearly in time between the steps (Cycles' motion triangles); add_mesh's
    // vertices stay what untimed queries see. Steps all equal to the first: no motion. Throws
    // std::invalid_argument (the mesh unchanged) for a vertex count other than add_mesh's, fewer
    // than two steps or non-finite values. A deforming emitter's triangle lights follow it.
    void set_mesh_motion(uint32_t mesh, const float* positions, size_t steps, size_t nv,
                         const float* corner_normals = nullptr, size_t nt = 0);
    // Hair: curves through points (np x 4: x, y, z, radius), curve c running from point
    // curve_offsets[c] to curve_offsets[c + 1] - 1 (nc + 1 offsets), rendered as Embree round
    // Catmull-Rom curves (Cycles' 3D curves), all with `material`. Curves with fewer than two points
    // and non-finite points are dropped (counted in mesh_dropped()). Placed by add_instance as a mesh.
    // `first_curve`: the index of curve 0 among its object's hair (Cycles numbers an object's curves
    // across all its particle systems), from which Hair Info's Random is hashed (curves.cpp).
    // `curve_uvs` (nc x 2, or null): each curve's UV, the render UV map at its root on the emitter,
    // constant along the strand (Cycles' ATTR_STD_UV of element CURVE); `attributes`: named values
    // per curve (`corners` nc x dims: UV maps by name, colours), what shader programs read by name.
    uint32_t add_curves(const float* points, size_t np, const int32_t* curve_offsets, size_t nc, uint32_t material,
                        uint32_t first_curve = 0, const float* curve_uvs = nullptr,
                        const std::vector<AttributeInput>& attributes = {});
    // Cycles' "Rounded Ribbons" curve shape for the hair `mesh` (add_curves): Embree flat Catmull-Rom
    // curves, flat strips facing the ray with `subdivisions` + 1 quads per segment (Cycles'
    // rtcSetGeometryTessellationRate), shaded with a normal faked as the round tube's (curve.h).
    void set_curve_ribbons(uint32_t mesh, uint32_t subdivisions);
    // The mesh's texture space (Blender's texspace_location / texspace_size), for Generated coordinates.
    void set_mesh_texspace(uint32_t mesh, const Vec3& location, const Vec3& size);
    // Attribute names are interned: shader programs refer to them by id.
    int32_t attribute_id(const std::string& name);
    uint32_t mesh_dropped(uint32_t mesh) const;
    // Object Info: colour (and its alpha), random in [0, 1) and pass index of the object.
    // holdout: camera rays that meet the instance (directly or through transparent surfaces) end
    // there as a hole in the film (alpha 0, no colour); other rays see it as usual (Cycles).
    // visibility: the ray types that see the instance (ray_visibility.h bits; Cycles' Ray
    // Visibility); its emissive triangles light only what their rays could reach.
    // motion: transform motion blur, the instance's matrices at evenly spaced times over the shutter
    // (none, or at least two; all equal counts as none). Throws std::invalid_argument for a singular
    // step. A moving emitter's triangle lights follow it (MovingTriangles).
    void add_instance(uint32_t mesh, const Transform& to_world, const Color& object_color = Color(1.0f),
                      float random = 0.0f, float pass_index = 0.0f, float object_alpha = 1.0f,
                      bool holdout = false, uint32_t visibility = kRayAllVisibility,
                      const std::vector<Transform>& motion = {});
    bool has_holdout() const { return has_holdout_; }
    // Some object or light is hidden from some ray type (Ray Visibility, a lamp or the World hidden
    // from the camera, a lamp's Multiple Importance off): paths must track their rays' types.
    bool has_ray_visibility() const { return hidden_objects_ || hidden_lights_; }
    uint32_t add_light(const LightDesc& desc);  // throws std::invalid_argument for unusable lights
    void set_world(const Color& radiance);
    // A World program that folded to a constant becomes the uniform WorldLight; any other the
    // EnvironmentLight (its map is built in commit()).
    void set_world(const WorldDesc& world);
    // Homogeneous media, referenced by Material::medium and by the world (-1: no world volume).
    // Throws std::invalid_argument for non-finite or negative coefficients.
    int32_t add_medium(const Medium& medium);
    void set_world_medium(int32_t medium);
    void set_camera(const CameraDesc& desc);
    bool has_camera() const { return has_camera_; }
    void commit();  // builds the BVH and the light-selection table; throws if no camera was set
    // The interactive viewport rebuilds the scene after every edit: a faster, lower-quality BVH
    // build pays off there (Embree's LOW quality: no spatial splits; slower rays).
    void set_fast_build(bool fast) { fast_build_ = fast; }
    // How next-event estimation chooses lights (scene/light_selection.h): the defensive mixture by
    // default, Cycles 3.4's distribution for the setting multiscatter_cycles_walk (the add-on sets it
    // before commit; after commit it rebuilds the table, nothing may be rendering).
    void set_light_selection(LightSelection selection);

    // --- interactive updates (fast-build scenes, after commit; nothing may be rendering) -------
    // Fast-build scenes keep every mesh in its own Embree prototype, so the viewport can move
    // instances and replace one mesh without rebuilding the others. Both return false, changing
    // nothing, when the scene cannot be updated in place (instance count differs, emissive
    // geometry, all triangles dropped): the caller then builds a new scene.
    // rows: n x 3 x 4 floats, the first three rows of each instance's matrix, in add_instance order.
    bool set_instance_transforms(const float* rows, size_t n);
    bool replace_mesh(uint32_t mesh, const float* vertices, size_t nv, const int32_t* triangles, size_t nt,
                      const float* corner_normals, const int32_t* material_index,
                      const std::vector<uint32_t>& slot_materials, const float* corner_uvs = nullptr,
                      const std::vector<AttributeInput>& attributes = {});
    // A material edit: false (nothing changed) when what commit() derived from the material would
    // change (cut-out or not, emissive or not, volumes); emission edits rebuild the light table.
    bool replace_material(uint32_t id, Material material);
    // A lamp or world edit: the lamps (as add_light takes them) and the world radiance replace the
    // old ones; the emissive triangles stay. Throws std::invalid_argument, changing nothing, for an
    // unusable light. The world's volume is not part of it (a new scene).
    bool replace_lights(const std::vector<LightDesc>& lights, const Color& world);
    bool replace_lights(const std::vector<LightDesc>& lights, const WorldDesc& world);

    // --- queries (thread-safe after commit) --------------------------------------------------------
    // The closest surface that ray.visibility sees.
    bool intersect(const Ray& ray, SurfaceHit* hit) const;
    // A shadow ray by default: objects with Ray Visibility > Shadow off do not block it.
    bool occluded(const Vec3& origin, const Vec3& dir, float tmax, float time = kShutterCentre,
                  uint32_t visibility = kRayShadow) const;
    // A visibility mask in the time's place would convert silently: pass the time first.
    bool occluded(const Vec3& origin, const Vec3& dir, float tmax, uint32_t visibility) const = delete;
    // The closest surface of instance `instance` alone (hit.attr.instance of a hit on it), whatever
    // the ray's visibility: subsurface walks inside an object (integrators/subsurface_walk.h).
    // False for instances without subsurface materials (they have no geometry of their own).
    bool intersect_instance(uint32_t instance, const Ray& ray, SurfaceHit* hit) const;
    // Some material has a Subsurface lobe (a BSSRDF closure): hits record their instance.
    bool has_subsurface() const { return has_subsurface_; }
    // Camera rays test the scene's bounding box before the BVH (scene_bounds.h): some of them miss it.
    bool tests_camera_rays_against_bounds() const { return camera_bounds_test_; }
    // Something moves during the shutter (an instance or the camera): camera rays draw a time.
    bool has_motion() const { return has_motion_; }
    // Lights that are not geometry (area, point/spot disks) struck before `ray.tmax`; adds their
    // MIS-weighted contribution through the callback.
    template <class F>
    void for_each_light_hit(const Ray& ray, F&& f) const {
        LightHit h;
        for (uint32_t i : hittable_lights_)
            if (lights_[i]->intersect(ray, &h)) f(i, h);
    }
    const Camera& camera() const { return camera_; }
    // --- shader programs (materials with per-hit node evaluation) ---------------------------------
    // What the program of a hit's material reads, rebuilt from the triangle and its barycentrics.
    ShaderContext shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray, bool full = true) const;
    // Attribute `id` at the context's point into out[0..3]; false when the mesh does not have it.
    bool attribute(const ShaderContext& ctx, int32_t id, float* out) const;
    // The shading of a hit on a material with a program: BSDF (shading normal from the program),
    // emission. `ray` describes the ray that found the hit (Light Path node).
    // *holdout_out (when given): the Holdout closures' weight, on the same footing as the lobes
    // (divided by the cut-out's keep probability).
    Bsdf program_bsdf(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, bool backfacing,
                      const ShaderRay& ray, Vec3* ns_out, Color* holdout_out = nullptr) const;
    // Whether the hit's normals and UV are bit for bit those shader_context() rebuilds for its
    // program: a static triangle mesh (fill_hit deforms and moves the others, the context does not)
    // with a UV map (without, the hit keeps no UV of its own). There a lowered program
    // (Material::image_closure) shades from the hit as the program would.
    bool hit_has_program_frame(const SurfaceHit& hit) const {
        if (!kWithTextures || !hit_ids_) return false;
        const Instance& inst = instances_[hit.attr.instance];
        const Mesh& mesh = meshes_[inst.mesh];
        return !mesh.curves && mesh.motion_steps == 0 && inst.motion.empty() && !mesh.uvs.empty();
    }
    // Emitted radiance at a hit towards wo: constant, textured or from the material's program.
    Color emission_at(const SurfaceHit& hit, const Vec3& wo) const {
        const Material& m = materials_[hit.material];
        return m.program ? program_emission(hit.attr, hit.material, wo) : m.emission_at(hit.attr.uv);
    }
    // SurfaceEmission, for triangle lights whose emission comes from a program.
    Color emission(uint32_t instance, uint32_t prim, uint32_t material, float bu, float bv,
                   const Vec3& wo) const override;
    // MovingTriangles, for the triangle lights of moving and deforming emitters: the corners where
    // the instance's triangle is at `time`, as Embree places it for rays.
    void triangle_at(uint32_t instance, uint32_t prim, float time, Vec3 v[3]) const override;
    const Material& material(uint32_t id) const { return materials_[id]; }
    // Some material's lobes vary over surfaces (textures, object colour): hits' SurfaceAttribs matter.
    bool has_varying_materials() const { return kWithTextures && varying_materials_; }
    // Some material has a shader program: hits must record where they are (SurfaceAttribs'
    // instance, triangle, barycentrics) and paths their Light Path state.
    bool has_programs() const { return kWithTextures && programs_; }
    // The World is a program that varies over directions (an EnvironmentLight): paths keep their
    // Light Path state for it (a backplate seen by camera rays only).
    bool world_has_program() const { return world_desc_.program != nullptr; }
    const std::vector<std::unique_ptr<Light>>& lights() const { return lights_; }
    const Light& light(uint32_t i) const { return *lights_[i]; }
    const DiscreteDistribution& light_selection() const { return light_selection_; }
    float light_pmf(uint32_t i) const { return light_selection_.pmf(i); }
    // Light i's share of the lights' power (light_selection() mixes it with a uniform choice among
    // emitters, scene/light_selection.h).
    float light_power_pmf(uint32_t i) const { return light_power_.pmf(i); }
    // Single scattering's light choice per ray segment in a medium (media_light_choice.h).
    const MediaLightChoice& media_lights() const { return media_lights_; }
    // Point and spot lights without radius inside scattering media (glow_lights.h); empty without.
    const std::vector<GlowLight>& glow_lights() const { return glow_lights_; }
    const std::vector<uint32_t>& infinite_lights() const { return infinite_lights_; }
    const SceneStats& stats() const { return stats_; }
    // What the scene analysis found unused after commit(), for the stats line ("skipped: ...").
    // Features add their entries here (e.g. "NEE (no lights)").
    const std::vector<std::string>& skipped() const { return skipped_; }
    // Spectral data: per light (same indices as lights()), and whether anything in the scene needs
    // spectral rendering (an emitter with a spectrum, a measured metal, a dispersive glass).
    const EmitterSource& emitter_source(uint32_t light) const { return emitter_sources_[light]; }
    size_t material_count() const { return materials_.size(); }
    bool has_spectral_content() const { return spectral_content_; }
    // Media: false when no material has a volume or is a pass-through boundary and the world has no
    // volume; integrators then take their surface-only code paths.
    bool has_media() const { return kWithVolumes && has_media_; }
    const Medium& medium(int32_t id) const { return media_[id]; }
    size_t medium_count() const { return media_.size(); }
    int32_t world_medium() const { return world_medium_; }
    int32_t camera_medium() const { return camera_medium_; }
    // The medium containing point p (by walking a ray out of the scene; nested media are not
    // supported: leaving any volume object returns to the world medium).
    int32_t medium_at(const Vec3& p) const;
    // The geometry's bounding sphere (centre of its box, half its diagonal), for lengths that must
    // cover the scene.
    Vec3 center() const { return center_; }
    float radius() const { return radius_; }
    // Where light can scatter: the bounding box of the volume objects whose medium scatters (empty
    // when none, lo > hi), and whether the world's volume scatters (then everywhere).
    struct ScatteringRegion {
        Vec3 lo{kInf}, hi{-kInf};
        bool everywhere = false;
        bool empty() const { return !everywhere && !(lo.x <= hi.x); }
    };
    const ScatteringRegion& scattering_region() const { return scattering_; }
    // The planes of the pass-through boundaries seen by shadow rays (boundary_planes.h).
    const BoundaryPlanes& boundary_planes() const { return boundary_planes_; }
    RTCDevice device() const { return device_; }

private:
    struct MeshAttribute {
        int32_t id;
        int dims;
        std::vector<float> corners;  // 3 x dims per (kept) triangle; dims per input curve on hair
    };
    struct Mesh {
        std::vector<float> positions;        // 3 floats per vertex (object space; world when flattened)
        std::vector<uint32_t> indices;       // 3 per triangle
        std::vector<Vec3> corner_normals;    // 3 per triangle, or empty for flat shading
        std::vector<uint32_t> materials;     // per triangle, engine material id
        std::vector<Point2> uvs;             // 3 per triangle, or empty
        std::vector<MeshAttribute> attributes;
        // Deformation motion blur (set_mesh_motion): motion_steps vertex arrays of 3 floats per vertex
        // back to back (one float3 of padding at the end, as positions), and 3 normals per kept
        // triangle per step when corner_normals is not empty; 0 steps: the mesh does not deform.
        uint32_t motion_steps = 0;
        std::vector<float> motion_positions;
        std::vector<Vec3> motion_normals;
        size_t input_triangles = 0;          // nt as given to add_mesh
        std::vector<uint32_t> kept;          // input triangle of each kept triangle (empty: none dropped)
        Vec3 texspace_location{0.0f}, texspace_size{1.0f};
        uint32_t dropped = 0;
        uint32_t users = 0;
        RTCScene prototype = nullptr;        // when instanced more than once
        const Scene* owner = nullptr;        // for the cut-out filter, which gets only the mesh
        // Hair (add_curves): control points x, y, z, radius, each curve's ends doubled as Cycles
        // does for Catmull-Rom; `indices` then holds each segment's first control point and
        // `materials` one id per segment, `segment_curves` the index of each segment's curve in its
        // object's hair (add_curves' first_curve + c, dropped curves counted).
        // `curve_intercepts` Hair Info's Intercept at each control point and `segment_lengths` its
        // Length per segment (Cycles' ATTR_STD_CURVE_INTERCEPT / _LENGTH: the polyline through the
        // points, in object space).
        bool curves = false;
        std::vector<float> curve_points;
        std::vector<uint32_t> segment_curves;
        std::vector<float> curve_intercepts;
        std::vector<float> segment_lengths;
        // Per input curve (index segment_curves - first_curve): its UV (empty without), and
        // `attributes` hold dims values per curve instead of per corner.
        uint32_t first_curve = 0;
        std::vector<Point2> curve_uvs;
        uint32_t ribbon_rate = 0;  // set_curve_ribbons: quads per segment; 0: round curves
        // The input curve (add_curves' index) of segment `prim`: where its UV and attributes are.
        size_t input_curve(uint32_t prim) const { return segment_curves[prim] - first_curve; }
    };
    // Hair (curves.cpp): rays leaving a hair ignore the curve they start on (Cycles' self skip);
    // the Embree geometry; a sole user's curves moved into world space; a hit and what its program reads.
    static void curve_self_filter(const struct RTCFilterFunctionNArguments* args);
    void build_curve_geometry(RTCScene target, Mesh& mesh, unsigned id, uint32_t visibility);
    static void flatten_curves(Mesh& mesh, const Transform& to_world);
    [[gnu::noinline]] void fill_curve_hit(const Ray& ray, const struct RTCRayHit& rh, uint32_t instance,
                                          SurfaceHit* hit) const;
    ShaderContext curve_shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray) const;
    // shader_context() of a triangle: one local returned, so the context is built in the caller's
    // slot (with the curves' return beside it, it was built in a local and copied out: 376 bytes).
    ShaderContext triangle_shader_context(const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                                          bool full) const;
    static void cutout_filter(const struct RTCFilterFunctionNArguments* args);
    struct Instance {
        uint32_t mesh;
        Transform to_world;
        bool identity;         // flattened into world space
        int32_t light_base;    // first triangle light of this instance, -1 if none emit
        Color object_color;
        Transform to_object;   // inverse of to_world (Object texture coordinates)
        float random = 0.0f, pass_index = 0.0f, alpha = 1.0f;
        bool holdout = false;
        std::vector<Transform> motion;  // transform motion blur steps, empty when it does not move
        RTCGeometry geometry = nullptr; // the Embree instance of a moving one, for its transform at a time
        uint32_t visibility = kRayAllVisibility;  // the Embree mask of its geometry
        RTCScene own = nullptr;  // its geometry alone, for subsurface walks (subsurface materials only)
    };
    // The shader inputs an instance gives every hit on it (transforms, Object Info), for meshes and curves alike.
    static void set_object_inputs(const Instance& inst, ShaderContext* c);
    // The Embree geometry of `inst` (its mesh, flattened or instanced) into `target` under geom_id.
    void attach_instance_geometry(RTCScene target, Instance& inst, unsigned geom_id, bool own);
    // The context a material's program reads at a hit for `outputs`: its basic part only where the
    // program reads no more (ShaderProgram::needs_full_context).
    ShaderContext program_context(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                                  ShaderOutputs outputs = ShaderOutputs::All) const;
    // Runs a material's program for `outputs` in `ctx`, or in the context it builds for the hit.
    ShaderResult run_program(uint32_t material, const ShaderContext& ctx, ShaderOutputs outputs = ShaderOutputs::All) const;
    ShaderResult run_program(uint32_t material, const SurfaceAttribs& at, const Vec3& wo, const ShaderRay& ray,
                             ShaderOutputs outputs = ShaderOutputs::All) const;
    Color program_emission(const SurfaceAttribs& at, uint32_t material, const Vec3& wo) const;
    // Cut-out filter for program materials: 1 - the grey part of the transparency at the hit.
    float program_keep(uint32_t instance, uint32_t prim, float bu, float bv, const Vec3& dir) const;
    Vec3 apply_normal_map(const Material& mat, const Mesh& mesh, const Instance& inst, uint32_t prim,
                          const Vec3& ns, const Vec3& ng, Point2 uv) const;
    void build_mesh_geometry(RTCScene target, Mesh& mesh, unsigned id, uint32_t visibility = kRayAllVisibility);
    Mesh make_mesh(const float* vertices, size_t nv, const int32_t* triangles, size_t nt, const float* corner_normals,
                   const int32_t* material_index, const std::vector<uint32_t>& slot_materials,
                   const float* corner_uvs) const;
    void build_prototype(Mesh& mesh);
    // The named corner attributes of the triangles make_mesh kept.
    void attach_attributes(Mesh& mesh, const std::vector<AttributeInput>& attributes);
    bool emissive(const Mesh& mesh) const;
    RTCBuildQuality build_quality() const { return fast_build_ ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_HIGH; }
    void add_triangle_lights(Instance& inst);
    static void sanitize(Material& material);
    void rebuild_lights();
    void finish_lights();  // world light, selection table, spectral flag: the end of commit()
    void find_glow_lights(const std::vector<float>& power);  // glow_lights_, at the end of finish_lights
    // light_selection_ for light_selection_mode_ from the lights' powers and emitters (finish_lights).
    void build_light_selection();
    void update_spectral_content();
    void set_skipped(const char* what, bool skipped);  // adds or removes a skipped() entry
    void update_skipped();
    void fill_hit(const Ray& ray, const struct RTCRayHit& rh, SurfaceHit* hit) const;
    // A deforming mesh's triangle corners (v) and corner normals (n, when it has them) at `time`.
    static void deformed_triangle(const Mesh& mesh, uint32_t prim, float time, Vec3 v[3], Vec3 n[3]);
    // The hit point at barycentrics (u, v) of a deforming mesh's triangle at `time`, its geometric
    // and shading normals (unnormalised). Out of line and returned by value: meshes that do not
    // deform do not pay for it (written through pointers, the three lived in memory at every hit:
    // fill_hit +18% instructions, cornell +0.8%).
    struct HitFrame {
        Vec3 p, ng, ns;
    };
    [[gnu::noinline]] static HitFrame deformed_point(const Mesh& mesh, uint32_t prim, float time, float u, float v);
    // The UV and normal-map part of fill_hit, for meshes with UVs (textured materials).
    [[gnu::noinline]] void fill_uv_attribs(const Mesh& mesh, const Instance& inst, uint32_t prim, float u, float v,
                                           SurfaceHit* hit) const;

    std::string embree_error_;
    RTCDevice device_ = nullptr;
    RTCScene scene_ = nullptr;
    std::vector<Material> materials_;
    std::vector<std::shared_ptr<const Texture>> textures_;
    std::vector<Mesh> meshes_;
    std::vector<Instance> instances_;
    bool has_holdout_ = false, has_motion_ = false;
    bool hidden_objects_ = false, hidden_lights_ = false;  // has_ray_visibility()
    std::vector<uint32_t> geom_to_instance_;       // top-level geometry id -> instance
    std::vector<std::vector<int32_t>> emissive_local_;  // per mesh: triangle -> local emitter index
    std::vector<std::unique_ptr<Light>> lights_;
    std::vector<LightDesc> light_descs_;  // the lamps as added, for replace_lights / rebuild_lights
    std::vector<EmitterSource> emitter_sources_;
    bool spectral_content_ = false;
    std::vector<uint32_t> hittable_lights_, infinite_lights_;
    DiscreteDistribution light_selection_, light_power_;
    LightSelection light_selection_mode_ = LightSelection::Defensive;
    std::vector<float> light_powers_;      // per light, as finish_lights found them
    std::vector<uint32_t> light_emitters_;  // per light: its emitter for the defensive mixture
    MediaLightChoice media_lights_;
    std::vector<GlowLight> glow_lights_;
    Camera camera_;
    bool has_camera_ = false, committed_ = false, fast_build_ = false, varying_materials_ = false, programs_ = false;
    bool has_subsurface_ = false;
    bool hit_ids_ = false;  // hits record instance, triangle and barycentrics (programs, subsurface)
    Color world_{0.0f};  // the constant World's radiance (also a program that folded to a constant)
    WorldDesc world_desc_;  // the program, map size and visibility
    std::vector<Medium> media_;
    int32_t world_medium_ = -1, camera_medium_ = -1;
    bool has_media_ = false;
    float radius_ = 1.0f;
    Vec3 center_{0.0f};
    SceneBounds bounds_;               // the BVH's bounds, padded (scene_bounds.h)
    bool camera_bounds_test_ = false;  // camera rays test bounds_ before the BVH
    void update_camera_bounds_test();
    ScatteringRegion scattering_;
    BoundaryPlanes boundary_planes_;
    // The Embree mask of an instance's geometry: its visibility, with kRayShadowSurface when shadow
    // rays see it and some triangle of `mesh` has a surface. boundary_planes_ from the instances.
    uint32_t geometry_mask(const Mesh& mesh, uint32_t visibility) const;
    void update_boundary_planes();
    SceneStats stats_;
    std::vector<std::string> skipped_;
    std::vector<std::string> attribute_names_;
};

}  // namespace smis
