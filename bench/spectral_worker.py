"""Runs inside Blender for bench/spectral_bench.py: exports the open .blend once through the add-on's
sync layer, then renders every job of a JSON list with the native session in this process (no Blender
start-up or re-export per render) and saves each image as .npy plus the engine's render time.

    blender -b --factory-startup --addons smis_render SCENE.blend --python bench/spectral_worker.py \
        -- JOBS.json OUT_DIR [RESOLUTION_PERCENTAGE]

JOBS.json: [{"name": ..., "settings": {session settings: samples, seed, spectral, wavelengths, ...}}].
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


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    jobs_path, out_dir = args[0], args[1]
    scene = bpy.context.scene
    if len(args) > 2:
        scene.render.resolution_percentage = int(args[2])
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
