"""Many-light direct illumination (issue 8): NEE, RIS and ReSTIR with the seed's MIS or Talbot MIS.

    /usr/bin/python3 bench/restir_bench.py            # full run (about 25 min on 2 shared cores)
    /usr/bin/python3 bench/restir_bench.py --quick    # a few minutes: budgets 2 4 s, 1 seed, 512-spp reference

Three parts, on scenes/many_lights.blend (144 area lights, 160 emissive quads, occluders; 128x128),
direct light only (max_bounces 0) with the add-on's default M, k, radius and history cap
(equal_time.RESTIR_COMMON):
1. Error against time: bench/equal_time.py's `restir` suite (NEE, RIS, RESTIR_SEED, RESTIR_TALBOT,
   both also without visibility reuse (_NOVIS: the supplement's Fig. 1 "without visibility reuse"),
   and the biased RESTIR_NONE (1/M) and RESTIR_SEED_BIASED (no visibility in the MIS)), relMSE /
   SMAPE / MSE against a converged NEE reference, estimators interleaved per budget and seed.
   Also the error over iterations: RIS, RESTIR_SEED and RESTIR_SEED with reuse across iterations
   (history cap 2) at 16/64/256 spp, relMSE x spp (constant for independent iterations).
2. The cost of Talbot's k^2 MIS: SEED and TALBOT (with and without visibility in the MIS) rendered
   side by side at a fixed sample count, interleaved, best of N (the machine is shared): the
   engine's own timing of the reuse stage (spatial combine and shading, per iteration), the pdf
   evaluations and the shadow rays of the MIS weights per pixel, for k = 5 and k = 10 neighbours.
3. Bias: the biased variants at a high sample count against the reference (image-mean ratio,
   relMSE), beside the unbiased RESTIR_SEED at the same count and their speed (samples per second).

Writes bench/results/restir_*.{csv,json} and the committed summary docs/bench/restir_summary.md
with docs/bench/restir_many_lights.{png,csv} and docs/bench/restir_cost.csv (--quick: bench/results
only, `_quick` suffix).
"""
import argparse
import csv
import datetime
import json
import os
import shutil
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import equal_time as ET  # noqa: E402
import metrics as M  # noqa: E402
from render import integrator_stats, remove, render_smis  # noqa: E402

SCENE = "many_lights"
SUITE = ET.SUITES["restir"]
DOCS = os.path.join(ROOT, "docs", "bench")
COST_VARIANTS = ["RESTIR_SEED", "RESTIR_TALBOT", "RESTIR_SEED_NOVIS", "RESTIR_TALBOT_NOVIS"]
BIAS_VARIANTS = ["RESTIR_SEED", "RESTIR_NONE", "RESTIR_SEED_BIASED"]
# Reuse across iterations on (history cap 2 x M, the former default) against the default (off).
CONVERGENCE_VARIANTS = {"RIS": ("RIS", {}), "RESTIR_SEED": ("RESTIR_SEED", {}),
                        "RESTIR_SEED_HISTORY": ("RESTIR_SEED", {"restir_history_cap": 2})}


def log(msg):
    print("[restir_bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)



def settings_of(estimator, **extra):
    settings = dict(ET.COMMON, **SUITE["estimators"][estimator])
    settings.update(extra)
    return settings


def measure_cost(blend, args):
    """Reuse-stage time per iteration, SEED against TALBOT, interleaved, best of N."""
    rows = []
    for k in args.cost_k:
        best = {}
        for rep in range(args.cost_reps):
            for est in COST_VARIANTS:  # interleaved: a load change hits every variant alike
                run = render_smis(blend, settings_of(est, samples=args.cost_spp, seed=1 + rep, time_limit=0.0,
                                                     restir_neighbors=k), threads=args.threads)
                st = integrator_stats(run.output)
                remove(run)
                reuse = st["reuse_seconds_per_iteration"]
                if est not in best or reuse < best[est]["reuse_seconds_per_iteration"]:
                    best[est] = {"k": k, "estimator": est, "reuse_seconds_per_iteration": reuse,
                                 "render_seconds": run.seconds, **st}
                log("cost k=%d %-20s rep %d: reuse %.4f s/iteration, %.1f pdf evaluations, %.1f shadow rays per pixel"
                    % (k, est, rep, reuse, st["mis_pdf_evaluations_per_pixel"], st["mis_shadow_rays_per_pixel"]))
        rows += [best[e] for e in COST_VARIANTS]
    return rows


def measure_bias(blend, ref, args):
    """Biased variants at high spp against the reference, beside the unbiased SEED."""
    rows = []
    for est in BIAS_VARIANTS:
        run = render_smis(blend, settings_of(est, samples=args.bias_spp, seed=11, time_limit=0.0),
                          threads=args.threads, timeout=7200)
        img = run.image
        m = M.metrics(ref, img, args.eps)
        rows.append({"estimator": est, "spp": args.bias_spp, "seconds": run.seconds,
                     "spp_per_second": args.bias_spp / run.seconds,
                     "mean_ratio": float(img[..., :3].mean() / ref[..., :3].mean()), **m})
        remove(run)
        log("bias %-20s %d spp in %.1f s: image mean ratio %.4f, %s"
            % (est, args.bias_spp, run.seconds, rows[-1]["mean_ratio"], M.describe(m)))
    return rows


def measure_convergence(blend, ref, ref_noise, args):
    """Equal-sample relMSE at growing sample counts: whether reuse across iterations (the history)
    correlates the iterations so that the error stops falling as 1/spp."""
    rows = []
    for spp in args.conv_spp:
        for seed in args.seeds:
            for name, (est, extra) in CONVERGENCE_VARIANTS.items():  # interleaved
                run = render_smis(blend, settings_of(est, samples=spp, seed=seed, time_limit=0.0, **extra),
                                  threads=args.threads, timeout=7200)
                m = M.metrics(ref, run.image, args.eps)
                remove(run)
                rows.append({"estimator": name, "spp": spp, "seed": seed, "seconds": run.seconds,
                             "relmse": m["relmse"], "relmse_minus_ref_noise": m["relmse"] - ref_noise})
                log("convergence %-22s %4d spp seed %d: relMSE %.5f in %.1f s" % (name, spp, seed, m["relmse"],
                                                                                  run.seconds))
    return rows


def convergence_table(rows, ref_noise):
    by = {}
    for r in rows:
        by.setdefault((r["estimator"], r["spp"]), []).append(r)
    names = list(CONVERGENCE_VARIANTS)
    lines = ["| spp | " + " | ".join("%s relMSE (x spp)" % n for n in names) + " | "
             + " | ".join("%s / RIS" % n for n in names[1:]) + " |", "|---" * (2 * len(names)) + "|"]
    for spp in sorted({r["spp"] for r in rows}):
        err = {n: float(np.mean([r["relmse"] for r in by[(n, spp)]])) for n in names}
        cells = ["%.4g (%.3g)" % (err[n], (err[n] - ref_noise) * spp) for n in names]
        ratios = ["%.3f" % ((err[n] - ref_noise) / (err["RIS"] - ref_noise)) for n in names[1:]]
        lines.append("| %d | %s | %s |" % (spp, " | ".join(cells), " | ".join(ratios)))
    return lines


def write_csv(path, rows):
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def relmse_at(agg, est, budget):
    for a in agg:
        if a["kind"] == "time" and a["estimator"] == est and a["budget_s"] == budget:
            return a
    return None


def time_to_reach(agg, est, target):
    """Seconds at which the estimator's mean relMSE curve first reaches `target` (log-log interpolation)."""
    pts = sorted((a["seconds"], a["relmse"]) for a in agg if a["kind"] == "time" and a["estimator"] == est)
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e0 >= target >= e1 and e0 > e1:
            f = np.log(e0 / target) / np.log(e0 / e1)
            return float(np.exp(np.log(t0) + f * np.log(t1 / t0)))
    # Below the target already at the smallest budget: an unbiased estimator's error falls as 1/time
    # (a measured segment's slope is too noisy to extrapolate along).
    if pts and pts[0][1] <= target:
        return pts[0][0] * pts[0][1] / target
    return None


def summary(path, doc, cost, bias, conv, args):
    agg, ref = doc["mean"], doc["reference"]
    est = doc["estimators"]
    C = ET.RESTIR_COMMON
    lines = ["# Many-light direct illumination: NEE, RIS, ReSTIR (seed MIS vs Talbot MIS)%s"
             % (" (quick run)" if args.quick else ""), "",
             "Generated by `bench/restir_bench.py%s` on %s (engine %s). Scene `scenes/many_lights.blend` "
             "(128x128; 144 area lights + 320 emissive triangles, pillars and pergola slats as occluders), "
             "max_bounces %d (direct light only, as the supplement's Fig. 1; RIS/ReSTIR act at the camera path's "
             "first non-specular vertex, deeper vertices would use NEE). M = %d candidates (RIS and ReSTIR), "
             "k = %d neighbours within %g px, history cap %d x M (0: no reuse across iterations; the add-on's "
             "defaults). The machine is "
             "shared by 4 processes (2 cores): load average %.2f at the start, %.2f at the end; every "
             "comparison is interleaved, and equal-time results move with the load."
             % (" --quick" if args.quick else "", datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
                doc["engine"]["commit"], C["max_bounces"], C["ris_candidates"], C["restir_neighbors"],
                C["restir_radius_px"], C["restir_history_cap"], doc["loadavg_start"][0], doc["loadavg_now"][0]), ""]
    lines += ["## 1. Error against time", "",
              "Reference: NEE %d spp (%.0f s), its own noise relMSE %.3g. Seeds %s. Plot: `%s`, data: `%s`."
              % (ref["spp"], ref["render_seconds"], ref["estimated_noise"]["relmse"],
                 ", ".join(map(str, doc["seeds"])), args.png_rel, args.csv_rel), ""]
    for key, label in (("relmse", "relMSE"), ("smape", "SMAPE"), ("mse", "MSE")):
        lines += ["### Equal time: %s" % label, ""] + ET.table(doc, agg, "time", key, label) + [""]
    lines += ["### Equal samples (%d spp): relMSE" % SUITE["equal_spp"], ""] + \
        ET.table(doc, agg, "spp", "relmse", "relMSE") + [""]
    # Time to reach the relMSE that NEE reaches at its largest budget.
    nee_last = max((a for a in agg if a["kind"] == "time" and a["estimator"] == "NEE"), key=lambda a: a["budget_s"])
    target = nee_last["relmse"]
    lines += ["### Time to reach relMSE %.4g (NEE's error at %g s)" % (target, nee_last["budget_s"]), "",
              "Interpolated in log-log between budgets; an estimator already below it at the smallest budget "
              "is extrapolated as error ~ 1/time.", "",
              "| estimator | seconds | speed-up over NEE |", "|---|---|---|"]
    t_nee = time_to_reach(agg, "NEE", target)
    for e in est:
        t = time_to_reach(agg, e, target)
        lines.append("| %s | %s | %s |" % (e, "%.2f" % t if t else "not reached",
                                           "%.2fx" % (t_nee / t) if t and t_nee else "-"))
    noise = ref["estimated_noise"]["relmse"]
    lines += ["", "### Error over iterations (equal samples)", "",
              "Mean relMSE over seeds %s; in brackets (relMSE - the reference's noise %.3g) x spp, which stays "
              "constant while the iterations are independent and grows when reuse correlates them. "
              "RESTIR_SEED_HISTORY reuses the previous iteration's reservoir (history cap 2 x M). The ratio "
              "columns are the noise-corrected relMSE over RIS's at the same spp." % (
                  ", ".join(map(str, args.seeds)), noise), ""] + convergence_table(conv, noise)
    lines += ["", "## 2. Cost of the MIS: k pdf evaluations (seed, Alg. 1) against k^2 (Talbot, Alg. 2)", "",
              "Fixed %d spp, best of %d interleaved repetitions; reuse time = the engine's reuse stage per "
              "iteration (spatial combine and shading, whole image, 2 threads; no temporal reuse at the "
              "default history cap 0), the pdf evaluations and shadow rays are those of the MIS weights per "
              "pixel and iteration. Data: `%s`."
              % (args.cost_spp, args.cost_reps, args.cost_rel), "",
              "| k | estimator | neighbours found | reuse s/iteration | pdf evaluations / px | MIS shadow rays / px "
              "| TALBOT / SEED reuse time |", "|---|---|---|---|---|---|---|"]
    by = {(r["k"], r["estimator"]): r for r in cost}
    for r in cost:
        seed_name = r["estimator"].replace("TALBOT", "SEED")
        ratio = r["reuse_seconds_per_iteration"] / by[(r["k"], seed_name)]["reuse_seconds_per_iteration"] \
            if "TALBOT" in r["estimator"] else None
        lines.append("| %d | %s | %.2f | %.4f | %.1f | %.1f | %s |"
                     % (r["k"], r["estimator"], r["neighbours_per_pixel"], r["reuse_seconds_per_iteration"],
                        r["mis_pdf_evaluations_per_pixel"], r["mis_shadow_rays_per_pixel"],
                        "%.2fx" % ratio if ratio else ""))
    lines += ["", "## 3. Bias of the biased variants", "",
              "%d spp each against the reference; an unbiased estimator's mean ratio is 1 within noise and "
              "its relMSE falls with samples, a biased one's stays at its bias." % args.bias_spp, "",
              "| estimator | image mean / reference | relMSE | SMAPE | samples per second |", "|---|---|---|---|---|"]
    for r in bias:
        lines.append("| %s | %.4f | %.4g | %.4g | %.1f |" % (r["estimator"], r["mean_ratio"], r["relmse"], r["smape"],
                                                          r["spp_per_second"]))
    lines.append("")
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--force-ref", action="store_true")
    ap.add_argument("--skip-time", action="store_true", help="reuse the last error-vs-time JSON")
    args = ap.parse_args()
    args.budgets = [2.0, 4.0] if args.quick else [2.0, 4.0, 8.0, 16.0]
    args.seeds = [1] if args.quick else [1, 2]
    args.ref_spp = 512 if args.quick else 4096
    args.cost_k = [5] if args.quick else [5, 10]
    args.cost_reps = 1 if args.quick else 3
    args.cost_spp = 8 if args.quick else 16
    args.bias_spp = 64 if args.quick else 256
    args.conv_spp = [4, 16] if args.quick else [16, 64, 256]
    args.eps = M.EPS_RELMSE
    # What equal_time.bench_scene expects of its arguments.
    args.estimators, args.extra, args.resume, args.strict = None, {}, False, False
    args.no_equal_spp, args.save_images = False, False
    suffix = "_quick" if args.quick else ""
    os.makedirs(ET.RESULTS, exist_ok=True)
    blend = ET.scene_blend(SCENE)

    if args.skip_time:
        with open(ET.result_base(SCENE, suffix) + ".json") as f:
            doc = json.load(f)
    else:
        doc = ET.bench_scene(SCENE, SUITE, args, suffix)
    ref, ref_rec = ET.reference(SCENE, SUITE, args.ref_spp, args.threads)
    conv = measure_convergence(blend, ref, ref_rec["estimated_noise"]["relmse"], args)
    cost = measure_cost(blend, args)
    bias = measure_bias(blend, ref, args)
    base = os.path.join(ET.RESULTS, "restir")
    write_csv(base + "_cost%s.csv" % suffix, cost)
    write_csv(base + "_bias%s.csv" % suffix, bias)
    write_csv(base + "_convergence%s.csv" % suffix, conv)
    with open(base + "%s.json" % suffix, "w") as f:
        json.dump({"cost": cost, "bias": bias, "convergence": conv}, f, indent=2)

    out_dir = ET.RESULTS if args.quick else DOCS
    png, csv_path = ET.result_base(SCENE, suffix) + ".png", ET.result_base(SCENE, suffix) + ".csv"
    if not args.quick:
        for src, dst in ((png, "restir_many_lights.png"), (csv_path, "restir_many_lights.csv"),
                         (base + "_cost.csv", "restir_cost.csv"), (base + "_bias.csv", "restir_bias.csv"),
                         (base + "_convergence.csv", "restir_convergence.csv")):
            shutil.copy(src, os.path.join(DOCS, dst))
        png, csv_path = os.path.join(DOCS, "restir_many_lights.png"), os.path.join(DOCS, "restir_many_lights.csv")
    args.png_rel, args.csv_rel = os.path.relpath(png, ROOT), os.path.relpath(csv_path, ROOT)
    args.cost_rel = os.path.relpath(os.path.join(out_dir, "restir_cost%s.csv" % suffix) if not args.quick
                                    else base + "_cost_quick.csv", ROOT)
    path = os.path.join(out_dir, "restir_summary%s.md" % suffix)
    summary(path, doc, cost, bias, conv, args)
    log("wrote %s" % os.path.relpath(path, ROOT))


if __name__ == "__main__":
    main()
