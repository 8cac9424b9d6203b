"""The interactive viewport's side of the sync: the 3D view as a camera, and which
objects an edit invalidates.

Blender calls view_update() after every edit with the depsgraph's list of updated
datablocks; only objects whose geometry changed are exported again, every other mesh
comes from the GeometryCache (keyed by object identity, like Cycles' BlenderSync).
Moves, mesh edits, material edits and lamp/world edits update the committed engine scene
in place (no render reads it then); anything else builds a new engine scene from the
cached buffers.
"""

import time

import bpy
import numpy as np
from mathutils import Matrix

from . import export_depsgraph, world as sync_world
from .instances import GeometryCache, instance_matrix, mesh_of, walk_instances
from .lights import usable_light_dict
from .visibility import instance_ray_visibility


ORTHO_BACKOFF = 1e4


def view_camera(region, region_data, width, height):
    """Camera dict for the engine from a 3D view: its view matrix and projection.

    The projection matrix gives the frustum at unit distance: perspective
    P[0][0] = 1/half_width and P[0][2] its horizontal offset (view shifts, camera-view
    zoom); orthographic P[0][0] = 2/width. The engine's horizontal sensor fit with a
    50 mm lens reproduces it (sensor = 2 lens / P[0][0])."""
    p = region_data.window_matrix
    to_world = region_data.view_matrix.inverted()
    if not region_data.is_perspective:
        # Blender's orthographic views clip from -clip_end; the engine's clip range starts at 0,
        # so step the eye back along the view axis instead.
        to_world = to_world @ Matrix.Translation((0.0, 0.0, ORTHO_BACKOFF))
    cam = {
        "matrix": [list(row) for row in to_world],
        "sensor_fit": "HORIZONTAL",
        "width": width,
        "height": height,
        "clip_start": 0.01,
        "clip_end": 1e5,
    }
    half_w, half_h = 1.0 / p[0][0], 1.0 / p[1][1]
    if region_data.is_perspective:
        lens = 50.0
        cam.update(type="PERSP", lens=lens, sensor_width=2.0 * lens * half_w,
                   shift_x=0.5 * p[0][2], shift_y=0.5 * p[1][2] * half_h / half_w)
    else:
        cam.update(type="ORTHO", ortho_scale=2.0 * half_w,
                   shift_x=-0.5 * p[0][3], shift_y=-0.5 * p[1][3] * half_h / half_w,
                   clip_start=0.0, clip_end=2.0 * ORTHO_BACKOFF)
    return cam


class ViewportSync:
    """Engine scenes for one viewport, re-exporting only what edits touched.

    After a full export, edits that move objects, change meshes, materials, lamps or the
    world are applied to the same engine scene in place (new instance matrices, the changed
    meshes' prototypes rebuilt, materials re-translated, the light table rebuilt); anything
    else (added or removed objects, images, volumes) builds a new scene from the cached
    meshes."""

    def __init__(self):
        self.cache = GeometryCache()
        self.export = None
        self.last_seconds = 0.0     # the last update (export + commit, or in-place update)
        self.last_exported = 0      # meshes taken from Blender by it
        self.last_in_place = False

    def invalidate(self, depsgraph):
        """Forget the meshes of objects whose geometry the last edit changed."""
        for update in depsgraph.updates:
            datablock = update.id
            if isinstance(datablock, bpy.types.Object) and update.is_updated_geometry:
                self.cache.invalidate(object_name=datablock.original.name_full)
            elif isinstance(datablock, bpy.types.Mesh):
                self.cache.invalidate(data_name=datablock.original.name_full)

    def build(self, native, depsgraph, reporter, camera, edited=False):
        """The engine scene for the depsgraph: updated in place when `edited` allows it,
        else exported (from cached meshes where possible). Returns the Export."""
        t0 = time.perf_counter()
        before = self.cache.exported
        self.last_in_place = edited and self.export is not None and self._update_in_place(depsgraph, reporter)
        if not self.last_in_place:
            self.cache.start_export()
            self.export = export_depsgraph(native, depsgraph, reporter, view_camera=camera, cache=self.cache)
        self.last_seconds = time.perf_counter() - t0
        self.last_exported = self.cache.exported - before
        return self.export

    def _update_in_place(self, depsgraph, reporter):
        changed_geometry = set()
        materials_changed = lights_changed = False
        for update in depsgraph.updates:
            datablock = update.id
            if isinstance(datablock, bpy.types.Object):
                if datablock.type == 'LIGHT':
                    lights_changed = True
                elif update.is_updated_geometry:
                    changed_geometry.add(datablock.original.name_full)
            elif isinstance(datablock, bpy.types.Material):
                materials_changed = True
            elif isinstance(datablock, (bpy.types.Light, bpy.types.World)):
                lights_changed = True
            elif isinstance(datablock, bpy.types.NodeTree):  # a material's or the world's nodes
                materials_changed = lights_changed = True
            elif not isinstance(datablock, (bpy.types.Mesh, bpy.types.Scene)):
                return False  # images, collections, ...: a new scene
        if materials_changed and not self.export.materials.replace_all():
            return False
        if lights_changed and not self._replace_lights(depsgraph, reporter):
            return False
        keys, matrices, edited = [], [], {}
        for kind, inst, obj in walk_instances(depsgraph, reporter):
            if kind == 'LIGHT':
                continue  # lamps: _replace_lights
            key = self.cache.identity(obj)
            if key not in self.cache.mesh_ids:
                continue  # empty geometry, never added to the engine
            keys.append(self.cache.instance_key(key, obj, instance_ray_visibility(inst)))
            matrices.append(instance_matrix(inst))
            if key[0] in changed_geometry:
                edited.setdefault(key, obj)
        if keys != self.cache.instance_keys:
            return False  # objects added, removed or re-ordered
        scene = self.export.scene
        try:
            for key, obj in edited.items():
                buf, mat_ids = mesh_of(obj, self.export.materials, self.cache)
                if buf is None or not scene.replace_mesh(
                        self.cache.mesh_ids[key], buf.vertices, buf.triangles, buf.corner_normals,
                        buf.material_index, mat_ids, buf.corner_uvs, buf.attributes or {}):
                    return False
        except (RuntimeError, ValueError):  # e.g. a new material: the committed scene can't take it
            return False
        return bool(scene.set_instance_transforms(np.array(matrices, dtype=np.float64).reshape(-1, 4, 4)))

    def _replace_lights(self, depsgraph, reporter):
        """Every lamp and the world background exported again (cheap: no geometry) and given to
        the engine scene, which keeps its emissive triangles. A world volume needs a new scene."""
        world = sync_world.export_world(sync_world.evaluated_world(depsgraph), reporter.warning)
        if world.get("volume") is not None:
            return False
        lamps = [d for d in (usable_light_dict(obj, instance_matrix(inst), reporter)
                             for kind, inst, obj in walk_instances(depsgraph, reporter) if kind == 'LIGHT')
                 if d is not None]
        try:
            return bool(self.export.scene.replace_lights(lamps, world))
        except ValueError:
            return False
