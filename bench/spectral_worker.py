"""Runs inside Blender for bench/spectral_bench.py: exports the open .blend once through the add-on's
sync layer, then renders every job of a JSON list with the native session in this process (no Blender
start-up or re-export per render) and saves each image as .npy plus the engine's render time.

    blender -b --factory-startup --addons smis_render SCENE.blend --python bench/spectral_worker.py \
        -- JOBS.json OUT_DIR [RESOLUTION_PERCENTAGE [no_dispersion]]

JOBS.json: [{"name": ..., "settings": {session settings: samples, seed, spectral, wavelengths, ...}}].
`no_dispersion` replaces every dispersive glass by a constant IOR equal to its n_d before the export.
Writes OUT_DIR/NAME.npy ((h, w, 3) float32, row 0 = bottom) and OUT_DIR/results.json
({name: {"seconds": engine render seconds, "paths": ..., "mode": resolved spectral mode}}).
"""
import json
import os
import sys

import bpy
import numpy as np

from smis_render import native, sync
from smis_render.properties import session_settings
from smis_render.sync.reports import Reporter


def remove_dispersion():
    """Every dispersive material becomes a constant-IOR one with the same n_d (the Glass / Principled
    IOR input set to the Sellmeier n at 587.56 nm), so only the spread over wavelengths is removed."""
    table = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "engine", "spectral",
                         "data", "glass_dispersion.csv")
    with open(table) as f:
        rows = [line.strip().split(",") for line in f.readlines()[1:] if line.strip()]
    n_d = {}
    for name, *c in rows:
        b, cc, l2 = [float(v) for v in c[:3]], [float(v) for v in c[3:]], 0.58756 ** 2
        n_d[name] = (1.0 + sum(bi * l2 / (l2 - ci) for bi, ci in zip(b, cc))) ** 0.5
    for mat in bpy.data.materials:
        glass = mat.smis.dispersion
        if glass == 'NONE':
            continue
        if glass in n_d and mat.node_tree:
            for node in mat.node_tree.nodes:
                if "IOR" in node.inputs:
                    node.inputs["IOR"].default_value = n_d[glass]
        mat.smis.dispersion = 'NONE'
        mat.update_tag()  # add-on properties do not tag the ID: the evaluated copy must see it
    bpy.context.view_layer.update()


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    jobs_path, out_dir = args[0], args[1]
    scene = bpy.context.scene
    if len(args) > 2:
        scene.render.resolution_percentage = int(args[2])
    if len(args) > 3 and args[3] == "no_dispersion":
        remove_dispersion()
    smis = native.load()
    export = sync.export_depsgraph(smis, bpy.context.evaluated_depsgraph_get(), Reporter(None))
    base = session_settings(scene)
    results = {}
    with open(jobs_path) as f:
        jobs = json.load(f)
    for job in jobs:
        settings = dict(base, **job["settings"])
        session = smis.RenderSession(export.scene, settings)
        session.run()
        p = session.progress()
        np.save(os.path.join(out_dir, job["name"] + ".npy"), np.asarray(session.pixels())[..., :3])
        results[job["name"]] = {"seconds": p["elapsed"], "paths": session.counters()["paths"],
                                "mode": smis.resolve_spectral_mode(export.scene, settings)}
        print("spectral_worker: %s %.3f s" % (job["name"], p["elapsed"]), flush=True)
    with open(os.path.join(out_dir, "results.json"), "w") as f:
        json.dump(results, f, indent=1)


main()
