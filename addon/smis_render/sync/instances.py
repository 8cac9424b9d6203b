"""Depsgraph object instances -> engine meshes, instances and lights.

Every renderable thing, real object or instance (collection instances,
particles, geometry-nodes instances), comes out of `depsgraph.object_instances`.
Meshes are exported once per *prototype* and placed by `add_instance`, so a
collection instanced 100 times costs one mesh export per object in it.
"""

from dataclasses import dataclass

import numpy as np

from . import hair, lights
from .mesh import mesh_buffers
from .visibility import instance_ray_visibility

# Geometry reaches the engine as Mesh data only. In Blender 3.4 curves, text, NURBS
# surfaces and metaballs are evaluated to a geometry set: the depsgraph yields the
# CURVE/FONT/SURFACE/META object itself (its data is a Curve/MetaBall) AND a separate
# MESH instance carrying the evaluated mesh (checked with `object_instances` on 3.4.1).
# Exporting both would render them twice, so only instances whose object is a MESH
# are exported, each through `to_mesh()` (Cycles' `object_is_geometry` does the same).
GEOMETRY_TYPES = {'MESH'}
# Skipped without a warning: their geometry comes as a MESH instance (see above), or
# they never render.
_SILENT_TYPES = {'CURVE', 'FONT', 'SURFACE', 'META', 'CAMERA', 'EMPTY', 'LIGHT_PROBE',
                 'SPEAKER', 'ARMATURE', 'LATTICE'}

# How often (in instances) the export asks Blender whether the user cancelled.
_BREAK_CHECK_EVERY = 256


class Cancelled(Exception):
    pass


@dataclass
class ExportCounts:
    meshes: int = 0          # prototypes added to the engine
    instances: int = 0       # add_instance calls
    lights: int = 0
    dropped_lights: int = 0
    dropped_triangles: int = 0
    dropped_curves: int = 0


def _prototype_key(obj):
    """What identifies the geometry of an (evaluated) object.

    For meshes, the evaluated mesh datablock: every instance of an object shares it
    (the depsgraph hands instances a temporary object whose `data` is the source's
    evaluated mesh), and so do objects sharing an unmodified mesh (linked
    duplicates), while a modifier gives an object its own evaluated mesh. The
    material slots are part of the key because they may be linked to the object
    rather than to the data.
    """
    data_ptr = obj.data.as_pointer() if obj.data is not None else 0
    materials = tuple(slot.material.name_full if slot.material else None
                      for slot in obj.material_slots)
    return (data_ptr, materials)


def _material_ids(obj, mesh, materials):
    mats = [slot.material for slot in obj.material_slots]
    if not mats:
        # Geometry-nodes instances may carry materials on the mesh only.
        mats = list(mesh.materials)
    if not mats:
        mats = [None]  # no material at all: our explicit default grey, not the engine's
    return [materials.id_for(m) for m in mats]


class GeometryCache:
    """Mesh buffers kept between exports (the interactive viewport), keyed by object identity:
    the original object's and mesh's names, not the evaluated datablocks, which Blender may
    re-create or reuse at every evaluation. Entries are dropped when the depsgraph reports a
    geometry update of the object or its mesh, so an edit re-exports only that object."""

    def __init__(self):
        self._entries = {}   # key -> MeshBuffers
        self.exported = 0    # meshes taken from Blender (to_mesh + foreach_get) since creation
        # What the last full export made of each object: engine mesh ids by object identity, and
        # the identities and object colours of the engine's instances in order (for in-place
        # viewport updates).
        self.mesh_ids = {}
        self.instance_keys = []

    @staticmethod
    def identity(obj):
        data = obj.data.original if obj.data is not None else None
        return obj.original.name_full, data.name_full if data is not None else ""

    @staticmethod
    def instance_key(key, obj, visibility):
        """What an instance of `key` was added with beyond its matrix: a new object colour or Ray
        Visibility needs a new scene (the viewport updates matrices and meshes only)."""
        return key, tuple(obj.color[:3]), tuple(sorted(visibility.items())) if visibility else None

    def record_instance(self, obj, mesh_id, visibility=None):
        key = self.identity(obj)
        self.mesh_ids[key] = mesh_id
        self.instance_keys.append(self.instance_key(key, obj, visibility))

    def start_export(self):
        self.mesh_ids, self.instance_keys = {}, []

    @classmethod
    def key(cls, obj, surface_data):
        """The cache key of an object's mesh exported with `surface_data` (its UV map and tangents)."""
        return cls.identity(obj) + (surface_data,)

    def get(self, key):
        return self._entries.get(key)

    def put(self, key, value):
        self._entries[key] = value

    def invalidate(self, object_name=None, data_name=None):
        for key in [k for k in self._entries if k[0] == object_name or k[1] == data_name]:
            del self._entries[key]

    def __len__(self):
        return len(self._entries)


def mesh_of(obj, materials, cache):
    """(MeshBuffers or None, engine material ids) of an evaluated object, from the cache when
    it holds them."""
    mat_ids = _material_ids(obj, obj.data, materials)
    uv_map = materials.uv_map_for(mat_ids)
    derived = materials.derived_attributes_for(mat_ids)
    key = cache.key(obj, (uv_map, derived)) if cache is not None else None
    if key is not None and cache.get(key) is not None:
        return cache.get(key), mat_ids
    mesh = obj.to_mesh()
    if mesh is None:
        return None, mat_ids
    try:
        buf = mesh_buffers(mesh, len(mat_ids), uv_map, derived, materials.warning, obj.name) \
            if len(mesh.polygons) else None
    finally:
        obj.to_mesh_clear()
    if key is not None and buf is not None:
        cache.exported += 1
        cache.put(key, buf)
    return buf, mat_ids


def _export_prototype(obj, scene, materials, counts, cache=None):
    """Add the geometry of an evaluated object to the engine; mesh id or None if empty."""
    buf, mat_ids = mesh_of(obj, materials, cache)
    if buf is None or buf.triangle_count == 0:
        return None
    if buf.corner_uvs is None and materials.uv_map_for(mat_ids) is not None:
        materials.warning("Object '%s' has textured materials but no UV map; textures read "
                          "their bottom-left texel" % obj.name)
    mesh_id = scene.add_mesh(buf.vertices, buf.triangles, buf.corner_normals,
                             buf.material_index, mat_ids, buf.corner_uvs, buf.attributes or {})
    if buf.texspace is not None:
        scene.set_mesh_texspace(mesh_id, buf.texspace[0], buf.texspace[1])
    counts.meshes += 1
    counts.dropped_triangles += scene.mesh_dropped(mesh_id)
    return mesh_id


def instance_matrix(inst):
    # inst.matrix_world is only valid during this iteration step: copy it out now.
    # Going through row tuples is 4x faster than np.array(Matrix) (2 vs 9 us), which
    # matters with 100k+ instances.
    m = inst.matrix_world.copy()
    return np.array([m[0][:], m[1][:], m[2][:], m[3][:]], dtype=np.float64)


def walk_instances(depsgraph, reporter, test_break=None):
    """The depsgraph's renderable instances as ('LIGHT', 'MESH', 'HAIR' (a mesh's particle hair) or
    'CURVES', instance, object), in the
    order the engine receives them; unsupported object types are warned about once."""
    unsupported = set()   # object types already warned about
    for i, inst in enumerate(depsgraph.object_instances):
        if test_break is not None and i % _BREAK_CHECK_EVERY == 0 and test_break():
            raise Cancelled()
        obj = inst.object
        obj_type = obj.type
        if obj_type == 'LIGHT':
            yield 'LIGHT', inst, obj
            continue
        if obj_type == 'CURVES':
            yield 'CURVES', inst, obj
            continue
        if obj_type == 'MESH' and not inst.is_instance and hair.particle_hair_systems(obj):
            yield 'HAIR', inst, obj  # the hair renders whether or not its emitter does
        if obj_type not in GEOMETRY_TYPES:
            if obj_type not in _SILENT_TYPES and obj_type not in unsupported:
                unsupported.add(obj_type)
                reporter.warning("Objects of type %s are not supported (first: '%s'), skipped"
                                 % (obj_type, obj.name))
            continue
        if not inst.is_instance and not inst.show_self:
            continue  # an instancer (particles, instancing faces) set not to render itself
        if obj_type == 'MESH' and obj.data is None:
            continue
        yield 'MESH', inst, obj


def is_holdout(inst, view_layer):
    """Object > Visibility > Holdout, or a holdout collection of the view layer, as Cycles reads it
    (an instance takes its instancer's)."""
    owner = inst.parent if inst.is_instance and inst.parent is not None else inst.object
    owner = getattr(owner, "original", owner)
    try:
        return bool(owner.holdout_get(view_layer=view_layer))
    except (AttributeError, TypeError, RuntimeError):
        return bool(getattr(owner, "is_holdout", False))


def export_instances(depsgraph, scene, materials, reporter, test_break=None, cache=None, motion=None):
    """Add all geometry and lights of the depsgraph to the engine scene; `cache`
    (GeometryCache) reuses meshes exported before and records which engine mesh and
    instances each object became; `motion` (sync.motion.Motion) the matrices of the instances
    that move over the shutter."""
    counts = ExportCounts()
    prototypes = {}   # prototype key -> engine mesh id, or None for empty geometry
    singular, broken = [], []  # objects skipped (the rest of the scene still renders)
    unblurred = []  # motion the engine refused (a singular step, unusable vertices): rendered without it
    for kind, inst, obj in walk_instances(depsgraph, reporter, test_break):
        if kind == 'LIGHT':
            if lights.export_light(scene, obj, instance_matrix(inst), reporter):
                counts.lights += 1
            else:
                counts.dropped_lights += 1
            continue
        if kind in ('HAIR', 'CURVES'):
            try:
                _export_hair(kind, inst, obj, scene, materials, counts, depsgraph.view_layer,
                             hair.ribbon_subdivisions(depsgraph.scene),
                             motion.of(inst) if motion is not None else None, unblurred)
            except (RuntimeError, ValueError, TypeError) as exc:
                broken.append("%s (%s)" % (obj.name, exc))
            continue
        key = _prototype_key(obj)
        if key in prototypes:
            mesh_id = prototypes[key]
        else:
            try:
                mesh_id = _export_prototype(obj, scene, materials, counts, cache)
            except (RuntimeError, ValueError, TypeError) as exc:
                broken.append("%s (%s)" % (obj.name, exc))
                mesh_id = None
            prototypes[key] = mesh_id
            deformation = motion.deformation_of(inst) if motion is not None and mesh_id is not None else None
            if deformation is not None:
                try:
                    scene.set_mesh_motion(mesh_id, *deformation)
                except ValueError as exc:
                    unblurred.append("'%s' (%s)" % (obj.name, exc))
        if mesh_id is not None:
            # Object Info: Cycles' random is the instance's random_id over 2^32, the pass index
            # the object's.
            steps = motion.of(inst) if motion is not None else None
            visibility = instance_ray_visibility(inst)
            args = (mesh_id, instance_matrix(inst), obj.color[:], (inst.random_id & 0xFFFFFFFF) / 4294967295.0,
                    float(obj.pass_index), is_holdout(inst, depsgraph.view_layer), visibility)
            try:
                _add_moving_instance(scene, args, steps, obj.name, unblurred)
            except ValueError:
                # A zero scale (a common way to hide an object in an animation) or a non-finite
                # transform: Cycles renders nothing of the object either.
                singular.append(obj.name)
                continue
            counts.instances += 1
            if cache is not None:
                cache.record_instance(obj, mesh_id, visibility)
    _warn_skipped(reporter, singular, "with a zero-scale, singular or non-finite transform")
    _warn_skipped(reporter, broken, "whose geometry could not be exported")
    if unblurred:
        reporter.warning("Rendered without motion blur: " + ", ".join(unblurred[:10])
                         + (" and %d more" % (len(unblurred) - 10) if len(unblurred) > 10 else ""))
    return counts


def _add_moving_instance(scene, args, steps, name, unblurred):
    """Scene.add_instance with the motion `steps` (or None); motion the engine refuses (a singular
    step) is dropped and the object named in `unblurred`. A still instance's ValueError propagates."""
    try:
        scene.add_instance(*args, motion=steps)
    except ValueError as exc:
        if steps is None:
            raise
        scene.add_instance(*args)
        if unblurred is not None:
            unblurred.append("'%s' (%s)" % (name, exc))


def _export_hair(kind, inst, obj, scene, materials, counts, view_layer, ribbons=None, steps=None, unblurred=None):
    """A mesh's particle hair or a Curves object as engine curves, one instance per hair system;
    `steps`: the object's matrices over the shutter (transform motion blur, as Cycles blurs a hair
    object's transform), or None."""
    if kind == 'HAIR':
        systems = [(hair.particle_strands(obj, p), hair.particle_material(obj, p),
                    lambda uv_map, p=p: hair.particle_uvs(obj, p, uv_map)) for p in hair.particle_hair_systems(obj)]
    else:
        systems = [(hair.curves_strands(obj.data), hair.curves_material(obj), lambda uv_map: hair.curves_uvs(obj.data))]
    first_curve = 0  # Cycles numbers an object's strands across its particle systems (Hair Info's Random)
    for (points, offsets), material, strand_uvs in systems:
        if len(offsets) < 2:
            continue
        mat_id = materials.id_for(material)
        uv_map = materials.uv_map_for([mat_id])
        uvs, attributes = strand_uvs(uv_map) if uv_map is not None else (None, {})
        mesh_id = scene.add_curves(points, offsets, mat_id, first_curve, uvs, attributes)
        if ribbons is not None:
            scene.set_curve_ribbons(mesh_id, ribbons)
        first_curve += len(offsets) - 1
        counts.meshes += 1
        counts.dropped_curves += scene.mesh_dropped(mesh_id)
        args = (mesh_id, instance_matrix(inst), obj.color[:], (inst.random_id & 0xFFFFFFFF) / 4294967295.0,
                float(obj.pass_index), is_holdout(inst, view_layer), instance_ray_visibility(inst))
        _add_moving_instance(scene, args, steps, obj.name, unblurred)
        counts.instances += 1


def _warn_skipped(reporter, names, why):
    if not names:
        return
    shown = ", ".join("'%s'" % n for n in names[:10]) + (" and %d more" % (len(names) - 10) if len(names) > 10 else "")
    reporter.warning("Skipped %d object%s %s: %s; the rest of the scene renders"
                     % (len(names), "" if len(names) == 1 else "s", why, shown))
