"""Path samples per second: our path tracer against Cycles on the same scene, measured in one run.

    blender -b --factory-startup --addons smis_render --python bench/path_speed.py -- [SCENE.blend] [SPP] [WxH]

WxH (e.g. 480x270) overrides the scene's resolution (at 100%). Both engines render the same resolution, bounce limit, sample count and pixel filter, without
denoising or adaptive sampling; wall time of the whole render call (export + BVH + rendering) is
measured for each, interleaved, best of REPEATS. Writes bench/results/path_speed.{json,csv}."""
import csv
import json
import os
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scenes"))
from cycles_settings import make_cycles_unbiased  # noqa: E402
args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
blend = args[0] if args else os.path.join(ROOT, "scenes", "cornell.blend")
spp = int(args[1]) if len(args) > 1 else 256
size = [int(v) for v in args[2].lower().split("x")] if len(args) > 2 else None
REPEATS = 3


def timed_render(engine):
    scene = bpy.context.scene
    scene.render.engine = engine
    t0 = time.perf_counter()
    bpy.ops.render.render()
    return time.perf_counter() - t0


bpy.ops.wm.open_mainfile(filepath=blend)
scene = bpy.context.scene
if size:
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
w = scene.render.resolution_x * scene.render.resolution_percentage // 100
h = scene.render.resolution_y * scene.render.resolution_percentage // 100
c = scene.cycles
make_cycles_unbiased(scene)
c.samples = spp
scene.smis.samples = spp
scene.smis.max_bounces = c.max_bounces
scene.smis.filter_type = "BOX"
scene.smis.filter_width = 1.0
scene.render.threads_mode = "AUTO"

paths = w * h * spp
# Interleaved, best of REPEATS each: a load that comes and goes on the machine hits both engines.
t_cycles = t_smis = float("inf")
for _ in range(REPEATS):
    t_cycles = min(t_cycles, timed_render("CYCLES"))
    t_smis = min(t_smis, timed_render("SMIS"))
result = {
    "scene": os.path.basename(blend), "width": w, "height": h, "spp": spp, "max_bounces": c.max_bounces,
    "threads": os.cpu_count(),
    "cycles_seconds": t_cycles, "smis_seconds": t_smis,
    "cycles_paths_per_second": paths / t_cycles, "smis_paths_per_second": paths / t_smis,
    "ratio_smis_over_cycles": t_cycles / t_smis,
}
out_dir = os.path.join(ROOT, "bench", "results")
os.makedirs(out_dir, exist_ok=True)
with open(os.path.join(out_dir, "path_speed.json"), "w") as f:
    json.dump(result, f, indent=2)
with open(os.path.join(out_dir, "path_speed.csv"), "w", newline="") as f:
    wr = csv.DictWriter(f, fieldnames=list(result))
    wr.writeheader()
    wr.writerow(result)
print("PATH SPEED " + json.dumps(result))
print(f"Cycles: {result['cycles_paths_per_second'] / 1e6:.3f} M paths/s   "
      f"SMIS: {result['smis_paths_per_second'] / 1e6:.3f} M paths/s   "
      f"ratio SMIS/Cycles: {result['ratio_smis_over_cycles']:.2f}")
