"""Estimate the noise of two independent Cycles renders of one scene and average them.

Run:
    blender -b --factory-startup --python scenes/combine_references.py -- OUT.exr A.exr B.exr [BLOCK]

A and B must be renders of the same scene with the same sample count and
different `scene.cycles.seed` (scenes/make_cycles_references.py ... SEED).
OUT.exr (RGBA half float, ZIP) is their mean, i.e. equivalent to one render
with twice the samples. OUT.exr.json gets the noise statistics:

  Images are averaged over BLOCK x BLOCK pixel blocks (default 4) and over
  R, G, B (sum of channels). For every block with mean > 1 % of the image's
  mean (the black outside of the box is skipped),
      d = (A - B) / ((A + B) / 2)
  The relative noise of ONE render is rms(d) / sqrt(2); of the average
  written to OUT it is rms(d) / 2. Percentiles of |d|/2 are reported too.
Passing OUT as '-' only prints the statistics.
"""
import json
import math
import os
import sys

import bpy
import numpy as np


def load(path):
    img = bpy.data.images.load(path, check_existing=False)
    w, h = img.size
    buf = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(buf)
    bpy.data.images.remove(img)
    return buf.reshape(h, w, 4)


def save_exr(path, rgba):
    h, w = rgba.shape[:2]
    sc = bpy.context.scene
    im = sc.render.image_settings
    im.file_format = 'OPEN_EXR'
    im.color_mode = 'RGBA'
    im.color_depth = '16'
    im.exr_codec = 'ZIP'
    img = bpy.data.images.new("combined", w, h, alpha=True, float_buffer=True)
    img.colorspace_settings.name = 'Linear'
    img.pixels.foreach_set(rgba.astype(np.float32).ravel())
    img.filepath_raw = path
    img.file_format = 'OPEN_EXR'
    img.save_render(path, scene=sc)
    back = load(path)
    err = np.abs(back - rgba) / np.maximum(np.abs(rgba), 1e-3)
    if err.max() > 2e-3:  # half float keeps ~3 digits
        raise RuntimeError("EXR round trip changed values (max rel err %g)" % err.max())


def block_mean(a, n):
    h, w = a.shape[:2]
    h2, w2 = h // n * n, w // n * n
    a = a[:h2, :w2]
    return a.reshape(h2 // n, n, w2 // n, n, *a.shape[2:]).mean(axis=(1, 3))


def stats(a, b, n):
    sa = block_mean(a[..., :3].sum(axis=2), n)
    sb = block_mean(b[..., :3].sum(axis=2), n)
    m = (sa + sb) / 2
    keep = m > 0.01 * m.mean()
    d = (sa - sb)[keep] / m[keep]
    rms = float(np.sqrt(np.mean(d * d)))
    ad = np.abs(d) / 2
    return {
        "block": n,
        "blocks_used": int(keep.sum()),
        "blocks_total": int(keep.size),
        "rel_noise_single_render_rms": rms / math.sqrt(2),
        "rel_noise_average_rms": rms / 2,
        "rel_noise_average_p95": float(np.percentile(ad, 95)),
        "rel_noise_average_p99": float(np.percentile(ad, 99)),
        "rel_noise_average_max": float(ad.max()),
        "pixel_rel_noise_average_rms": None,
    }


def main():
    argv = sys.argv
    args = argv[argv.index("--") + 1:]
    out, pa, pb = args[:3]
    n = int(args[3]) if len(args) > 3 else 4
    a, b = load(pa), load(pb)
    s = stats(a, b, n)
    s1 = stats(a, b, 1)
    s["pixel_rel_noise_average_rms"] = s1["rel_noise_average_rms"]
    s["inputs"] = [os.path.abspath(pa), os.path.abspath(pb)]
    for p in (pa, pb):
        meta = p + ".json"
        if os.path.exists(meta):
            with open(meta) as f:
                s.setdefault("input_meta", []).append(json.load(f))
    print("combine_references: %s" % json.dumps({k: v for k, v in s.items() if k.startswith(("rel", "pixel", "blocks"))}))
    if out != '-':
        save_exr(os.path.abspath(out), (a + b) / 2)
        with open(out + ".json", "w") as f:
            json.dump(s, f, indent=2)
        print("combine_references: wrote", out)


main()
