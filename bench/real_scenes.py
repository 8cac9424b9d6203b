"""Public scenes made by others, rendered by SMIS and by Cycles at equal settings (issue 17).

    /usr/bin/python3 bench/real_scenes.py [--scenes-dir DIR] [--samples 128] [--max-size 160] [--quick] [--settings JSON]

For every .blend under the scenes folder (default: ../shared/real_scenes beside the checkout) that
Blender 3.4 opens, and every glTF 2.0 file there (.gltf/.glb, imported with Blender's importer into a
scene with a camera and a bundled CC0 studio HDRI as its world, bench/tools/gltf_to_blend.py): both engines render it at the same resolution (scaled so the longer side is at
most --max-size pixels), samples, bounces (the scene's Cycles max bounces, at most 8) and box filter;
Cycles with its unbiased settings (scenes/cycles_settings.py). Printed per scene: our warnings, the
mean relative error over 8x8 blocks (mean over blocks of |ours - Cycles| / max(Cycles, 0.01), on the
blocks' average luminance) and the image-mean ratio, and samples per second against Cycles' (each
engine's own render time; Cycles' includes its scene sync). Both images carry noise: the error has a
noise floor, which --samples lowers. Writes bench/results/real_scenes.{csv,json,md}.
"""
import argparse
import csv
import glob
import json
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render import BLENDER, RenderError, remove, render_cycles, render_smis  # noqa: E402
from metrics import load_exr  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "bench", "results")
_WARNING = re.compile(r"^Warning: (.*)$", re.M)


def block_relative_error(ref, est, block=8, eps=0.01):
    """Mean over 8x8 blocks of |mean est - mean ref| / max(mean ref, eps), on luminance."""
    w = np.array([0.2126, 0.7152, 0.0722], dtype=np.float64)
    r = ref[..., :3].astype(np.float64) @ w
    e = est[..., :3].astype(np.float64) @ w
    h, wd = (r.shape[0] // block) * block, (r.shape[1] // block) * block
    if h == 0 or wd == 0:
        return float("nan")
    rb = r[:h, :wd].reshape(h // block, block, wd // block, block).mean(axis=(1, 3))
    eb = e[:h, :wd].reshape(h // block, block, wd // block, block).mean(axis=(1, 3))
    return float(np.mean(np.abs(eb - rb) / np.maximum(rb, eps)))


GLTF_HDRI = "/usr/share/blender/datafiles/studiolights/world/courtyard.exr"


def gltf_to_blend(src, out_dir):
    """The .blend a user gets by importing a glTF file (see bench/tools/gltf_to_blend.py)."""
    os.makedirs(out_dir, exist_ok=True)
    dst = os.path.join(out_dir, os.path.splitext(os.path.basename(src))[0] + ".blend")
    tool = os.path.join(ROOT, "bench", "tools", "gltf_to_blend.py")
    proc = subprocess.run([BLENDER, "-b", "--factory-startup", "--python", tool, "--", src, dst, GLTF_HDRI],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
    if proc.returncode != 0 or not os.path.exists(dst):
        raise RenderError("glTF import failed: %s" % proc.stdout[-300:], proc.stdout)
    return dst


def run_scene(blend, samples, max_size, bounces_cap=8, settings=None):
    # The longer side at most max_size pixels, for both engines (run inside Blender first).
    shrink = [
        # A scene saved without a camera (glTF test files) gets one looking at its meshes from a
        # diagonal, the same for both engines, so it can be compared at all.
        "if scene.camera is None:",
        "    import mathutils",
        "    pts = [o.matrix_world @ mathutils.Vector(c) for o in scene.objects if o.type == 'MESH'"
        " for c in o.bound_box]",
        "    lo = mathutils.Vector([min(p[i] for p in pts) for i in range(3)]) if pts else mathutils.Vector((-1,-1,-1))",
        "    hi = mathutils.Vector([max(p[i] for p in pts) for i in range(3)]) if pts else mathutils.Vector((1,1,1))",
        "    c, rad = (lo + hi) / 2, max((hi - lo).length / 2, 1e-3)",
        "    cam = bpy.data.objects.new('bench camera', bpy.data.cameras.new('bench camera'))",
        "    scene.collection.objects.link(cam)",
        "    cam.location = c + mathutils.Vector((1.0, -1.4, 0.9)).normalized() * rad * 2.8",
        "    cam.rotation_euler = (c - cam.location).to_track_quat('-Z', 'Y').to_euler()",
        "    scene.camera = cam",
        "r = bpy.context.scene.render",
              "f = min(1.0, %d / max(r.resolution_x * r.resolution_percentage / 100.0,"
              " r.resolution_y * r.resolution_percentage / 100.0))" % max_size,
              "r.resolution_x = max(8, int(r.resolution_x * r.resolution_percentage / 100.0 * f))",
              "r.resolution_y = max(8, int(r.resolution_y * r.resolution_percentage / 100.0 * f))",
              "r.resolution_percentage = 100"]
    row = {"scene": os.path.relpath(blend, os.path.dirname(os.path.dirname(blend)))}
    # Our Light Paths set as the unbiased Cycles reference has them: unset, ours would take the file's
    # own Cycles settings (per-type limits, clamps, caustics) where the file stores them.
    unbiased = {"diffuse_bounces": bounces_cap, "glossy_bounces": bounces_cap, "transmission_bounces": bounces_cap,
                "transparent_bounces": bounces_cap, "clamp_direct": 0.0, "clamp_indirect": 0.0,
                "caustics_reflective": True, "caustics_refractive": True}
    smis = render_smis(blend, {"samples": samples, "max_bounces": bounces_cap, "seed": 1, **unbiased,
                               **(settings or {})},
                       prelude=shrink)
    cycles = render_cycles(blend, samples, seed=1, max_bounces=bounces_cap, prelude=shrink)
    ours, ref = load_exr(smis.path), load_exr(cycles.path)
    warnings = sorted(set(_WARNING.findall(smis.output)))
    row.update({
        "block_rel_error": block_relative_error(ref, ours),
        "mean_ratio": float(np.mean(ours[..., :3]) / max(np.mean(ref[..., :3]), 1e-12)),
        "nonfinite": int(np.count_nonzero(~np.isfinite(ours[..., :3]))),
        "smis_seconds": smis.seconds, "cycles_seconds": cycles.seconds,
        "speed_vs_cycles": cycles.seconds / max(smis.seconds, 1e-6),
        "warnings": len(warnings), "warning_text": " | ".join(warnings)[:2000],
        "size": "%dx%d" % (ours.shape[1], ours.shape[0]),
    })
    remove(smis)
    remove(cycles)
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes-dir", default=os.path.join(os.path.dirname(ROOT), "shared", "real_scenes"))
    ap.add_argument("--samples", type=int, default=128)
    ap.add_argument("--max-size", type=int, default=160)
    ap.add_argument("--quick", action="store_true", help="32 samples at 96 px")
    ap.add_argument("--only", nargs="*", default=None, help="substrings of the scenes to run")
    ap.add_argument("--settings", default="{}",
                    help='our settings on top of the defaults, as JSON, e.g. \'{"integrator": "PSF_SMIS_UNBIASED", '
                         '"spectral": "HERO"}\': every estimator against Cycles on real scenes')
    a = ap.parse_args()
    if a.quick:
        a.samples, a.max_size = 32, 96
    blends = sorted(glob.glob(os.path.join(a.scenes_dir, "**", "*.blend"), recursive=True))
    blends += sorted(f for ext in ("gltf", "glb")
                     for f in glob.glob(os.path.join(a.scenes_dir, "**", "*." + ext), recursive=True))
    if a.only:
        blends = [b for b in blends if any(s in b for s in a.only)]
    if not blends:
        print("no .blend files under %s" % a.scenes_dir)
        return 0
    rows = []
    for blend in blends:
        name = os.path.relpath(blend, a.scenes_dir)
        try:
            if not blend.endswith(".blend"):
                blend = gltf_to_blend(blend, os.path.join(RESULTS, "gltf_scenes"))
            row = run_scene(blend, a.samples, a.max_size, settings=json.loads(a.settings))
            row["scene"] = name
        except (RenderError, OSError, ValueError) as exc:
            row = {"scene": name, "error": str(exc).splitlines()[0][:300]}
        rows.append(row)
        if "error" in row:
            print("%-60s ERROR %s" % (name, row["error"]))
        else:
            print("%-60s err %6.2f%%  mean %.3f  speed %.2fx  warnings %d %s"
                  % (name, 100 * row["block_rel_error"], row["mean_ratio"], row["speed_vs_cycles"],
                     row["warnings"], row["warning_text"][:160]))
    os.makedirs(RESULTS, exist_ok=True)
    with open(os.path.join(RESULTS, "real_scenes.json"), "w") as f:
        json.dump({"samples": a.samples, "max_size": a.max_size, "rows": rows}, f, indent=1)
    keys = ["scene", "size", "block_rel_error", "mean_ratio", "speed_vs_cycles", "smis_seconds",
            "cycles_seconds", "nonfinite", "warnings", "warning_text", "error"]
    with open(os.path.join(RESULTS, "real_scenes.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    ok = [r for r in rows if "error" not in r]
    within = sum(1 for r in ok if r["block_rel_error"] <= 0.02)
    lines = ["| scene | error (8x8 blocks) | mean ratio | samples/s vs Cycles | warnings |",
             "| --- | --- | --- | --- | --- |"]
    for r in rows:
        if "error" in r:
            lines.append("| %s | render failed | | | %s |" % (r["scene"], r["error"][:80]))
        else:
            lines.append("| %s | %.2f%% | %.3f | %.2fx | %d |" % (r["scene"], 100 * r["block_rel_error"],
                                                              r["mean_ratio"], r["speed_vs_cycles"], r["warnings"]))
    lines.append("")
    lines.append("%d of %d scenes within 2%% (%d samples, longest side %d px)."
                 % (within, len(rows), a.samples, a.max_size))
    with open(os.path.join(RESULTS, "real_scenes.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
