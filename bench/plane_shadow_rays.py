"""Russian roulette on the photon planes' visibility (issue 22): of a camera ray's plane crossings,
about K trace their shadow ray, chosen by unshadowed contribution and divided by their probability
(settings.plane_shadow_rays; 0 traces one per crossing). Error and time per iteration for each K,
side by side in one run, on scenes/volume_planes.blend (planes_bench's set-up: camera rays' single
scattering only, 48x48, PLANES_SMIS_EXACT with 40,960 planes), and the efficiency 1 / (MSE x time)
relative to K = 0.

    blender -b --factory-startup --addons smis_render --python bench/plane_shadow_rays.py -- [--quick]

Writes bench/results/plane_shadow_rays.{json,csv} and docs/bench/plane_shadow_rays.md.
"""
import csv
import json
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import planes_bench as pb  # noqa: E402

KS = [0, 4, 16, 64, 256, 1024]
SEEDS = 3 if pb.QUICK else 6


def main():
    scene, base = pb.export_scene()
    ref = pb.reference(scene, base)
    rows = []
    for seed in range(1, SEEDS + 1):
        for k in KS:  # interleaved, so load on the machine hits every K alike
            img, secs, stats, _ = pb.render(scene, dict(base, plane_shadow_rays=k),
                                            "PLANES_SMIS_EXACT", 1, seed)
            rows.append({"K": k, "seed": seed, "seconds": secs, "mse": pb.mse(ref, img),
                         "smape": pb.smape(ref, img), "plane_hits": stats.get("plane_hits", 0.0),
                         "shadow_rays": stats.get("shadow_rays", 0.0)})
        pb.log("seed %d: %s" % (seed, "  ".join("K=%d %.2fs" % (r["K"], r["seconds"]) for r in rows[-len(KS):])))
    summary = []
    for k in KS:
        sel = [r for r in rows if r["K"] == k]
        summary.append({"K": k, **{key: float(np.mean([r[key] for r in sel]))
                                   for key in ("seconds", "mse", "smape", "plane_hits", "shadow_rays")}})
    t0, m0 = summary[0]["seconds"], summary[0]["mse"]
    for s in summary:
        s["efficiency_vs_all"] = (m0 * t0) / (s["mse"] * s["seconds"])
    os.makedirs(pb.RESULTS, exist_ok=True)
    with open(os.path.join(pb.RESULTS, "plane_shadow_rays.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)
    with open(os.path.join(pb.RESULTS, "plane_shadow_rays.json"), "w") as f:
        json.dump({"rows": rows, "summary": summary, "quick": pb.QUICK}, f, indent=1)
    lines = ["# Photon planes: Russian roulette on visibility", "",
             "`bench/plane_shadow_rays.py`%s: scenes/volume_planes.blend at 48x48, camera rays' single "
             "scattering, PLANES_SMIS_EXACT, 40,960 planes, one iteration, mean over %d seeds (K interleaved). "
             "Efficiency = MSE x time of K = 0 over that of K (equal-time error ratio; > 1 is better)." %
             (" --quick" if pb.QUICK else "", SEEDS), "",
             "| K | shadow rays / iteration | plane crossings | seconds | MSE | SMAPE | efficiency vs K = 0 |",
             "|---|---|---|---|---|---|---|"]
    for s in summary:
        lines.append("| %s | %.0f | %.0f | %.3f | %.4g | %.4f | %.2fx |" % (
            s["K"] if s["K"] else "0 (all)", s["shadow_rays"], s["plane_hits"], s["seconds"], s["mse"], s["smape"],
            s["efficiency_vs_all"]))
    out = os.path.join(pb.RESULTS if pb.QUICK else pb.DOCS, "plane_shadow_rays.md")
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


main()
sys.stdout.flush()
os._exit(0)
