"""Where the photon planes' SMAPE comes from: per-pixel SMAPE of PATH and PLANES_SMIS_EXACT at equal time.

    /usr/bin/python3 bench/planes_smape_map.py SCENE BUDGET_S SEED[,SEED...] ['{"NAME": {settings}, ...}']
    /usr/bin/python3 bench/planes_smape_map.py volume_spot 15 1,2

512x384 against bench/references/<scene>_512x384_ref.exr (bench/single_scattering_equal_time.py makes
it). The pixels are split by the volume's share of the reference (from a max_bounces 0 planes render,
30 s, cached in OUT): > 0.8, mixed, < 0.2; per class the mean SMAPE / relMSE and its share of the
image's SMAPE, with the planes' statistics (iterations, surface_samples, thread time of the path
samples and of the gathering). Optional variants: more estimators as a JSON dict of settings.
Images go to OUT (default /tmp/planes_smape_map) as .npy.
"""
import json
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUT = os.environ.get("OUT", "/tmp/planes_smape_map")
sys.path.insert(0, HERE)
import metrics as M
from render import render_smis, remove, integrator_stats
W, H = 512, 384
RES = {"resolution_x": W, "resolution_y": H, "resolution_percentage": 100}
COMMON = {"integrator": "PATH", "max_bounces": 1, "filter_type": "BOX", "filter_width": 1.0, "samples": 1 << 20}

def run(scene, settings, seed, budget):
    s = dict(COMMON, seed=seed, time_limit=float(budget)); s.update(settings)
    r = render_smis(os.path.join(ROOT, "scenes", scene + ".blend"), s, render=RES)
    img = r.image.astype(np.float64)[..., :3]
    st = integrator_stats(r.output)
    out = (img, r.seconds, r.samples_done, st)
    remove(r)
    return out

def smape_map(ref, est):
    num = np.abs(ref - est); den = np.abs(ref) + np.abs(est)
    return np.where(den > 0, num / np.where(den > 0, den, 1), 0).mean(axis=-1)

def main():
    os.makedirs(OUT, exist_ok=True)
    scene = sys.argv[1]; budget = float(sys.argv[2]); seeds = [int(x) for x in sys.argv[3].split(",")]
    variants = json.loads(sys.argv[4]) if len(sys.argv) > 4 else {}
    ref = M.load_exr(os.path.join(ROOT, "bench", "references", "%s_512x384_ref.exr" % scene)).astype(np.float64)[..., :3]
    volpath = os.path.join(OUT, "%s_vol.npy" % scene)
    if os.path.exists(volpath):
        vol = np.load(volpath)
    else:
        vol, secs, n, st = run(scene, {"volume_estimator": "PLANES_SMIS_EXACT", "photon_planes": 4096,
                                        "max_bounces": 0}, 77, 30)
        np.save(volpath, vol)
        print("volume-only planes render: %.1f s, %d iterations" % (secs, n))
    lum = lambda a: a.mean(axis=-1)
    frac = np.clip(lum(vol) / np.maximum(lum(ref), 1e-8), 0, 1)
    classes = {"vol>0.8": frac > 0.8, "mixed": (frac >= 0.2) & (frac <= 0.8), "surf<0.2": frac < 0.2}
    print(scene, "pixel classes:", {k: round(float(v.mean()), 3) for k, v in classes.items()})
    ests = {"PATH": {"volume_estimator": "PATH"},
            "PLANES": {"volume_estimator": "PLANES_SMIS_EXACT", "photon_planes": 512, "plane_surface_samples": 0}}
    ests.update(variants)
    for seed in seeds:
        for name, st in ests.items():
            img, secs, n, stats = run(scene, st, seed, budget)
            sm = smape_map(ref, img)
            rel = (((img - ref) ** 2) / (ref ** 2 + 0.01)).mean(axis=-1)
            np.save(os.path.join(OUT, "%s_%s_%d.npy" % (scene, name, seed)), img.astype(np.float32))
            parts = "  ".join("%s %.3f/%.3g (share %.2f)" % (k, sm[m].mean(), rel[m].mean(), sm[m].sum() / sm.sum())
                              for k, m in classes.items())
            keys = ("iterations", "surface_samples", "plane_hits", "shadow_rays", "build_seconds", "render_seconds",
                    "path_thread_seconds", "gather_thread_seconds")
            print("%s seed %d %-10s %.1f s %s it  SMAPE %.4f relMSE %.4g | %s | %s  load %.1f" % (
                scene, seed, name, secs, n, sm.mean(), rel.mean(), parts,
                {k: stats[k] for k in keys if k in stats}, os.getloadavg()[0]), flush=True)


if __name__ == "__main__":
    main()
