"""Export speed: one million triangles in many objects, and the interactive viewport's re-sync after
a one-object edit. Measured, not asserted (the machine is shared; numbers vary run to run).

    blender -b --factory-startup --addons smis_render --python bench/export_bench.py

Scenes (built here, 1,000,000+ triangles each as rendered):
  instanced  20 meshes of ~5,000 triangles, each used by 10 objects sharing the mesh (linked
             duplicates, one Embree prototype each) = 200 objects, 1.0 M triangles
  unique     200 objects with their own ~5,000-triangle mesh = 1.0 M triangles exported
For each: a full export (best of REPEATS), split into the Python sync (depsgraph walk,
to_mesh, foreach_get) and the engine commit (Embree BVH build); then, through the viewport's
ViewportSync, a move of one object, an edit of one object's mesh, and edits of the material all
objects share, of the light and of the world, each re-synced (best of REPEATS). Writes
bench/results/export_bench.json.
"""
import json
import os
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPEATS = 3
MESHES, USERS = 20, 10

from smis_render import native, sync  # noqa: E402
from smis_render.sync import camera as sync_camera  # noqa: E402
from smis_render.sync.reports import Reporter  # noqa: E402
from smis_render.sync.viewport import ViewportSync  # noqa: E402


def build(unique):
    bpy.ops.wm.read_homefile(use_empty=False)
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    coll = bpy.context.scene.collection
    mat = bpy.data.materials.new("BenchMat")
    mat.use_nodes = True
    n = 0
    for m in range(MESHES):
        bpy.ops.mesh.primitive_uv_sphere_add(segments=50, radius=0.4, ring_count=51, location=(0, 0, 0))
        src = bpy.context.active_object
        for c in list(src.users_collection):
            c.objects.unlink(src)
        src.data.materials.append(mat)
        for u in range(USERS):
            data = src.data.copy() if unique else src.data
            obj = bpy.data.objects.new("S%d_%d" % (m, u), data)
            obj.location = (m - MESHES / 2, u - USERS / 2, 0.0)
            coll.objects.link(obj)
            n += 1
    bpy.context.view_layer.update()
    return n


def full_export(depsgraph):
    best = None
    for _ in range(REPEATS):
        e = sync.export_depsgraph(native.load(), depsgraph, Reporter(None))
        if best is None or e.seconds < best.seconds:
            best = e
    return best


class ViewUpdate:
    """A depsgraph_update_post handler doing what view_update() does: the depsgraph's list of
    updates is only valid inside the handler."""

    def __init__(self, vs, camera):
        self.vs, self.camera, self.times = vs, camera, []

    def __call__(self, scene, depsgraph):
        self.vs.invalidate(depsgraph)
        e = self.vs.build(native.load(), depsgraph, Reporter(None), self.camera, edited=True)
        commit = 0.0 if self.vs.last_in_place else e.commit_seconds
        self.times.append((self.vs.last_seconds, commit, self.vs.last_exported, self.vs.last_in_place))


def resync(handler, edit):
    handler.times = []
    for _ in range(REPEATS):
        edit()
        bpy.context.view_layer.update()  # fires depsgraph_update_post
    return min(handler.times)


def measure(unique):
    objects = build(unique)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    e = full_export(depsgraph)
    vs = ViewportSync()
    camera = sync_camera.export_camera(None, depsgraph, print)
    vs.build(native.load(), depsgraph, Reporter(None), camera)
    recorder = ViewUpdate(vs, camera)
    bpy.app.handlers.depsgraph_update_post.append(recorder)
    try:
        target = bpy.data.objects["S3_4"]

        def move():
            target.location.z += 0.1

        def edit_mesh():
            # A geometry update of the one object (a displace-like edit of its own vertices).
            for v in target.data.vertices[:50]:
                v.co.z += 0.01
            target.data.update()
        def edit_material():
            bsdf = bpy.data.materials["BenchMat"].node_tree.nodes["Principled BSDF"]
            bsdf.inputs["Roughness"].default_value = 0.9 - bsdf.inputs["Roughness"].default_value

        def edit_light():
            bpy.data.lights["Light"].energy += 10.0

        def edit_world():
            bg = bpy.context.scene.world.node_tree.nodes["Background"]
            bg.inputs["Strength"].default_value += 0.1
        moved = resync(recorder, move)
        edited = resync(recorder, edit_mesh) if unique else None
        others = {name: resync(recorder, fn) for name, fn in
                  (("material", edit_material), ("light", edit_light), ("world", edit_world))}
    finally:
        bpy.app.handlers.depsgraph_update_post.remove(recorder)
    row = {
        "scene": "unique" if unique else "instanced",
        "objects": objects,
        "triangles": e.stats["triangles"],
        "meshes_exported": e.counts.meshes,
        "full_export_s": round(e.seconds, 4),
        "full_sync_python_s": round(e.seconds - e.commit_seconds, 4),
        "full_commit_bvh_s": round(e.commit_seconds, 4),
        "move_resync_s": round(moved[0], 4),
        "move_resync_python_s": round(moved[0] - moved[1], 4),
        "move_meshes_exported": moved[2],
        "move_in_place": moved[3],
    }
    for name, t in others.items():
        row.update({name + "_resync_s": round(t[0], 4), name + "_meshes_exported": t[2], name + "_in_place": t[3]})
    if edited:
        row.update(edit_resync_s=round(edited[0], 4), edit_resync_python_s=round(edited[0] - edited[1], 4),
                   edit_meshes_exported=edited[2], edit_in_place=edited[3])
    return row


rows = [measure(False), measure(True)]
for r in rows:
    print("export_bench:", json.dumps(r))
os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
with open(os.path.join(ROOT, "bench", "results", "export_bench.json"), "w") as f:
    json.dump(rows, f, indent=1)
sys.stdout.flush()
