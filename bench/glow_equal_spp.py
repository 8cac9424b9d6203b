"""The path tracer with and without its light-aimed continuations at surfaces in fog
(integrators/glow_directions.h, issue 22), at equal samples per pixel on the volume scenes, against
the cached references of bench/single_scattering_equal_time.py (bench/references/<scene>_512x384_ref).

    BLENDER_USER_SCRIPTS=$PWD/.bl_scripts blender -b --factory-startup --addons smis_render \
        --python bench/glow_equal_spp.py -- [--spp 16] [--seeds 1 2 3] [--scenes volume_spot ...]

Runs inside Blender: each scene is exported once through the add-on's sync layer at 512x384 with the
equal-time benchmark's settings (PATH, max_bounces 1, volume bounces 0, BOX 1 px) and rendered with
native sessions, glow_directions off and on for each seed (interleaved; the same seeds), so no
Blender start-up is timed. Prints per scene and seed relMSE (eps 1e-2) and SMAPE of both, their
ratio, and the render seconds (wall-clock, noisy under load). Writes bench/results/glow_equal_spp.json.
"""
import json
import os
import sys
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import metrics as M  # noqa: E402

from smis_render import _smis, properties, sync  # noqa: E402

WIDTH, HEIGHT = 512, 384


class Reporter:
    def warning(self, message):
        print("WARNING:", message)

    def info(self, message):
        print(message)


def args():
    a = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out = {"spp": 16, "seeds": [1, 2, 3], "scenes": ["volume_spot", "volume_planes", "volume_thin_hg", "volume_slit"]}
    key = None
    for x in a:
        if x.startswith("--"):
            key = x[2:]
            out[key] = [] if key in ("seeds", "scenes") else True
        elif key in ("seeds", "scenes"):
            out[key].append(int(x) if key == "seeds" else x)
        else:
            out[key] = int(x)
    return out


def export_scene(name):
    bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "scenes", name + ".blend"))
    sc = bpy.context.scene
    sc.render.resolution_x, sc.render.resolution_y, sc.render.resolution_percentage = WIDTH, HEIGHT, 100
    sc.smis.integrator = "PATH"
    sc.smis.max_bounces = 1
    sc.smis.filter_type = "BOX"
    sc.smis.filter_width = 1.0
    export = sync.export_depsgraph(_smis, bpy.context.evaluated_depsgraph_get(), Reporter())
    base = properties.session_settings(sc)
    base.update({"threads": 0, "time_limit": 0.0})
    return export.scene, base


def render(scene, base, spp, seed, glow):
    session = _smis.RenderSession(scene, dict(base, samples=spp, seed=seed, glow_directions=glow))
    t0 = time.perf_counter()
    session.run()
    seconds = time.perf_counter() - t0
    if session.error():
        raise RuntimeError(session.error())
    return np.array(session.pixels()), seconds


def main():
    a = args()
    rows = []
    for name in a["scenes"]:
        ref = M.load_exr(os.path.join(ROOT, "bench", "references", "%s_%dx%d_ref.exr" % (name, WIDTH, HEIGHT)))
        scene, base = export_scene(name)
        for seed in a["seeds"]:
            row = {"scene": name, "seed": seed, "spp": a["spp"]}
            for glow in (False, True):
                img, seconds = render(scene, base, a["spp"], seed, glow)
                m = M.metrics(ref, img)
                tag = "new" if glow else "old"
                row.update({tag + "_relmse": m["relmse"], tag + "_smape": m["smape"], tag + "_seconds": seconds})
            rows.append(row)
            print("GLOW %-15s seed %d %d spp: relMSE old %.5g new %.5g (x%.3f)  SMAPE old %.5f new %.5f  "
                  "seconds old %.2f new %.2f" % (name, seed, a["spp"], row["old_relmse"], row["new_relmse"],
                                                 row["new_relmse"] / row["old_relmse"], row["old_smape"],
                                                 row["new_smape"], row["old_seconds"], row["new_seconds"]), flush=True)
        rs = [r for r in rows if r["scene"] == name]
        mean = {k: float(np.mean([r[k] for r in rs])) for k in ("old_relmse", "new_relmse", "old_smape", "new_smape",
                                                                 "old_seconds", "new_seconds")}
        print("GLOW %-15s mean over %d seeds: relMSE old %.5g new %.5g (x%.3f)  SMAPE old %.5f new %.5f (x%.3f)  "
              "seconds old %.2f new %.2f" % (name, len(rs), mean["old_relmse"], mean["new_relmse"],
                                             mean["new_relmse"] / mean["old_relmse"], mean["old_smape"],
                                             mean["new_smape"], mean["new_smape"] / mean["old_smape"],
                                             mean["old_seconds"], mean["new_seconds"]), flush=True)
    os.makedirs(os.path.join(ROOT, "bench", "results"), exist_ok=True)
    with open(os.path.join(ROOT, "bench", "results", "glow_equal_spp.json"), "w") as f:
        json.dump(rows, f, indent=1)


main()
sys.stdout.flush()
os._exit(0)
