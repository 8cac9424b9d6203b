"""Single scattering at equal time on every volume scene, 512x384: our PATH, photon planes, Cycles.

    /usr/bin/python3 bench/single_scattering_equal_time.py --quick   # budgets 5 15 s, 3 seeds
    /usr/bin/python3 bench/single_scattering_equal_time.py           # budgets 5 15 60 s, 3 seeds
    /usr/bin/python3 bench/single_scattering_equal_time.py --scenes volume_spot --budgets 5 --seeds 1

Every scene of VOLUME_SCENES (scenes/build_scenes.py builds them) at 512x384 (volume_planes is
96x96 in its file and is rendered at 512x384 here), max_bounces 1 and volume bounces 0 (single
scattering), BOX 1 px filter, no denoising, no clamping:
  PATH               our volume path tracer (distance/equiangular mixture, NEE)
  PLANES_SMIS_EXACT  photon planes, SMIS with exact densities (the best plane estimator at equal
                     plane count), PLANE_COUNT planes per iteration and the integrator's own number
                     of path samples per plane set (plane_surface_samples 0)
  CYCLES             Blender 3.4's Cycles with volume bounces 0 (scenes/cycles_settings.py)
1. Reference per scene: two halves averaged, cached in bench/references/<scene>_512x384_ref.{exr,json,png}
   with its own noise estimated from the halves (the floor under every metric). With --ref-spp N
   one half is our PATH and the other Cycles, N samples each (seeds 1001/1002; independent of the
   machine's load), and the halves' mean ratio is recorded; without, two time-limited halves of our
   PATH (REF_SECONDS each). Our PATH matches Cycles within about
   1% in the means on these scenes (the accuracy test for volume_planes, and the previews of
   the new scenes), so one reference serves both engines.
2. Equal time: for each budget and seed the three estimators one after the other (interleaved, so
   a change of the machine's load hits all alike; the 1-minute load average is recorded per run).
3. Equal plane count: PLANES_UNWEIGHTED, PLANES_CMIS and PLANES_SMIS_EXACT with the same seed draw
   the same planes and the same path samples (common random numbers): ORDER_ITERATIONS iterations
   of PLANE_COUNT planes, relMSE and SMAPE against the reference, paired per seed (the paper's
   ordering is SMIS exact < CMIS < unweighted).
Writes bench/results/single_scattering[_quick].{csv,json}, one plot per scene
(bench/results/single_scattering[_quick]_<scene>.png) and docs/bench/single_scattering[_quick].md.
"""
import argparse
import csv
import datetime
import json
import os
import re
import shutil
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import metrics as M  # noqa: E402
from equal_time import engine_version, scene_blend  # noqa: E402
from render import remove, render_cycles, render_smis  # noqa: E402

VOLUME_SCENES = ["volume_planes", "volume_spot", "volume_slit", "volume_thin_hg", "volume_beams", "volume_searchlights",
                 "volume_stage"]
WIDTH, HEIGHT = 512, 384
COMMON = {"integrator": "PATH", "max_bounces": 1, "filter_type": "BOX", "filter_width": 1.0}
# Planes per iteration: small enough that one iteration (its crossings and its path samples) fits
# in the smallest budget at 512x384 on a loaded 2-core machine (volume_thin_hg: 1024 planes, 13
# crossings per camera ray, took 8 s); a longer budget runs more iterations (fresh plane sets).
PLANE_COUNT = 512
PLANES = {"photon_planes": PLANE_COUNT, "plane_surface_samples": 0}
ESTIMATORS = {
    "PATH": {"volume_estimator": "PATH"},
    "PLANES_SMIS_EXACT": dict(PLANES, volume_estimator="PLANES_SMIS_EXACT"),
    "CYCLES": None,
}
ORDER_ESTIMATORS = ["PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_EXACT"]
ORDER_ITERATIONS = 3
BUDGETS, QUICK_BUDGETS = [5.0, 15.0, 60.0], [5.0, 15.0]
SEEDS = [1, 2, 3]
REF_SECONDS, REF_SEEDS = 90.0, (1001, 1002)
RENDER_TIMEOUT = 6 * 3600  # every render here; a long reference on a loaded machine takes hours
RESOLUTION = {"resolution_x": WIDTH, "resolution_y": HEIGHT, "resolution_percentage": 100}
RESOLUTION_PRELUDE = ["scene.render.%s = %d" % kv for kv in RESOLUTION.items()]
REF_DIR = os.path.join(HERE, "references")
RESULTS = os.path.join(HERE, "results")
_CYCLES_SAMPLE = re.compile(r"Sample (\d+)/(\d+)")


def log(msg):
    print("[single_scattering %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


def smis(blend, settings, seed, budget=0.0, samples=1 << 20):
    return render_smis(blend, dict(COMMON, **settings, seed=seed, time_limit=float(budget), samples=samples),
                       render=RESOLUTION, timeout=RENDER_TIMEOUT)


def reference(name, force, seconds, half_spp=0):
    """(image, record) of the cached or freshly rendered reference of `name`.

    With half_spp: one half is our PATH, the other Cycles, half_spp samples each (a sample count, so
    the machine's load does not change the reference's noise); their mean is the reference, so a
    systematic difference between the engines is split between them instead of favouring one, and
    the half-vs-half error (noise plus that difference) is recorded. Without: two time-limited
    halves of our PATH."""
    stem = os.path.join(REF_DIR, "%s_%dx%d_ref" % (name, WIDTH, HEIGHT))
    settings = dict(COMMON, volume_estimator="PATH")
    engines = ["SMIS", "CYCLES"] if half_spp else ["SMIS", "SMIS"]
    if not force and os.path.exists(stem + ".exr") and os.path.exists(stem + ".json"):
        with open(stem + ".json") as f:
            rec = json.load(f)
        same = rec.get("settings") == settings and rec.get("engines", ["SMIS", "SMIS"]) == engines
        # A reference of fixed samples (--ref-spp) serves later runs without --ref-spp as well: it is the
        # load-independent one, and a time-limited one must not silently replace it.
        if not half_spp and rec.get("half_spp"):
            same = rec.get("settings") == settings
        else:
            same = same and (rec.get("half_spp") == half_spp if half_spp else rec.get("half_seconds") == seconds)
        if same:
            log("%s: cached reference (%d spp)" % (name, rec["spp"]))
            return M.load_exr(stem + ".exr"), rec
    halves, runs = [], []
    for engine, seed in zip(engines, REF_SEEDS):
        if engine == "CYCLES":
            run = render(name, "CYCLES", seed, samples=half_spp)
        elif half_spp:
            run = smis(scene_blend(name), {"volume_estimator": "PATH"}, seed, samples=half_spp)
        else:
            run = smis(scene_blend(name), {"volume_estimator": "PATH"}, seed, budget=seconds)
        spp = run.samples_done
        halves.append(run.image.astype(np.float64))
        runs.append({"engine": engine, "seed": seed, "spp": spp, "seconds": run.seconds,
                     "load1": os.getloadavg()[0]})
        remove(run)
        log("%s: reference half %s seed %d: %d spp in %.1f s" % (name, engine, seed, spp, run.seconds))
    a, b = halves
    ref = 0.5 * (a + b)
    ref[..., 3] = 1.0
    half_vs_half = M.metrics(a, b)
    # The engines' means, channel by channel over the image: a difference here is bias, not noise.
    mean_ratio = (a[..., :3].mean(axis=(0, 1)) / np.maximum(b[..., :3].mean(axis=(0, 1)), 1e-12)).tolist()
    rec = {"scene": name, "resolution": [WIDTH, HEIGHT], "settings": settings, "engines": engines,
           "half_seconds": None if half_spp else seconds, "half_spp": half_spp,
           "spp": sum(r["spp"] for r in runs), "halves": runs,
           "render_seconds": sum(r["seconds"] for r in runs), "half_vs_half": half_vs_half,
           "half_mean_ratio_rgb": mean_ratio,
           # independent halves: E|a-b|^2 = 2 var(half) (+ the engines' difference squared),
           # var(mean) = var(half) / 2
           "estimated_noise": {"mse": half_vs_half["mse"] / 4.0, "relmse": half_vs_half["relmse"] / 4.0,
                               "relmse_eps": half_vs_half["relmse_eps"]},
           "created": datetime.datetime.now().isoformat(timespec="seconds"), "engine": engine_version()}
    M.save_exr(stem + ".exr", ref.astype(np.float32))
    M.save_png(stem + ".png", ref.astype(np.float32))
    with open(stem + ".json", "w") as f:
        json.dump(rec, f, indent=2)
    return ref.astype(np.float32), rec


def render(name, estimator, seed, budget=0.0, samples=1 << 20):
    blend = scene_blend(name)
    if estimator == "CYCLES":
        run = render_cycles(blend, samples=samples, seed=seed, time_limit=float(budget), max_bounces=1,
                            prelude=RESOLUTION_PRELUDE, timeout=RENDER_TIMEOUT)
        found = _CYCLES_SAMPLE.findall(run.output)
        run.samples_done = max(int(d) for d, _ in found) if found else -1
        return run
    settings = ESTIMATORS.get(estimator) or dict(PLANES, volume_estimator=estimator)
    return smis(blend, settings, seed, budget, samples)


def row_of(name, kind, estimator, seed, budget, run, ref, eps):
    m = M.metrics(ref, run.image, eps)
    row = {"scene": name, "kind": kind, "estimator": estimator, "budget_s": budget, "seed": seed,
           "seconds": run.seconds, "wall_seconds": round(run.wall_seconds, 2), "samples_done": run.samples_done,
           "smape": m["smape"], "relmse": m["relmse"], "mse": m["mse"], "nonfinite": m["nonfinite"],
           "load1": round(os.getloadavg()[0], 2)}
    remove(run)
    log("%s %-18s %-6s seed %d: %.1f s, %s passes, SMAPE %.4f relMSE %.4g (load %.1f)"
        % (name, estimator, "%gs" % budget if kind == "time" else "order", seed, row["seconds"],
           row["samples_done"], row["smape"], row["relmse"], row["load1"]))
    return row


def mean_rows(rows):
    groups = {}
    for r in rows:
        groups.setdefault((r["scene"], r["kind"], r["estimator"], r["budget_s"]), []).append(r)
    out = {}
    for key, rs in groups.items():
        out[key] = {k: float(np.mean([r[k] for r in rs])) for k in ("seconds", "samples_done", "smape", "relmse")}
        out[key]["n"] = len(rs)
    return out


def plot(path, name, rows, ref_rec):
    if not any(r["scene"] == name and r["kind"] == "time" for r in rows):
        return  # an --order-only run has no equal-time rows to plot
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.0))
    styles = {"PATH": ("k", "o"), "PLANES_SMIS_EXACT": ("tab:blue", "^"), "CYCLES": ("tab:red", "D")}
    for ax, key in zip(axes, ("smape", "relmse")):
        for est, (color, marker) in styles.items():
            pts = [(r["budget_s"], r["seconds"], r[key]) for r in rows
                   if r["scene"] == name and r["kind"] == "time" and r["estimator"] == est]
            if not pts:
                continue
            budgets = sorted({p[0] for p in pts})
            x = [np.mean([p[1] for p in pts if p[0] == b]) for b in budgets]
            y = [np.mean([p[2] for p in pts if p[0] == b]) for b in budgets]
            ax.plot(x, y, marker=marker, color=color, label=est)
            ax.scatter([p[1] for p in pts], [p[2] for p in pts], color=color, s=8, alpha=0.4)
        if key == "relmse":
            ax.axhline(ref_rec["estimated_noise"]["relmse"], color="gray", linestyle=":", label="reference noise")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render time [s]")
        ax.set_ylabel(key)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("%s %dx%d: single scattering at equal time (dots: seeds)" % (name, WIDTH, HEIGHT))
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def summary(path, rows, refs, args, load_start):
    means = mean_rows(rows)
    lines = ["# Single scattering at equal time, %dx%d%s" % (WIDTH, HEIGHT, " (quick run)" if args.quick else ""), "",
             "Generated by `bench/single_scattering_equal_time.py%s` on %s (engine %s). Errors against each "
             "scene's reference (below: its halves and their noise floor), mean over seeds %s; relMSE eps %g. "
             "Time is each engine's render time (`time_limit`; Cycles' includes its sync). PLANES_SMIS_EXACT: "
             "%d planes per iteration, path samples per plane set chosen by the integrator. Ratios are SMAPE / "
             "relMSE (relMSE x seconds, the inverse efficiency ratio, in brackets: a render that overran its "
             "budget, since an iteration or a Cycles pass is not interrupted, is charged the time it took); "
             "< 1: the first is better. The machine was shared with other jobs (load average at start %.1f, per run "
             "in the CSV): the ratios side by side count, not the absolute times."
             % (" --quick" if args.quick else "", datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
                engine_version().get("commit"), ", ".join(map(str, args.seeds)), args.eps, PLANE_COUNT,
                load_start), ""]
    for name in args.scenes:
        if name not in refs:
            continue
        ref = refs[name]
        engines = ref.get("engines", ["SMIS", "SMIS"])
        kind = ("half our PATH, half Cycles (%d spp each; the halves' mean RGB ratio ours / Cycles %s)"
                % (ref["half_spp"], " ".join("%.4f" % r for r in ref["half_mean_ratio_rgb"]))
                if engines == ["SMIS", "CYCLES"] else "two time-limited halves of our PATH")
        lines += ["## %s" % name, "", "Reference: %d spp in %.0f s, %s; noise floor relMSE %.3g (from the "
                  "halves' difference, so it includes any difference between them)."
                  % (ref["spp"], ref["render_seconds"], kind, ref["estimated_noise"]["relmse"]), "",
                  "| budget | PATH SMAPE / relMSE (spp, s) | PLANES_SMIS_EXACT SMAPE / relMSE (iterations, s) | "
                  "CYCLES SMAPE / relMSE (spp, s) | PATH / CYCLES | PLANES / PATH | PLANES / CYCLES |",
                  "|---|---|---|---|---|---|---|"]
        variants = set()
        for budget in args.budgets:
            cell = {e: means.get((name, "time", e, budget)) for e in ESTIMATORS}
            if not any(cell.values()):
                continue

            def fmt(a):
                return "%.4f / %.4g (%.0f, %.1f)" % (a["smape"], a["relmse"], a["samples_done"], a["seconds"]) if a else "-"

            def rat(a, b):
                # relMSE ratio at the times actually taken, and the efficiency ratio relMSE x seconds
                # (an iteration or a pass that overran its budget is charged its time)
                return ("%.2f / %.2f (%.2f)" % (a["smape"] / b["smape"], a["relmse"] / b["relmse"],
                                                a["relmse"] * a["seconds"] / (b["relmse"] * b["seconds"])))\
                    if a and b else "-"
            p, q, c = cell["PATH"], cell["PLANES_SMIS_EXACT"], cell.get("CYCLES")
            lines.append("| %g s | %s | %s | %s | %s | %s | %s |" % (budget, fmt(p), fmt(q), fmt(c), rat(p, c),
                                                                    rat(q, p), rat(q, c)))
            variants.update((e, budget) for e in cell if e.startswith("PLANES_SMIS_EXACT+") and cell[e])
        for e, budget in sorted(variants):  # --planes-variant runs, against PATH and the plain planes
            a = means.get((name, "time", e, budget))
            p, q = means.get((name, "time", "PATH", budget)), means.get((name, "time", "PLANES_SMIS_EXACT", budget))
            lines.append("| %g s | %s `%s`: %s | / PATH %s | / PLANES_SMIS_EXACT %s | | | |"
                         % (budget, e, json.dumps(ESTIMATORS.get(e)), fmt(a), rat(a, p), rat(a, q)))
        order = [r for r in rows if r["scene"] == name and r["kind"] == "order"]
        if order:
            lines += ["", "Equal plane count (%d iterations x %d planes, same planes and path samples per seed):"
                      % (ORDER_ITERATIONS, PLANE_COUNT), "",
                      "| seed | " + " | ".join("%s relMSE / SMAPE" % e for e in ORDER_ESTIMATORS) + " | ordering holds |",
                      "|---|" + "---|" * (len(ORDER_ESTIMATORS) + 1)]
            for seed in args.seeds:
                by = {r["estimator"]: r for r in order if r["seed"] == seed}
                if len(by) < len(ORDER_ESTIMATORS):
                    continue
                vals = [by[e] for e in ORDER_ESTIMATORS]
                holds = all(vals[i + 1]["relmse"] < vals[i]["relmse"] for i in range(len(vals) - 1))
                lines.append("| %d | %s | %s |" % (seed, " | ".join("%.4g / %.4f" % (v["relmse"], v["smape"])
                                                                   for v in vals), "yes" if holds else "**no**"))
        # the plot beside the summary (bench/results is not tracked)
        plot_name = "%s_%s.png" % (args.stem, name)
        if any(r["scene"] == name and r["kind"] == "time" for r in rows):
            shutil.copyfile(os.path.join(RESULTS, plot_name), os.path.join(os.path.dirname(path), plot_name))
            lines += ["", "Plot: [%s](%s)." % (plot_name, plot_name)]
        lines.append("")
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="budgets 5 15 s (the full run adds 60 s)")
    ap.add_argument("--scenes", nargs="+", default=VOLUME_SCENES)
    ap.add_argument("--budgets", nargs="+", type=float, default=None)
    ap.add_argument("--seeds", nargs="+", type=int, default=SEEDS)
    ap.add_argument("--no-order", action="store_true", help="skip the equal-plane-count ordering")
    ap.add_argument("--order-only", action="store_true", help="only the equal-plane-count ordering")
    ap.add_argument("--force-ref", action="store_true")
    ap.add_argument("--ref-seconds", type=float, default=REF_SECONDS, help="time limit of each reference half")
    ap.add_argument("--ref-spp", type=int, default=0,
                    help="samples of each reference half; halves are then our PATH and Cycles (0: two "
                         "time-limited halves of our PATH)")
    ap.add_argument("--ref-only", action="store_true", help="only render (or load) the references")
    ap.add_argument("--eps", type=float, default=M.EPS_RELMSE)
    ap.add_argument("--summarize", action="store_true", help="only rewrite the summary and plots from the JSON")
    ap.add_argument("--stem", default=None, help="results name (default single_scattering[_quick])")
    ap.add_argument("--merge", nargs="*", default=[], help="with --summarize: more runs' stems, whose scenes replace")
    ap.add_argument("--planes-variant", action="append", default=[], metavar="LABEL:KEY=VALUE[,KEY=VALUE]",
                    help="one more PLANES_SMIS_EXACT run per budget and seed with these settings, named "
                         "PLANES_SMIS_EXACT+LABEL (interleaved with the others; e.g. k2:plane_min_crossings=2)")
    ap.add_argument("--no-cycles", action="store_true", help="leave Cycles out of the equal-time runs")
    args = ap.parse_args()
    for variant in args.planes_variant:
        label, _, pairs = variant.partition(":")
        extra = {k: json.loads(v) for k, v in (kv.split("=", 1) for kv in pairs.split(",") if kv)}
        ESTIMATORS["PLANES_SMIS_EXACT+" + label] = dict(ESTIMATORS["PLANES_SMIS_EXACT"], **extra)
    if args.no_cycles:
        del ESTIMATORS["CYCLES"]
    args.budgets = args.budgets or (QUICK_BUDGETS if args.quick else BUDGETS)
    args.stem = args.stem or "single_scattering" + ("_quick" if args.quick else "")
    if args.summarize:  # the Markdown summary again from the JSONs of earlier runs (later ones win per scene)
        doc = {"rows": [], "references": {}}
        for stem in [args.stem] + args.merge:
            with open(os.path.join(RESULTS, stem + ".json")) as f:
                part = json.load(f)
            doc["rows"] = [r for r in doc["rows"] if r["scene"] not in part["references"]] + part["rows"]
            doc["references"].update(part["references"])
            doc.update({k: part[k] for k in ("seeds", "budgets", "loadavg_start")})
        args.seeds, args.budgets = doc["seeds"], doc["budgets"]
        args.scenes = [n for n in args.scenes if n in doc["references"]]
        for name in args.scenes:
            plot(os.path.join(RESULTS, "%s_%s.png" % (args.stem, name)), name, doc["rows"], doc["references"][name])
        summary(os.path.join(ROOT, "docs", "bench", args.stem + ".md"), doc["rows"], doc["references"], args,
                doc["loadavg_start"])
        return
    os.makedirs(RESULTS, exist_ok=True)
    load_start = os.getloadavg()[0]
    rows, refs = [], {}
    out_json = os.path.join(RESULTS, args.stem + ".json")
    for name in args.scenes:
        ref, refs[name] = reference(name, args.force_ref, args.ref_seconds, args.ref_spp)
        if args.ref_only:
            continue
        for budget in [] if args.order_only else args.budgets:
            for seed in args.seeds:
                for est in ESTIMATORS:
                    rows.append(row_of(name, "time", est, seed, budget, render(name, est, seed, budget), ref, args.eps))
        if not args.no_order:
            for seed in args.seeds:
                for est in ORDER_ESTIMATORS:
                    run = render(name, est, seed, samples=ORDER_ITERATIONS)
                    rows.append(row_of(name, "order", est, seed, 0.0, run, ref, args.eps))
        plot(os.path.join(RESULTS, "%s_%s.png" % (args.stem, name)), name, rows, refs[name])
        with open(out_json, "w") as f:
            json.dump({"resolution": [WIDTH, HEIGHT], "budgets": args.budgets, "seeds": args.seeds,
                       "plane_count": PLANE_COUNT, "estimators": ESTIMATORS, "references": refs,
                       "loadavg_start": load_start, "engine": engine_version(), "rows": rows}, f, indent=1)
        with open(os.path.join(RESULTS, args.stem + ".csv"), "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
        summary(os.path.join(ROOT, "docs", "bench", args.stem + ".md"), rows, refs, args, load_start)
    if args.ref_only:  # the loop wrote no results: say so rather than name files it did not touch
        log("references ready: %s" % ", ".join(args.scenes))
    else:
        log("wrote %s and docs/bench/%s.md" % (os.path.relpath(out_json, ROOT), args.stem))


if __name__ == "__main__":
    main()
