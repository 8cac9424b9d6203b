"""Equal-time comparison of path-space filtering integrators (West et al. 2020, Sec. 4.4, Figs. 4-5).

    /usr/bin/python3 bench/psf_bench.py            # full run: ~25 min on 2 cores, + ~9 min of references
    /usr/bin/python3 bench/psf_bench.py --quick    # CI-sized: budgets 2 4 8 s, 1 seed: ~4 min (+ ~1 min)
    /usr/bin/python3 bench/psf_bench.py --integrators PATH --budgets 2 4 --seeds 1   # pipeline check

For each scene (scenes/psf_glossy.blend, scenes/psf_room.blend; built with scenes/build_scenes.py
when missing):

1. Reference: PATH, `--ref-spp` samples per pixel (default 4096; 512 with --quick) rendered as two
   independent halves (seeds 1001 and 1002, spp/2 each) and averaged, cached in
   bench/references/<scene>_ref.exr with bench/references/<scene>_ref.json (spp, seeds, settings,
   render seconds, and the reference's own noise measured from the two halves). A cached reference
   is reused when its settings match and it has at least the requested spp; otherwise it is
   re-rendered (--force-ref after changing a scene or the path tracer). Cost, measured on this
   2-core machine (shared, so effectively one core): 4096 spp took 222 s (psf_glossy) and 329 s
   (psf_room); estimated noise of those references: relMSE 4.6e-4 and 2.4e-4, about a tenth of
   PATH's error at 32 s. The reference noise sets a floor under every metric: its estimated MSE and
   relMSE (half-vs-half value / 4, the noise of the average) are in the JSON, in the summary, and
   drawn as a dotted line on the relMSE plot; read errors near that floor as "converged".
2. For each integrator (default PATH, PSF_KELLER, PSF_SMIS), time budget (default 2 4 8 16 32 s,
   set through scene.smis.time_limit with samples = 2^20 so that time is the only limit) and seed
   (default 1 2 3): render with our engine and compute SMAPE, relMSE (eps stated, default 1e-2) and
   MSE against the reference (bench/metrics.py). Time is the engine's own render time from its
   final stats line (export and Blender start-up excluded; 0.1 s resolution).
3. Write bench/results/psf_{glossy,room}.csv (one row per render, plus one 'mean' row per integrator
   and budget), psf_{glossy,room}.json (everything, including the reference record and any
   integrator that failed, the engine's commit and modified files), psf_{glossy,room}.png (log-log SMAPE and relMSE against mean
   render seconds, one line per integrator) and bench/results/psf_summary.md (per scene and
   budget: the winner by SMAPE and by relMSE, each integrator's error relative to PATH, and the
   winner's margin over the runner-up). --quick writes the same files with a `_quick` suffix so it
   never overwrites a full run.

Common render settings: max_bounces 8 (as the scenes' Cycles settings), BOX pixel filter 1 px (as
our Cycles references), everything else the add-on's defaults (psf_radius_px etc.) unless given
with --set KEY=VALUE (applied to scene.smis for every render except the reference) or
--psf-radius R (only for PSF_* integrators). An integrator the add-on does not offer (or that
fails) is skipped with its error recorded; --strict aborts instead. The machine is shared: the
load average at the start and end is recorded, since equal-time results depend on it.
"""
import argparse
import csv
import datetime
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import metrics as M  # noqa: E402
from render import RenderError, parse_value, remove, render_smis  # noqa: E402

SCENES = ["psf_glossy", "psf_room"]
INTEGRATORS = ["PATH", "PSF_KELLER", "PSF_SMIS"]
BUDGETS = [2.0, 4.0, 8.0, 16.0, 32.0]
SEEDS = [1, 2, 3]
REF_SPP = 4096
QUICK = {"budgets": [2.0, 4.0, 8.0], "seeds": [1], "ref_spp": 512}
REF_SEEDS = (1001, 1002)
MAX_SAMPLES = 1 << 20
COMMON = {"max_bounces": 8, "filter_type": "BOX", "filter_width": 1.0}
REF_DIR = os.path.join(HERE, "references")
RESULTS = os.path.join(HERE, "results")


def log(msg):
    print("[psf_bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


def scene_blend(name):
    path = os.path.join(ROOT, "scenes", name + ".blend")
    if not os.path.exists(path):
        log("building %s with scenes/build_scenes.py" % path)
        subprocess.run(["blender", "-b", "--factory-startup", "--python",
                        os.path.join(ROOT, "scenes", "build_scenes.py"), "--", name],
                       check=True, capture_output=True)
    return path


def engine_version():
    """Commit and local changes of the engine sources, to tell which engine made a reference."""
    def git(*a):
        try:
            return subprocess.run(["git", "-C", ROOT, *a], capture_output=True, text=True,
                                  timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""
    dirty = [ln[3:] for ln in git("status", "--porcelain", "--", "engine", "addon").splitlines()]
    return {"commit": git("rev-parse", "--short", "HEAD"), "modified": dirty}


# ----------------------------------------------------------------------------------------------
# reference
# ----------------------------------------------------------------------------------------------
def reference(name, spp, threads, force=False):
    """(image (h, w, 4), record dict) of the cached or freshly rendered PATH reference."""
    os.makedirs(REF_DIR, exist_ok=True)
    exr = os.path.join(REF_DIR, name + "_ref.exr")
    meta = os.path.join(REF_DIR, name + "_ref.json")
    settings = dict(COMMON, integrator="PATH")
    if not force and os.path.exists(exr) and os.path.exists(meta):
        with open(meta) as f:
            rec = json.load(f)
        if rec.get("spp", 0) >= spp and rec.get("settings") == settings:
            log("%s: cached reference %s (%d spp)" % (name, os.path.relpath(exr, ROOT), rec["spp"]))
            return M.load_exr(exr), rec
        log("%s: cached reference has %s spp / other settings: re-rendering" % (name, rec.get("spp")))
    half = (spp + 1) // 2
    blend = scene_blend(name)
    halves, runs = [], []
    for seed in REF_SEEDS:
        log("%s: reference half, PATH %d spp, seed %d" % (name, half, seed))
        run = render_smis(blend, dict(settings, samples=half, seed=seed, time_limit=0.0), threads=threads,
                          timeout=7200)
        halves.append(run.image.astype(np.float64))
        runs.append(run.summary())
        remove(run)
        log("%s: half done in %.1f s" % (name, run.seconds))
    a, b = halves
    ref = 0.5 * (a + b)
    ref[..., 3] = 1.0
    half_vs_half = M.metrics(a, b)
    rec = {
        "scene": name, "blend": os.path.relpath(blend, ROOT), "integrator": "PATH", "spp": 2 * half,
        "halves": [{"seed": s, "spp": half, "seconds": r["seconds"]} for s, r in zip(REF_SEEDS, runs)],
        "render_seconds": sum(r["seconds"] for r in runs), "settings": settings,
        "threads": threads or os.cpu_count(),
        "half_vs_half": half_vs_half,
        # independent halves: E|a-b|^2 = 2 var(half) and var(mean) = var(half)/2 = E|a-b|^2 / 4
        "estimated_noise": {"mse": half_vs_half["mse"] / 4.0, "relmse": half_vs_half["relmse"] / 4.0,
                            "relmse_eps": half_vs_half["relmse_eps"]},
        "created": datetime.datetime.now().isoformat(timespec="seconds"),
        "engine": engine_version(),
        "note": "mean of two PATH renders with different seeds; estimated_noise is the expected "
                "MSE/relMSE of this reference against the true image (a floor under every metric)",
    }
    M.save_exr(exr, ref.astype(np.float32))
    M.save_png(os.path.join(REF_DIR, name + "_ref.png"), ref.astype(np.float32))
    with open(meta, "w") as f:
        json.dump(rec, f, indent=2)
    log("%s: reference written (%d spp, %.0f s; noise floor relMSE %.3g)"
        % (name, rec["spp"], rec["render_seconds"], rec["estimated_noise"]["relmse"]))
    return ref.astype(np.float32), rec


# ----------------------------------------------------------------------------------------------
# runs
# ----------------------------------------------------------------------------------------------
def result_base(name, suffix):
    """bench/results/psf_glossy<suffix> for scene psf_glossy (no doubled 'psf_')."""
    short = name[4:] if name.startswith("psf_") else name
    return os.path.join(RESULTS, "psf_%s%s" % (short, suffix))


def run_key(r):
    return (r["integrator"], float(r["budget_s"]), int(r["seed"]))


def failure_reason(text):
    """The most telling line of a failed render's output."""
    lines = [ln.strip() for ln in text.strip().splitlines() if ln.strip()]
    for pattern in ("enum", "TypeError", "AttributeError", "ValueError", "RuntimeError", "Error", "rror"):
        hits = [ln for ln in lines if pattern in ln and "script failed" not in ln]
        if hits:
            return hits[-1][:400]
    return (lines or ["unknown failure"])[-1][:400]


def settings_for(integrator, budget, seed, args):
    s = dict(COMMON, integrator=integrator, samples=MAX_SAMPLES, time_limit=float(budget), seed=seed)
    if integrator.startswith("PSF") and args.psf_radius is not None:
        s["psf_radius_px"] = float(args.psf_radius)
    s.update(args.extra)
    return s


def bench_scene(name, args, suffix):
    ref, ref_rec = reference(name, args.ref_spp, args.threads, args.force_ref)
    blend = scene_blend(name)
    out_json = result_base(name, suffix) + ".json"
    done = {}
    if args.resume and os.path.exists(out_json):
        with open(out_json) as f:
            old = json.load(f)
        if old.get("reference", {}).get("created") == ref_rec.get("created"):
            done = {run_key(r): r for r in old.get("runs", [])}
            log("%s: resuming, %d runs already done" % (name, len(done)))
    runs, failed = [], {}
    load_start = os.getloadavg()
    img_dir = os.path.join(RESULTS, "psf_images%s" % suffix, name)  # EXR + PNG per run
    for integrator in args.integrators:
        for budget in args.budgets:
            for seed in args.seeds:
                if integrator in failed:
                    continue
                settings = settings_for(integrator, budget, seed, args)
                key = (integrator, float(budget), int(seed))
                if (key in done and done[key].get("settings") == settings
                        and done[key].get("relmse_eps") == args.eps):
                    runs.append(done[key])
                    continue
                try:
                    run = render_smis(blend, settings, threads=args.threads, timeout=max(600, 20 * budget))
                except RenderError as exc:
                    failed[integrator] = failure_reason(str(exc))
                    log("%s: %s FAILED: %s" % (name, integrator, failed[integrator]))
                    if args.strict:
                        raise
                    continue
                img = run.image
                m = M.metrics(ref, img, args.eps)
                row = {"scene": name, "integrator": integrator, "budget_s": float(budget), "seed": seed,
                       "seconds": run.seconds, "wall_seconds": round(run.wall_seconds, 3),
                       "samples_done": run.samples_done, **m, "settings": settings}
                runs.append(row)
                if args.save_images and seed == args.seeds[0]:
                    os.makedirs(img_dir, exist_ok=True)
                    stem = os.path.join(img_dir, "%s_%gs" % (integrator, budget))
                    M.save_exr(stem + ".exr", img)
                    M.save_png(stem + ".png", img)
                remove(run)
                log("%s: %-11s %5.1f s budget seed %d: %.1f s, %d spp, %s"
                    % (name, integrator, budget, seed, run.seconds, run.samples_done, M.describe(m)))
                write_scene(name, suffix, ref_rec, runs, failed, args, load_start, partial=True)
    return write_scene(name, suffix, ref_rec, runs, failed, args, load_start, partial=False)


def aggregate(runs):
    """Mean (and min/max) over seeds per (integrator, budget)."""
    groups = {}
    for r in runs:
        groups.setdefault((r["integrator"], r["budget_s"]), []).append(r)
    out = []
    for (integ, budget), rs in groups.items():
        agg = {"integrator": integ, "budget_s": budget, "n_seeds": len(rs)}
        for k in ("seconds", "wall_seconds", "samples_done", "smape", "relmse", "mse"):
            vals = np.array([r[k] for r in rs], dtype=np.float64)
            agg[k] = float(vals.mean())
            if k in ("smape", "relmse", "mse"):
                agg[k + "_min"], agg[k + "_max"] = float(vals.min()), float(vals.max())
        agg["relmse_eps"] = rs[0]["relmse_eps"]
        out.append(agg)
    return out


CSV_FIELDS = ["scene", "kind", "integrator", "budget_s", "seed", "seconds", "wall_seconds", "samples_done",
              "smape", "relmse", "relmse_eps", "mse"]


def write_scene(name, suffix, ref_rec, runs, failed, args, load_start, partial):
    os.makedirs(RESULTS, exist_ok=True)
    agg = aggregate(runs)
    doc = {
        "scene": name, "partial": partial, "quick": args.quick,
        "integrators": args.integrators, "budgets_s": args.budgets, "seeds": args.seeds,
        "relmse_eps": args.eps, "common_settings": COMMON, "extra_settings": args.extra,
        "psf_radius_px": args.psf_radius, "threads": args.threads or os.cpu_count(),
        "loadavg_start": load_start, "loadavg_now": os.getloadavg(),
        "engine": engine_version(), "reference": ref_rec, "failed": failed, "mean": agg, "runs": runs,
        "written": datetime.datetime.now().isoformat(timespec="seconds"),
    }
    base = result_base(name, suffix)
    with open(base + ".json", "w") as f:
        json.dump(doc, f, indent=2)
    with open(base + ".csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=CSV_FIELDS, extrasaction="ignore")
        w.writeheader()
        for r in runs:
            w.writerow(dict(r, kind="run"))
        for a in agg:
            w.writerow(dict(a, scene=name, kind="mean", seed="mean"))
    if not partial:
        plot(base + ".png", name, agg, ref_rec, args)
    return doc


def plot(path, name, agg, ref_rec, args):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    styles = {"PATH": ("k", "o"), "PSF_KELLER": ("tab:orange", "s"), "PSF_SMIS": ("tab:blue", "^"),
              "PSF_SMIS_UNBIASED": ("tab:green", "v"), "PSF_PATH": ("tab:gray", "x")}
    for ax, key, label in ((axes[0], "smape", "SMAPE"),
                           (axes[1], "relmse", "relMSE (eps=%g)" % args.eps)):
        for integ in args.integrators:
            pts = sorted((a["seconds"], a[key], a[key + "_min"], a[key + "_max"]) for a in agg
                         if a["integrator"] == integ)
            if not pts:
                continue
            x, y, lo, hi = (np.array(v) for v in zip(*pts))
            color, marker = styles.get(integ, (None, "d"))
            ax.plot(x, y, marker=marker, color=color, label=integ)
            if len(args.seeds) > 1:
                ax.fill_between(x, lo, hi, color=color, alpha=0.15, linewidth=0)
        if key == "relmse" and args.eps == ref_rec["estimated_noise"]["relmse_eps"]:
            ax.axhline(ref_rec["estimated_noise"]["relmse"], color="gray", linestyle=":",
                       label="reference noise")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xticks(args.budgets)
        ax.set_xticklabels(["%g" % b for b in args.budgets])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("render time [s] (engine time, mean over seeds)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("%s: equal-time error vs PATH reference (%d spp), %d seed(s)"
                 % (name, ref_rec["spp"], len(args.seeds)))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# summary
# ----------------------------------------------------------------------------------------------
def summary(docs, path, args):
    lines = ["# Path-space filtering: equal-time comparison%s" % (" (quick run)" if args.quick else ""), "",
             "Generated by `bench/psf_bench.py%s` on %s. Errors are against a converged PATH "
             "reference and averaged over seeds; time is the engine's render time "
             "(`scene.smis.time_limit` budget, Blender start-up and export excluded). "
             "SMAPE = mean |r-e|/(|r|+|e|) (West et al. 2020, Sec. 4.4); relMSE = mean (e-r)^2/(r^2+eps) "
             "with eps = %g; both per channel, lower is better. Ratios are `integrator / PATH` "
             "(< 1: better than path tracing) and the winner's margin `runner-up / winner`."
             % (" --quick" if args.quick else "", datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
                args.eps), ""]
    for doc in docs:
        name, ref = doc["scene"], doc["reference"]
        agg = doc["mean"]
        integs = [i for i in doc["integrators"] if any(a["integrator"] == i for a in agg)]
        lines += ["## %s" % name, "",
                  "Reference: PATH %d spp (%.0f s); its own estimated noise: relMSE %.3g, MSE %.3g "
                  "(errors near these values are at the reference's floor). Seeds: %s. Threads: %s. "
                  "Load average start/end: %s / %s."
                  % (ref["spp"], ref["render_seconds"], ref["estimated_noise"]["relmse"],
                     ref["estimated_noise"]["mse"], ", ".join(map(str, doc["seeds"])), doc["threads"],
                     "%.2f" % doc["loadavg_start"][0], "%.2f" % doc["loadavg_now"][0]), ""]
        if doc["failed"]:
            for integ, why in doc["failed"].items():
                lines.append("* **%s skipped**: %s" % (integ, why))
            lines.append("")
        by = {(a["integrator"], a["budget_s"]): a for a in agg}
        for key, label in (("smape", "SMAPE"), ("relmse", "relMSE")):
            head = ["budget", *["%s %s (spp)" % (i, label) for i in integs], "winner", "margin"]
            if "PATH" in integs:
                head += ["%s / PATH" % i for i in integs if i != "PATH"]
            pair = "PSF_KELLER" in integs and "PSF_SMIS" in integs
            if pair:
                head.append("PSF_SMIS / PSF_KELLER")
            lines += ["### %s" % label, "", "| " + " | ".join(head) + " |",
                      "|" + "---|" * len(head)]
            for budget in doc["budgets_s"]:
                cells = [a for a in (by.get((i, budget)) for i in integs) if a is not None]
                if not cells:
                    continue
                row = ["%g s" % budget]
                for i in integs:
                    a = by.get((i, budget))
                    row.append("%.4g (%d)" % (a[key], round(a["samples_done"])) if a else "-")
                ranked = sorted(cells, key=lambda a: a[key])
                row.append("**%s**" % ranked[0]["integrator"])
                row.append("%.3gx" % (ranked[1][key] / ranked[0][key]) if len(ranked) > 1 and ranked[0][key] > 0
                           else "-")
                if "PATH" in integs:
                    p = by.get(("PATH", budget))
                    for i in integs:
                        if i == "PATH":
                            continue
                        a = by.get((i, budget))
                        row.append("%.3g" % (a[key] / p[key]) if a and p and p[key] > 0 else "-")
                if pair:
                    a, k = by.get(("PSF_SMIS", budget)), by.get(("PSF_KELLER", budget))
                    row.append("%.3g" % (a[key] / k[key]) if a and k and k[key] > 0 else "-")
                lines.append("| " + " | ".join(row) + " |")
            lines.append("")
        starved = sorted({"%s at %g s" % (a["integrator"], a["budget_s"]) for a in agg if a["samples_done"] < 1})
        if starved:
            lines += ["Warning: no complete sample pass within the budget (0 spp, the image is partial): "
                      + ", ".join(starved) + ".", ""]
        lines += ["Plot: `bench/results/%s`." % os.path.basename(doc["_png"]), ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="budgets 2 4 8 s, seed 1, 512-spp reference (unless given explicitly)")
    ap.add_argument("--scenes", nargs="+", default=SCENES)
    ap.add_argument("--integrators", nargs="+", default=INTEGRATORS)
    ap.add_argument("--budgets", nargs="+", type=float, default=None, help="seconds (default 2 4 8 16 32)")
    ap.add_argument("--seeds", nargs="+", type=int, default=None, help="default 1 2 3")
    ap.add_argument("--ref-spp", type=int, default=None, help="reference spp (default %d)" % REF_SPP)
    ap.add_argument("--force-ref", action="store_true", help="re-render the references")
    ap.add_argument("--eps", type=float, default=M.EPS_RELMSE, help="relMSE epsilon (default %(default)g)")
    ap.add_argument("--threads", type=int, default=0, help="render threads, 0 = all cores")
    ap.add_argument("--psf-radius", type=float, default=None, help="scene.smis.psf_radius_px for PSF_*")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="extra scene.smis setting for every compared render")
    ap.add_argument("--save-images", action="store_true",
                    help="keep the first seed's image of every run (bench/results/psf_images/)")
    ap.add_argument("--resume", action="store_true",
                    help="reuse runs from an earlier (partial) JSON made with the same reference and "
                         "settings (it cannot tell whether the engine was rebuilt since)")
    ap.add_argument("--strict", action="store_true", help="abort when an integrator fails")
    args = ap.parse_args()
    args.budgets = args.budgets or (QUICK["budgets"] if args.quick else BUDGETS)
    args.seeds = args.seeds or (QUICK["seeds"] if args.quick else SEEDS)
    args.ref_spp = args.ref_spp or (QUICK["ref_spp"] if args.quick else REF_SPP)
    args.extra = {k: parse_value(v) for k, v in (s.split("=", 1) for s in args.set)}
    suffix = "_quick" if args.quick else ""
    log("scenes %s, integrators %s, budgets %s s, seeds %s, reference %d spp, threads %s"
        % (args.scenes, args.integrators, args.budgets, args.seeds, args.ref_spp, args.threads or "all"))

    docs = []
    for name in args.scenes:
        doc = bench_scene(name, args, suffix)
        doc["_png"] = result_base(name, suffix) + ".png"
        docs.append(doc)
    # scenes not run this time keep their line in the summary if their results exist
    for name in SCENES:
        if name in args.scenes:
            continue
        path = result_base(name, suffix) + ".json"
        if os.path.exists(path):
            with open(path) as f:
                doc = json.load(f)
            if not doc.get("partial"):
                doc["_png"] = path[:-5] + ".png"
                docs.append(doc)
    summary_path = os.path.join(RESULTS, "psf_summary%s.md" % suffix)
    summary(docs, summary_path, args)
    log("wrote %s" % os.path.relpath(summary_path, ROOT))


if __name__ == "__main__":
    main()
