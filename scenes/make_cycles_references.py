"""Render the open .blend with Cycles (CPU, unbiased settings) to a small RGBA EXR.

Run:
    blender -b SCENE.blend --python scenes/make_cycles_references.py -- OUT.exr SAMPLES [SEED] [THREADS]

SEED defaults to 0 (scene.cycles.seed), THREADS to 0 (= all cores).
Writes OUT.exr (half float, RGBA, ZIP) plus OUT.exr.json with the settings used
and the render time. Scene-linear values, Cycles' "Combined" pass.

The unbiased settings (see /work/shared/BLENDER_NOTES.md) are forced here even
if the .blend already has them: every per-type bounce limit = max_bounces (the
value saved in the file, 8 for scenes/build_scenes.py output), blur_glossy 0,
light_sampling_threshold 0, clamps 0, caustics on, denoising off, adaptive
sampling off, BOX pixel filter 1 px, CPU device.
"""
import json
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import make_cycles_unbiased  # noqa: E402


def main():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) < 2:
        raise SystemExit("usage: blender -b SCENE.blend --python make_cycles_references.py -- OUT.exr SAMPLES [SEED] [THREADS]")
    out = os.path.abspath(args[0])
    samples = int(args[1])
    seed = int(args[2]) if len(args) > 2 else 0
    threads = int(args[3]) if len(args) > 3 else 0

    sc = bpy.context.scene
    sc.render.engine = 'CYCLES'
    c = sc.cycles
    c.device = 'CPU'
    c.samples = samples
    c.seed = seed
    c.use_animated_seed = False
    make_cycles_unbiased(sc)
    c.use_auto_tile = False
    sc.render.resolution_percentage = 100
    sc.render.use_border = False
    sc.render.film_transparent = False
    if threads > 0:
        sc.render.threads_mode = 'FIXED'
        sc.render.threads = threads
    else:
        sc.render.threads_mode = 'AUTO'

    im = sc.render.image_settings
    im.file_format = 'OPEN_EXR'
    im.color_mode = 'RGBA'
    im.color_depth = '16'
    im.exr_codec = 'ZIP'
    sc.render.use_file_extension = False
    sc.render.filepath = out

    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    dt = time.time() - t0

    meta = {
        "blend": bpy.data.filepath,
        "output": out,
        "engine": "CYCLES 3.4 CPU",
        "samples": samples,
        "seed": seed,
        "max_bounces": c.max_bounces,
        "per_type_bounces": c.diffuse_bounces,
        "volume_bounces": c.volume_bounces,
        "resolution": [sc.render.resolution_x, sc.render.resolution_y],
        "pixel_filter": "BOX 1.0 px",
        "blur_glossy": 0.0,
        "light_sampling_threshold": 0.0,
        "clamps": 0.0,
        "caustics": True,
        "denoising": False,
        "adaptive_sampling": False,
        "threads": sc.render.threads,
        "render_seconds": round(dt, 2),
        "blender": bpy.app.version_string,
    }
    with open(out + ".json", "w") as f:
        json.dump(meta, f, indent=2)
    print("make_cycles_references: %s (%d spp, seed %d) in %.1f s" % (out, samples, seed, dt))


main()
