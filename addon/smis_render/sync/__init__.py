"""Blender depsgraph -> engine scene, one way.

Each module translates one kind of Blender data into plain dicts and numpy
buffers for the native `_smis.Scene`; nothing here does light transport and
the engine never sees a Blender object.
"""

import time
from dataclasses import dataclass, field

from . import camera, instances, materials, motion, world
from .camera import CameraError
from .instances import Cancelled


class ExportError(Exception):
    """A problem that makes the scene unrenderable; reported as an ERROR."""


@dataclass
class Export:
    scene: object                  # the committed _smis.Scene
    camera: dict                   # the dict given to set_camera (resolution, border)
    counts: instances.ExportCounts
    stats: dict = field(default_factory=dict)   # scene.stats() after commit
    seconds: float = 0.0
    commit_seconds: float = 0.0   # of `seconds`: the engine's BVH build and light tables
    materials: object = None       # the MaterialCache (engine material ids of this scene)


def export_depsgraph(native, depsgraph, reporter, engine=None, view_camera=None, cache=None):
    """Build and commit an engine scene. Raises ExportError, or Cancelled on test_break.

    The interactive viewport passes the 3D view's camera dict (`view_camera`) and a
    GeometryCache (`cache`) that keeps meshes between updates."""
    t0 = time.perf_counter()
    scene = native.Scene()
    if cache is not None:
        scene.set_fast_build(True)  # the viewport rebuilds after every edit
    bl_scene = depsgraph.scene
    smis = getattr(bl_scene, "smis", None)
    if smis is not None and (smis.multiscatter_cycles_walk or smis.beckmann_cycles_sampling):
        # Cycles' multiscatter and anisotropic Beckmann estimators are inconsistent: its image depends
        # on its MIS weights, hence on how it chooses lights (scene/light_selection.h).
        scene.set_light_selection("CYCLES_3_4")

    # Motion blur (final renders only): the scene evaluated at the shutter's times first, then
    # exported at its frame.
    moving = motion.collect(engine, depsgraph, reporter.warning) if view_camera is None else None
    try:
        try:
            cam = view_camera or camera.export_camera(engine, depsgraph, reporter.warning)
            if moving is not None:
                cam = dict(cam, **moving.camera_fields())
            scene.set_camera(cam)
        except (CameraError, ValueError) as exc:
            raise ExportError(str(exc)) from exc

        scene.set_world(world.export_world(world.evaluated_world(depsgraph), reporter.warning))

        test_break = engine.break_requested if engine is not None else None
        mats = materials.MaterialCache(scene, reporter)
        counts = instances.export_instances(depsgraph, scene, mats, reporter, test_break, cache, moving)
    finally:
        if moving is not None:
            moving.restore()

    if counts.instances == 0 and counts.lights == 0:
        reporter.warning("The scene is empty (no renderable objects or lights); "
                         "rendering the world background only")
    t_commit = time.perf_counter()
    try:
        scene.commit()
    except ValueError as exc:
        raise ExportError("The engine refused the scene: %s" % exc) from exc

    done = time.perf_counter()
    return Export(scene=scene, camera=cam, counts=counts, stats=dict(scene.stats()),
                  seconds=done - t0, commit_seconds=done - t_commit, materials=mats)


__all__ = ["Export", "ExportError", "Cancelled", "export_depsgraph"]
