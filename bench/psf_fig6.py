"""Equal-sample comparison that isolates the weighting (West et al. 2020, Fig. 6): PSF_KELLER and
PSF_SMIS on the same gathered paths (same seed, radius and neighbours), 8 paths per pixel, against
the converged PATH reference of equal_time.py, averaged over seeds; PSF_PATH (no reuse) beside them.

    /usr/bin/python3 bench/psf_fig6.py [--scene psf_glossy] [--spp 8] [--seeds 1 2 3]

Writes bench/results/psf_fig6_<scene>.{json,md}. The paper reports PSF_SMIS / Keller = 0.78x SMAPE
and 0.07x MSE on its scene."""
import argparse
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from metrics import load_exr, metrics  # noqa: E402
from render import remove, render_smis  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--scene", default="psf_glossy")
ap.add_argument("--spp", type=int, default=8)
ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
ap.add_argument("--max-neighbors", type=int, default=24)  # the engine's default
a = ap.parse_args()

ref_path = os.path.join(HERE, "references", a.scene + "_ref.exr")
if not os.path.exists(ref_path):
    raise SystemExit(f"missing {ref_path}: run bench/equal_time.py --suite psf first (it renders and caches it)")
ref = load_exr(ref_path)
blend = os.path.join(ROOT, "scenes", a.scene + ".blend")
integrators = ["PSF_PATH", "PSF_KELLER", "PSF_SMIS"]
rows = {}
for name in integrators:
    ms = []
    for seed in a.seeds:
        run = render_smis(blend, {"samples": a.spp, "seed": seed, "integrator": name, "max_bounces": 8,
                                  "filter_type": "BOX", "filter_width": 1.0,
                                  "psf_max_neighbors": a.max_neighbors})
        ms.append(metrics(ref, run.image))
        remove(run)
    rows[name] = {k: sum(m[k] for m in ms) / len(ms) for k in ("smape", "relmse", "mse")}
    print(name, rows[name], flush=True)

k, s = rows["PSF_KELLER"], rows["PSF_SMIS"]
result = {"scene": a.scene, "spp": a.spp, "seeds": a.seeds, "psf_max_neighbors": a.max_neighbors,
          "psf_radius_px": 6.0, "keller_normal_cos": 0.9, "keller_plane": 0.1, "metrics": rows,
          "smis_over_keller": {m: s[m] / k[m] for m in ("smape", "relmse", "mse")},
          "paper_smis_over_keller": {"smape": 0.78, "mse": 0.07}}
os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
with open(os.path.join(HERE, "results", f"psf_fig6_{a.scene}.json"), "w") as f:
    json.dump(result, f, indent=2)
lines = [f"# Fig. 6 set-up on {a.scene}: {a.spp} paths/pixel, seeds {a.seeds}, "
         f"{a.max_neighbors} techniques, radius 6 px, Keller thresholds cos 0.9 / plane 0.1 r", "",
         "| integrator | SMAPE | relMSE (eps 0.01) | MSE |", "|---|---|---|---|"]
lines += [f"| {n} | {r['smape']:.4f} | {r['relmse']:.4g} | {r['mse']:.4g} |" for n, r in rows.items()]
lines += ["", f"PSF_SMIS / PSF_KELLER: SMAPE {result['smis_over_keller']['smape']:.3f}x "
          f"(paper 0.78x), MSE {result['smis_over_keller']['mse']:.4f}x (paper 0.07x)"]
with open(os.path.join(HERE, "results", f"psf_fig6_{a.scene}.md"), "w") as f:
    f.write("\n".join(lines) + "\n")
print("\n".join(lines))
