"""Image error metrics shared by every benchmark, and an EXR loader.

All metric functions take the reference `ref` and the estimate `est` as numpy float arrays of shape
(h, w, 3) (an alpha channel, if present, is dropped: (h, w, 4) is accepted) in scene-linear units,
compute per channel and per pixel, and average over every pixel and channel:

  SMAPE   (West et al. 2020, Sec. 4.4)  mean of |r - e| / (|r| + |e|); a pixel channel where both
          r and e are 0 counts as 0. Bounded in [0, 1], robust to outliers, no epsilon.
  relMSE  mean of (e - r)^2 / (r^2 + eps), eps = 1e-2 by default (EPS_RELMSE). The epsilon changes
          the value a lot in dark regions: always report it (metrics() puts it in its output).
  MSE     mean of (e - r)^2.

Work is done in float64. Non-finite values in the estimate are not hidden: they make the metric
non-finite (`metrics()` also counts them).

`load_exr(path)` reads an EXR with the engine's own reader: a (h, w, 4) float32 RGBA array with
row 0 = the bottom row (Blender's layout). Works in /usr/bin/python3 (imports a private copy of
addon/smis_render/_smis*.so, safe while the engine is rebuilt) and inside Blender
(`from smis_render import _smis`).

Usable as a command line tool too:
    /usr/bin/python3 bench/metrics.py REF.exr EST.exr [--eps 1e-2]
"""
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
EPS_RELMSE = 1e-2

_smis_module = None


def _private_copy_import(attempts=10, wait=15.0):
    """Import addon/smis_render/_smis*.so from a private copy in a temporary folder.

    Outside Blender only read_exr is needed. The checkout's module may be rebuilt (truncated and
    rewritten in place) while a long benchmark runs: a process that mapped that very file could
    crash, and an import during the rewrite fails with 'file too short'. A copy taken once, and
    retried until it imports, avoids both."""
    import glob
    import importlib.util
    import shutil
    import tempfile
    import time
    last = None
    for _ in range(attempts):
        found = sorted(glob.glob(os.path.join(ROOT, "addon", "smis_render", "_smis*.so")))
        if not found:
            raise ImportError("no _smis*.so in addon/smis_render: build the engine first")
        tmp = tempfile.mkdtemp(prefix="smis_bench_mod_")
        dst = os.path.join(tmp, os.path.basename(found[0]))
        shutil.copy2(found[0], dst)
        try:
            spec = importlib.util.spec_from_file_location("_smis", dst)
            mod = importlib.util.module_from_spec(spec)
            spec.loader.exec_module(mod)
            shutil.rmtree(tmp, ignore_errors=True)  # the mapped file stays valid after unlink
            return mod
        except ImportError as exc:  # being rebuilt right now: wait for the linker to finish
            last = exc
            shutil.rmtree(tmp, ignore_errors=True)
            time.sleep(wait)
    raise ImportError("could not import a copy of %s: %s" % (found[0], last))


def _smis():
    """The engine's native module: the add-on's when inside Blender, else a private copy."""
    global _smis_module
    if _smis_module is None:
        try:
            from smis_render import _smis as mod  # inside Blender, add-on enabled
        except ImportError:
            mod = _private_copy_import()
        _smis_module = mod
    return _smis_module


def load_exr(path, layer=""):
    """(h, w, 4) float32 RGBA, row 0 = bottom. `layer`: channel prefix in a multilayer EXR."""
    if not os.path.exists(path):
        raise FileNotFoundError(path)
    return np.asarray(_smis().read_exr(path, layer) if layer else _smis().read_exr(path))


def save_exr(path, rgba):
    """Write (h, w, 4) float RGBA (row 0 = bottom, as load_exr returns) as a float EXR."""
    img = np.ascontiguousarray(rgba, dtype=np.float32)
    if img.ndim != 3 or img.shape[2] != 4:
        raise ValueError("save_exr wants (h, w, 4), got %s" % (img.shape,))
    _smis().write_exr(path, img)


BLENDER_OCIO = "/usr/share/blender/datafiles/colormanagement/config.ocio"


def save_png(path, rgba, view="Filmic", exposure=0.0):
    """Display-referred PNG through Blender's OCIO config (as scripts/exr_to_png.py)."""
    img = np.ascontiguousarray(rgba, dtype=np.float32)
    _smis().write_png(path, img, BLENDER_OCIO, "sRGB", view, "None", float(exposure), 1.0)


def _rgb_pair(ref, est):
    r = np.asarray(ref, dtype=np.float64)
    e = np.asarray(est, dtype=np.float64)
    if r.ndim == 3 and r.shape[2] == 4:
        r = r[..., :3]
    if e.ndim == 3 and e.shape[2] == 4:
        e = e[..., :3]
    if r.shape != e.shape:
        raise ValueError("reference %s and estimate %s differ in shape" % (r.shape, e.shape))
    if r.ndim != 3 or r.shape[2] != 3:
        raise ValueError("expected (h, w, 3) images, got %s" % (r.shape,))
    return r, e


def smape(ref, est):
    """Symmetric mean absolute percentage error, per channel, averaged (0/0 counts as 0)."""
    r, e = _rgb_pair(ref, est)
    num = np.abs(r - e)
    den = np.abs(r) + np.abs(e)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(den > 0.0, num / np.where(den > 0.0, den, 1.0), 0.0)
    # a non-finite estimate must show up, not be masked by the where() above
    q = np.where(np.isfinite(e), q, np.nan)
    return float(q.mean())


def relmse(ref, est, eps=EPS_RELMSE):
    """Relative MSE: mean of (e - r)^2 / (r^2 + eps), per channel, averaged."""
    r, e = _rgb_pair(ref, est)
    return float(((e - r) ** 2 / (r * r + eps)).mean())


def mse(ref, est):
    r, e = _rgb_pair(ref, est)
    return float(((e - r) ** 2).mean())


def metrics(ref, est, eps=EPS_RELMSE):
    """All metrics as a dict, with the relMSE epsilon stated and non-finite pixels counted."""
    r, e = _rgb_pair(ref, est)
    return {
        "smape": smape(r, e),
        "relmse": relmse(r, e, eps),
        "relmse_eps": eps,
        "mse": mse(r, e),
        "nonfinite": int((~np.isfinite(e)).any(axis=-1).sum()),
    }


def describe(m):
    """One line for logs, e.g. 'SMAPE 0.0512  relMSE(eps=0.01) 0.0231  MSE 0.00412'."""
    return "SMAPE %.4g  relMSE(eps=%g) %.4g  MSE %.4g%s" % (
        m["smape"], m["relmse_eps"], m["relmse"], m["mse"],
        "  NON-FINITE pixels %d" % m["nonfinite"] if m.get("nonfinite") else "")


def _main():
    import argparse
    ap = argparse.ArgumentParser(description="Error of EST.exr against REF.exr (RGB, alpha ignored).")
    ap.add_argument("ref")
    ap.add_argument("est")
    ap.add_argument("--eps", type=float, default=EPS_RELMSE, help="relMSE epsilon (default %(default)g)")
    ap.add_argument("--json", action="store_true", help="print JSON instead of one line")
    a = ap.parse_args()
    m = metrics(load_exr(a.ref), load_exr(a.est), a.eps)
    print(json.dumps(m) if a.json else describe(m))


if __name__ == "__main__":
    _main()
