"""Transform motion blur: the camera's and the objects' matrices over the shutter, taken as Cycles 3.4
takes them (intern/cycles/blender/sync.cpp, sync_motion; util.h, object_motion_steps).

Cycles evaluates the scene again at the shutter's times around the frame and keeps each object's
matrix there; the engine interpolates between these steps (scene/motion.h) and gives every camera
sample a time in the shutter. Deformation motion blur as Cycles' sync_mesh_motion takes it: the
evaluated mesh's vertices (and corner normals) at the object's own step times, linear in time between
them in the engine; a mesh whose vertex count changes over the shutter renders without it (named in
a warning). Moving and deforming emitters are blurred, their light samples taken at the path's
time in the engine; lamps do not move (Cycles 3.4's lights have one transform).
"""

import math

import numpy as np

from .camera import camera_object
from .instances import GEOMETRY_TYPES, instance_matrix

# Objects whose transform can blur: meshes (their particle hair with them) and Curves objects (hair
# curves; only meshes deform here).
MOVING_TYPES = GEOMETRY_TYPES | {'CURVES'}
from .mesh import mesh_buffers

RAMP_TABLE_SIZE = 256   # Cycles' resolution of the shutter curve


def motion_steps(obj, parent=None):
    """Cycles' object_motion_steps: 0 when the object (or its instancer) turns motion blur off,
    else 2^(motion_steps - 1) + 1 evenly spaced steps, an odd count so one falls on the frame."""
    def settings(o):
        c = getattr(o, "cycles", None)
        return (bool(getattr(c, "use_motion_blur", True)), int(getattr(c, "motion_steps", 1))) if c else (True, 1)
    use, steps = settings(obj)
    if parent is not None and parent != obj:
        parent_use, parent_steps = settings(parent)
        use, steps = use and parent_use, max(steps, parent_steps)
    if not use:
        return 0
    return (2 << (max(1, steps) - 1)) + 1


def relative_times(steps):
    """The steps' times in the shutter, from -1 (open) to 1 (close)."""
    return [-1.0 + 2.0 * i / (steps - 1) for i in range(steps)]


def instance_key(inst):
    """What identifies a depsgraph instance from one evaluation of the scene to the next."""
    obj = inst.object.original
    if not inst.is_instance:
        return ("", obj.name_full, ())
    parent = inst.parent.original.name_full if inst.parent is not None else ""
    return (parent, obj.name_full, tuple(inst.persistent_id))


def _may_deform(obj):
    """The object's mesh may change over the shutter (deforming modifiers or animated shape keys) and
    Cycles would blur that (its Deformation option is on)."""
    original = obj.original
    cycles = getattr(original, "cycles", None)
    if cycles is not None and not getattr(cycles, "use_deform_motion", True):
        return False
    keys = getattr(original.data, "shape_keys", None)
    if keys is not None and keys.animation_data is not None:
        return True
    if getattr(original.data, "animation_data", None) is not None:
        return True  # keyed vertex positions (or other mesh data)
    return any(m.type in {'ARMATURE', 'CAST', 'CURVE', 'DISPLACE', 'HOOK', 'LATTICE', 'MESH_DEFORM', 'SHRINKWRAP',
                          'SIMPLE_DEFORM', 'SMOOTH', 'SURFACE_DEFORM', 'WARP', 'WAVE', 'CLOTH', 'SOFT_BODY',
                          'OCEAN', 'NODES'} and m.show_render for m in original.modifiers)


def _deformed_mesh(obj):
    """(vertices (N, 3), triangles (M, 3), corner normals (M, 3, 3) or None) of the evaluated object,
    through the export's own mesh_buffers, so every step matches what the frame's export gives."""
    mesh = obj.to_mesh()
    try:
        buf = mesh_buffers(mesh, 1)
        return buf.vertices, buf.triangles, buf.corner_normals
    finally:
        obj.to_mesh_clear()


def _deformation(found, steps):
    """The steps' (positions, normals) of a deforming mesh, or a reason it has none: 'static' (no
    vertex moves), 'topology' (the vertices or triangles change over the shutter)."""
    rels = relative_times(steps)
    if any(r not in found for r in rels):
        return 'static'
    meshes = [found[r] for r in rels]
    vertices, triangles, normals = meshes[0]
    if any(len(v) != len(vertices) or not np.array_equal(t, triangles) or (n is None) != (normals is None)
           for v, t, n in meshes[1:]):
        return 'topology'
    positions = np.stack([v for v, _, _ in meshes])
    if np.array_equal(positions.min(axis=0), positions.max(axis=0)):
        return 'static'
    return positions, (np.stack([n for _, _, n in meshes]) if normals is not None else None)


def shutter_curve(render):
    """The shutter curve at RAMP_TABLE_SIZE times over the shutter, or None when it is flat."""
    mapping = render.motion_blur_shutter_curve
    mapping.initialize()
    curve = mapping.curves[0]
    values = [max(0.0, float(mapping.evaluate(curve, i / (RAMP_TABLE_SIZE - 1)))) for i in range(RAMP_TABLE_SIZE)]
    if max(values) - min(values) < 1e-6:
        return None
    if max(values) <= 0.0:
        return None
    return values


class Motion:
    """The matrices of what moves over the shutter: `camera` (steps x 4 x 4 or None) and, per
    instance key, the steps of the instances that move (`of(inst)`)."""

    def __init__(self, camera=None, instances=None, shutter_curve_values=None, deforming=None):
        self.restore = lambda: None  # back to the frame from the shutter's centre
        self.camera = camera
        self.instances = instances or {}
        self.shutter_curve = shutter_curve_values
        # object name -> (positions (steps, N, 3), corner normals (steps, M, 3, 3) or None)
        self.deforming = deforming or {}

    def of(self, inst):
        return self.instances.get(instance_key(inst))

    def deformation_of(self, inst):
        """Scene.set_mesh_motion's arguments for the instance's mesh, or None when it does not deform."""
        return None if inst.is_instance else self.deforming.get(inst.object.original.name_full)

    def camera_fields(self):
        fields = {}
        if self.camera is not None:
            fields["motion"] = self.camera
        if self.shutter_curve is not None:
            fields["shutter_curve"] = self.shutter_curve
        return fields


def collect(engine, depsgraph, warn):
    """Evaluate the scene at the shutter's step times and return a Motion, or None when the render
    has no motion blur (turned off, previews, the viewport). Leaves the scene at the shutter's centre
    (Cycles exports everything that does not move there: with the shutter starting or ending at the
    frame, a still object stands where it is half a shutter later or earlier); Motion.restore()
    returns it to its frame."""
    scene = depsgraph.scene
    render = scene.render
    if engine is None or engine.is_preview or not render.use_motion_blur:
        return None
    shutter = float(render.motion_blur_shutter)
    if not shutter > 0.0:
        return None
    cycles = getattr(scene, "cycles", None)
    position = getattr(cycles, "motion_blur_position", 'CENTER')
    if getattr(cycles, "rolling_shutter_type", 'NONE') != 'NONE':
        warn("Rolling shutter is not supported; motion blur renders with a global shutter")
    # Cycles' frame_center_delta: the shutter opens at the frame (START) or closes there (END).
    delta = {'START': 0.5 * shutter, 'END': -0.5 * shutter}.get(position, 0.0)
    frame, subframe = scene.frame_current, scene.frame_subframe

    wanted = {}      # instance key -> steps
    deforming = {}   # object name -> (original object, steps), for the objects whose mesh may deform
    cam_obj = camera_object(engine, scene)
    for inst in depsgraph.object_instances:
        obj = inst.object
        if obj.type not in MOVING_TYPES:
            continue
        steps = motion_steps(obj.original, inst.parent.original if inst.is_instance and inst.parent else None)
        if steps:
            wanted[instance_key(inst)] = steps
            if not inst.is_instance and obj.type in GEOMETRY_TYPES and _may_deform(obj):
                deforming[obj.original.name_full] = (obj.original, steps)
    camera_steps = motion_steps(cam_obj) if cam_obj is not None else 0

    times = sorted({t for n in set(wanted.values()) | ({camera_steps} if camera_steps else set())
                    for t in relative_times(n)})
    seen = {key: {} for key in wanted}
    camera_seen = {}
    meshes = {name: {} for name in deforming}  # relative time -> _deformed_mesh
    try:
        for rel in times:
            t = frame + subframe + delta + rel * 0.5 * shutter
            whole = math.floor(t)
            engine.frame_set(int(whole), t - whole)
            for inst in depsgraph.object_instances:
                if inst.object.type in MOVING_TYPES:
                    entry = seen.get(instance_key(inst))
                    if entry is not None:
                        entry[rel] = instance_matrix(inst)
            if camera_steps:
                camera_seen[rel] = np.array(cam_obj.evaluated_get(depsgraph).matrix_world, dtype=np.float64)
            for name, (original, steps) in deforming.items():
                if rel in relative_times(steps):
                    meshes[name][rel] = _deformed_mesh(original.evaluated_get(depsgraph))
    finally:
        centre = frame + subframe + delta
        engine.frame_set(int(math.floor(centre)), centre - math.floor(centre))

    def steps_of(found, steps):
        """The matrices at the object's own step times, or None when it is missing at one of them or
        does not move."""
        rels = relative_times(steps)
        if any(r not in found for r in rels):
            return None
        mats = np.stack([found[r] for r in rels])
        return mats if np.any(mats != mats[0]) else None

    instances = {}
    for key, steps in wanted.items():
        mats = steps_of(seen[key], steps)
        if mats is not None:
            instances[key] = mats
    deformation = {name: _deformation(meshes[name], steps) for name, (_, steps) in deforming.items()}
    changing = sorted(name for name, d in deformation.items() if d == 'topology')
    if changing:
        # Cycles (sync_mesh_motion) drops the deformation of such a mesh too, in its log only.
        shown = ", ".join("'%s'" % n for n in changing[:10])
        warn("No deformation motion blur for %s: the mesh topology changes over the shutter" % shown)
    camera = steps_of(camera_seen, camera_steps) if camera_steps else None
    motion = Motion(camera, instances, shutter_curve(render),
                    {name: d for name, d in deformation.items() if not isinstance(d, str)})
    motion.restore = lambda: engine.frame_set(frame, subframe) if delta else None
    return motion
