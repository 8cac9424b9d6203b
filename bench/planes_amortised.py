"""Photon planes with one plane set serving M path samples per pixel, against the path tracer, at equal time.

    /usr/bin/python3 bench/planes_amortised.py [BUDGET_S] [M,M,...] [SEED,SEED,...]
    /usr/bin/python3 bench/planes_amortised.py 16 1,0 1,2,3     # the README's table

scenes/volume_planes.blend at its own resolution, PLANES_SMIS_EXACT with `plane_surface_samples` M
(0 = the integrator's choice, reported as the `surface_samples` statistic) and PATH, each with the
time limit BUDGET_S (seconds), interleaved per seed so a change of the machine's load hits all of
them alike. Error against bench/references/volume_planes_ref.exr (made by bench/equal_time.py).
Prints one line per render and writes bench/results/planes_amortised.csv.
"""
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import metrics as M  # noqa: E402
from render import integrator_stats, remove, render_smis  # noqa: E402

COMMON = {"integrator": "PATH", "max_bounces": 1, "filter_type": "BOX", "filter_width": 1.0, "samples": 1 << 20}


def main():
    budget = float(sys.argv[1]) if len(sys.argv) > 1 else 8.0
    ms = [int(x) for x in sys.argv[2].split(",")] if len(sys.argv) > 2 else [1, 4, 16, 64, 0]
    seeds = [int(x) for x in sys.argv[3].split(",")] if len(sys.argv) > 3 else [1, 2]
    ref = M.load_exr(os.path.join(HERE, "references", "volume_planes_ref.exr"))
    estimators = [("PATH", {"volume_estimator": "PATH"})] + [
        ("PLANES_SMIS_EXACT_M%d" % m, {"volume_estimator": "PLANES_SMIS_EXACT", "plane_surface_samples": m})
        for m in ms]
    rows = []
    for seed in seeds:
        for label, extra in estimators:
            settings = dict(COMMON, time_limit=budget, seed=seed, **extra)
            run = render_smis(os.path.join(ROOT, "scenes", "volume_planes.blend"), settings)
            err = M.metrics(ref, run.image)
            stats = integrator_stats(run.output)
            row = {"estimator": label, "seed": seed, "budget_s": budget, "seconds": run.seconds,
                   "samples_done": run.samples_done, "surface_samples": stats.get("surface_samples", ""),
                   "smape": err["smape"], "relmse": err["relmse"]}
            rows.append(row)
            print("%-22s seed %d  %6.2f s  %5s iterations  M %-4s  SMAPE %.4f  relMSE %.4f" % (
                label, seed, run.seconds, run.samples_done, row["surface_samples"], err["smape"], err["relmse"]),
                flush=True)
            remove(run)
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    with open(os.path.join(HERE, "results", "planes_amortised.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


if __name__ == "__main__":
    main()
