"""The interactive viewport's side of the sync: the 3D view as a camera, and which
objects an edit invalidates.

Blender calls view_update() after every edit with the depsgraph's list of updated
datablocks; only objects whose geometry changed are exported again, every other mesh
comes from the GeometryCache (keyed by object identity, like Cycles' BlenderSync).
The engine scene itself is rebuilt from the cached buffers and committed (Embree
builds a new BVH): the engine scene is immutable while a render reads it.
"""

import time

import bpy
import numpy as np
from mathutils import Matrix

from . import export_depsgraph
from .instances import GeometryCache, instance_matrix, mesh_of, walk_instances


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

    After a full export, edits that only move objects or change meshes are applied to the
    same engine scene in place (new instance matrices, the changed meshes' prototypes
    rebuilt); anything else (materials, lights, world, added or removed objects) builds a
    new scene from the cached meshes."""

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
        for update in depsgraph.updates:
            datablock = update.id
            if isinstance(datablock, bpy.types.Object):
                if datablock.type == 'LIGHT':
                    return False
                if update.is_updated_geometry:
                    changed_geometry.add(datablock.original.name_full)
            elif not isinstance(datablock, (bpy.types.Mesh, bpy.types.Scene)):
                return False  # materials, world, lights, collections: a new scene
        keys, matrices, edited = [], [], {}
        for kind, inst, obj in walk_instances(depsgraph, reporter):
            if kind == 'LIGHT':
                continue  # unchanged: a light edit returned above
            key = self.cache.identity(obj)
            if key not in self.cache.mesh_ids:
                continue  # empty geometry, never added to the engine
            keys.append((key, tuple(obj.color[:3])))  # a new object colour needs a new scene
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
                        buf.material_index, mat_ids, buf.corner_uvs):
                    return False
        except (RuntimeError, ValueError):  # e.g. a new material: the committed scene can't take it
            return False
        return bool(scene.set_instance_transforms(np.array(matrices, dtype=np.float64).reshape(-1, 4, 4)))
