"""Error against time for every scene and every estimator that applies, Cycles as a peer.

    /usr/bin/python3 bench/equal_time.py            # full run: every suite, budgets 2-32 s, 3 seeds
    /usr/bin/python3 bench/equal_time.py --quick    # CI-sized: budgets 2 4 s, 1 seed, 512-spp references
    /usr/bin/python3 bench/equal_time.py --suite psf --estimators PATH PSF_SMIS --budgets 2 --seeds 1

Suites (SUITES below) group scenes with the estimators that apply to them:
  surfaces  cornell, cornell_diffuse, demo, principled_coat    PATH, CYCLES
  psf       psf_glossy, psf_room              PATH, PSF_KELLER, PSF_SMIS, CYCLES  (West et al. Figs. 4-5)
  restir    many_lights                       NEE, RIS, RESTIR_*, CYCLES (bench/restir_bench.py runs it)
  volume    volume_planes                     PATH, PLANES_UNWEIGHTED/CMIS/SMIS_EXACT, CYCLES
An estimator is a label with the scene.smis settings that select it; CYCLES is Blender's Cycles with
the unbiased settings of scenes/cycles_settings.py (same resolution, bounces and pixel filter, no
denoising, no clamping), a peer wherever it renders the same image.

For each scene:
1. Reference: our PATH (or the suite's reference settings) at `--ref-spp` samples per pixel (default
   4096; 512 with --quick), rendered as two independent halves (seeds 1001 and 1002) and averaged,
   cached in bench/references/<scene>_ref.exr with a JSON record (spp, seeds, settings, render
   seconds, and the reference's own noise from the two halves: a floor under every metric, drawn as
   a dotted line). A cached reference is reused when its settings match and it has enough spp
   (--force-ref after changing a scene or the engine). Our PATH matches Cycles within 1% (see the
   accuracy tests), so one reference serves both engines.
2. Equal time: each estimator at each budget (default 2 4 8 16 32 s; `scene.smis.time_limit` with
   samples = 2^20, Cycles' `time_limit`) and seed (default 1 2 3): SMAPE (paper Sec. 4.4), relMSE
   (eps stated, default 1e-2) and MSE against the reference (bench/metrics.py). Time is the engine's
   own render time (ours from its stats line, Cycles' from Blender's Time line, which includes its
   scene sync; Blender start-up excluded for both).
3. Equal samples: each estimator at the suite's `equal_spp` (e.g. 8 spp for path-space filtering, the
   paper's Fig. 6 count), same seeds, to separate the estimator's quality from its speed.
4. Writes bench/results/equal_time_<scene>.{csv,json,png} (one row per render plus a 'mean' row per
   estimator and budget; log-log SMAPE and relMSE against mean seconds) and
   bench/results/equal_time_summary.md: per scene and budget, the winner by SMAPE and relMSE, each
   estimator's ratio to the suite's baseline, the winner's margin, and the equal-sample table.
   --quick writes `_quick` files so it never overwrites a full run.

Common settings: max_bounces 8 (as the scenes' Cycles settings), BOX pixel filter 1 px (as the
Cycles references), everything else the add-on's defaults unless given with --set KEY=VALUE
(applied to scene.smis for every compared render of ours). An estimator the add-on does not offer
(or that fails) is skipped with its error recorded; --strict aborts instead. The machine is shared:
the load average at the start and end is recorded, since equal-time results depend on it, and the
estimators are interleaved per budget and seed so that a load change hits all of them alike.
"""
import argparse
import csv
import datetime
import json
import os
import re
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import metrics as M  # noqa: E402
from render import RenderError, parse_value, remove, render_cycles, render_smis  # noqa: E402

CYCLES = "CYCLES"
# Many-light direct illumination (issue 8): direct light only (max_bounces 0, as the ReSTIR
# supplement's Fig. 1), the add-on's default M, k, radius and history cap, stated explicitly.
RESTIR_COMMON = {"integrator": "PATH", "max_bounces": 0, "ris_candidates": 16, "restir_neighbors": 5,
                 "restir_radius_px": 3.0, "restir_history_cap": 0}
VOLUME_COMMON = {"integrator": "PATH", "max_bounces": 1}
SUITES = {
    "surfaces": {
        "scenes": ["cornell", "cornell_diffuse", "demo", "principled_coat"],
        "estimators": {"PATH": {"integrator": "PATH"}, CYCLES: None},
        "baseline": "PATH", "equal_spp": 64,
    },
    "psf": {
        "scenes": ["psf_glossy", "psf_room"],
        "estimators": {"PATH": {"integrator": "PATH"}, "PSF_KELLER": {"integrator": "PSF_KELLER"},
                       "PSF_SMIS": {"integrator": "PSF_SMIS"}, CYCLES: None},
        "baseline": "PATH", "pair": ("PSF_SMIS", "PSF_KELLER"), "equal_spp": 8,
    },
    # Many-light direct illumination (issue 8): the direct light at the first non-specular vertex by
    # NEE, RIS or ReSTIR; _NOVIS without visibility reuse (unbiased, no shadow rays in the MIS);
    # RESTIR_NONE and RESTIR_SEED_BIASED are the biased variants (1/M; no visibility in the MIS).
    "restir": {
        "scenes": ["many_lights"],
        "estimators": dict({name: dict(RESTIR_COMMON, **s) for name, s in (
            ("NEE", {"direct_light": "NEE"}),
            ("RIS", {"direct_light": "RIS"}),
            ("RESTIR_SEED", {"direct_light": "RESTIR", "restir_mis": "SEED"}),
            ("RESTIR_TALBOT", {"direct_light": "RESTIR", "restir_mis": "TALBOT"}),
            ("RESTIR_SEED_NOVIS", {"direct_light": "RESTIR", "restir_mis": "SEED", "restir_visibility_reuse": False}),
            ("RESTIR_TALBOT_NOVIS", {"direct_light": "RESTIR", "restir_mis": "TALBOT",
                                     "restir_visibility_reuse": False}),
            ("RESTIR_NONE", {"direct_light": "RESTIR", "restir_mis": "NONE"}),
            ("RESTIR_SEED_BIASED", {"direct_light": "RESTIR", "restir_mis": "SEED", "restir_unbiased": False}))},
            # Cycles 3.4 has no light tree (3.5 added one): it samples the lights by power.
            **{CYCLES: None}),
        # NEE reads none of the RIS/ReSTIR settings: the reference does not depend on them.
        "reference": {"integrator": "PATH", "max_bounces": 0, "direct_light": "NEE"},
        "baseline": "NEE", "pair": ("RESTIR_SEED", "RESTIR_TALBOT"), "equal_spp": 16,
    },
    # Single scattering in a fog box (issue 5, West et al. Sec. 6): the path tracer (distance and
    # equiangular sampling, NEE) against photon planes with the three weightings; max_bounces 1 and
    # Cycles with volume bounces 0 (the scene's smis_volume_bounces) render the same single scattering.
    "volume": {
        "scenes": ["volume_planes"],
        "estimators": dict({name: dict(VOLUME_COMMON, volume_estimator=est) for name, est in (
            ("PATH", "PATH"), ("PLANES_UNWEIGHTED", "PLANES_UNWEIGHTED"), ("PLANES_CMIS", "PLANES_CMIS"),
            ("PLANES_SMIS_EXACT", "PLANES_SMIS_EXACT"))}, **{CYCLES: None}),
        "reference": dict(VOLUME_COMMON, volume_estimator="PATH"),
        "baseline": "PATH", "pair": ("PLANES_SMIS_EXACT", "PLANES_CMIS"), "equal_spp": 16,
    },
}
BUDGETS = [2.0, 4.0, 8.0, 16.0, 32.0]
SEEDS = [1, 2, 3]
REF_SPP = 4096
QUICK = {"budgets": [2.0, 4.0], "seeds": [1], "ref_spp": 512}
REF_SEEDS = (1001, 1002)
MAX_SAMPLES = 1 << 20
COMMON = {"max_bounces": 8, "filter_type": "BOX", "filter_width": 1.0}
REF_DIR = os.path.join(HERE, "references")
RESULTS = os.path.join(HERE, "results")
_CYCLES_SAMPLE = re.compile(r"Sample (\d+)/(\d+)")


def log(msg):
    print("[equal_time %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


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
def reference(name, suite, spp, threads, force=False):
    """(image (h, w, 4), record dict) of the cached or freshly rendered reference."""
    os.makedirs(REF_DIR, exist_ok=True)
    exr = os.path.join(REF_DIR, name + "_ref.exr")
    meta = os.path.join(REF_DIR, name + "_ref.json")
    settings = dict(COMMON, **suite.get("reference", {"integrator": "PATH"}))
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
        log("%s: reference half, %d spp, seed %d" % (name, half, seed))
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
        "scene": name, "blend": os.path.relpath(blend, ROOT), "integrator": settings.get("integrator"),
        "spp": 2 * half,
        "halves": [{"seed": s, "spp": half, "seconds": r["seconds"]} for s, r in zip(REF_SEEDS, runs)],
        "render_seconds": sum(r["seconds"] for r in runs), "settings": settings,
        "threads": threads or os.cpu_count(),
        "half_vs_half": half_vs_half,
        # independent halves: E|a-b|^2 = 2 var(half) and var(mean) = var(half)/2 = E|a-b|^2 / 4
        "estimated_noise": {"mse": half_vs_half["mse"] / 4.0, "relmse": half_vs_half["relmse"] / 4.0,
                            "relmse_eps": half_vs_half["relmse_eps"]},
        "created": datetime.datetime.now().isoformat(timespec="seconds"),
        "engine": engine_version(),
        "note": "mean of two renders with different seeds; estimated_noise is the expected "
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
    return os.path.join(RESULTS, "equal_time_%s%s" % (name, suffix))


def run_key(r):
    return (r["kind"], r["estimator"], float(r["budget_s"]), int(r["seed"]))


def failure_reason(text):
    """The most telling line of a failed render's output."""
    lines = [ln.strip() for ln in text.strip().splitlines() if ln.strip()]
    for pattern in ("enum", "TypeError", "AttributeError", "ValueError", "RuntimeError", "Error", "rror"):
        hits = [ln for ln in lines if pattern in ln and "script failed" not in ln]
        if hits:
            return hits[-1][:400]
    return (lines or ["unknown failure"])[-1][:400]


def render_one(blend, suite, estimator, seed, args, budget=None, spp=None):
    """One render of `estimator`: time-limited (budget seconds) or sample-limited (spp)."""
    if estimator == CYCLES:
        samples = spp if spp else MAX_SAMPLES
        # Cycles gets the bounce limit our renders of the suite use (0 for direct light only).
        ours = dict(COMMON, **suite.get("reference", suite["estimators"][suite["baseline"]]))
        run = render_cycles(blend, samples=samples, seed=seed, time_limit=float(budget or 0.0),
                            max_bounces=ours["max_bounces"], threads=args.threads,
                            timeout=max(600, 20 * (budget or 30)))
        found = _CYCLES_SAMPLE.findall(run.output)
        run.samples_done = max(int(d) for d, _ in found) if found else (spp or -1)
        return run, {"engine": CYCLES, "samples": samples, "time_limit": float(budget or 0.0)}
    settings = dict(COMMON, **suite["estimators"][estimator])
    settings.update(samples=spp or MAX_SAMPLES, time_limit=float(budget or 0.0), seed=seed)
    settings.update(args.extra)
    run = render_smis(blend, settings, threads=args.threads, timeout=max(600, 20 * (budget or 30)))
    return run, settings


def bench_scene(name, suite, args, suffix):
    ref, ref_rec = reference(name, suite, args.ref_spp, args.threads, args.force_ref)
    blend = scene_blend(name)
    estimators = [e for e in suite["estimators"] if not args.estimators or e in args.estimators]
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
    # Equal time first, then equal samples (budget 0 marks those); estimators innermost, so they
    # are interleaved and share whatever load the machine has at that moment.
    jobs = [("time", b, s) for b in args.budgets for s in args.seeds]
    jobs += [("spp", 0.0, s) for s in args.seeds] if suite.get("equal_spp") and not args.no_equal_spp else []
    for kind, budget, seed in jobs:
        for estimator in estimators:
            if estimator in failed:
                continue
            key = (kind, estimator, float(budget), int(seed))
            if key in done and done[key].get("relmse_eps") == args.eps:
                runs.append(done[key])
                continue
            try:
                run, settings = render_one(blend, suite, estimator, seed, args,
                                           budget=budget if kind == "time" else None,
                                           spp=suite["equal_spp"] if kind == "spp" else None)
            except RenderError as exc:
                failed[estimator] = failure_reason(str(exc))
                log("%s: %s FAILED: %s" % (name, estimator, failed[estimator]))
                if args.strict:
                    raise
                continue
            img = run.image
            m = M.metrics(ref, img, args.eps)
            row = {"scene": name, "kind": kind, "estimator": estimator, "budget_s": float(budget),
                   "seed": seed, "seconds": run.seconds, "wall_seconds": round(run.wall_seconds, 3),
                   "samples_done": run.samples_done, **m, "settings": settings}
            runs.append(row)
            if args.save_images and seed == args.seeds[0]:
                img_dir = os.path.join(RESULTS, "equal_time_images%s" % suffix, name)
                os.makedirs(img_dir, exist_ok=True)
                stem = os.path.join(img_dir, "%s_%s" % (estimator, "%gs" % budget if kind == "time"
                                                        else "%dspp" % suite["equal_spp"]))
                M.save_exr(stem + ".exr", img)
                M.save_png(stem + ".png", img)
            remove(run)
            log("%s: %-11s %s seed %d: %.1f s, %d spp, %s"
                % (name, estimator, "%5.1f s budget" % budget if kind == "time" else "equal spp",
                   seed, run.seconds, run.samples_done, M.describe(m)))
            write_scene(name, suite, estimators, suffix, ref_rec, runs, failed, args, load_start, partial=True)
    return write_scene(name, suite, estimators, suffix, ref_rec, runs, failed, args, load_start, partial=False)


def aggregate(runs):
    """Mean (and min/max) over seeds per (kind, estimator, budget)."""
    groups = {}
    for r in runs:
        groups.setdefault((r["kind"], r["estimator"], r["budget_s"]), []).append(r)
    out = []
    for (kind, est, budget), rs in groups.items():
        agg = {"kind": kind, "estimator": est, "budget_s": budget, "n_seeds": len(rs)}
        for k in ("seconds", "wall_seconds", "samples_done", "smape", "relmse", "mse"):
            vals = np.array([r[k] for r in rs], dtype=np.float64)
            agg[k] = float(vals.mean())
            if k in ("smape", "relmse", "mse"):
                agg[k + "_min"], agg[k + "_max"] = float(vals.min()), float(vals.max())
        agg["relmse_eps"] = rs[0]["relmse_eps"]
        out.append(agg)
    return out


CSV_FIELDS = ["scene", "row", "kind", "estimator", "budget_s", "seed", "seconds", "wall_seconds",
              "samples_done", "smape", "relmse", "relmse_eps", "mse"]


def write_scene(name, suite, estimators, suffix, ref_rec, runs, failed, args, load_start, partial):
    os.makedirs(RESULTS, exist_ok=True)
    agg = aggregate(runs)
    doc = {
        "scene": name, "partial": partial, "quick": args.quick, "estimators": estimators,
        "estimator_settings": {e: suite["estimators"][e] for e in estimators},
        "baseline": suite["baseline"], "pair": suite.get("pair"), "equal_spp": suite.get("equal_spp"),
        "budgets_s": args.budgets, "seeds": args.seeds,
        "relmse_eps": args.eps, "common_settings": COMMON, "extra_settings": args.extra,
        "threads": args.threads or os.cpu_count(),
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
            w.writerow(dict(r, row="run"))
        for a in agg:
            w.writerow(dict(a, scene=name, row="mean", seed="mean"))
    if not partial:
        plot(base + ".png", name, doc)
    return doc


STYLES = {"PATH": ("k", "o"), "PSF_KELLER": ("tab:orange", "s"), "PSF_SMIS": ("tab:blue", "^"),
          "PSF_SMIS_UNBIASED": ("tab:green", "v"), "PSF_PATH": ("tab:gray", "x"), CYCLES: ("tab:red", "D"),
          "NEE": ("k", "o"), "RIS": ("tab:purple", "s"), "RESTIR_SEED": ("tab:blue", "^"),
          "RESTIR_TALBOT": ("tab:orange", "v"), "RESTIR_SEED_NOVIS": ("tab:blue", "^"),
          "RESTIR_TALBOT_NOVIS": ("tab:orange", "v"), "RESTIR_NONE": ("tab:gray", "x"),
          "RESTIR_SEED_BIASED": ("tab:cyan", "x")}
# Variants of one estimator share its colour: without visibility reuse dashed, biased dotted.
LINESTYLES = {"RESTIR_SEED_NOVIS": "--", "RESTIR_TALBOT_NOVIS": "--", "RESTIR_NONE": ":",
              "RESTIR_SEED_BIASED": ":"}


def plot(path, name, doc):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker  # noqa: F401
    agg = [a for a in doc["mean"] if a["kind"] == "time"]
    ref_rec = doc["reference"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, key, label in ((axes[0], "smape", "SMAPE"),
                           (axes[1], "relmse", "relMSE (eps=%g)" % doc["relmse_eps"])):
        for est in doc["estimators"]:
            pts = sorted((a["seconds"], a[key], a[key + "_min"], a[key + "_max"]) for a in agg
                         if a["estimator"] == est)
            if not pts:
                continue
            x, y, lo, hi = (np.array(v) for v in zip(*pts))
            color, marker = STYLES.get(est, (None, "d"))
            ax.plot(x, y, marker=marker, color=color, linestyle=LINESTYLES.get(est, "-"), label=est)
            if len(doc["seeds"]) > 1:
                ax.fill_between(x, lo, hi, color=color, alpha=0.15, linewidth=0)
        if key == "relmse" and doc["relmse_eps"] == ref_rec["estimated_noise"]["relmse_eps"]:
            ax.axhline(ref_rec["estimated_noise"]["relmse"], color="gray", linestyle=":",
                       label="reference noise")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xticks(doc["budgets_s"])
        ax.set_xticklabels(["%g" % b for b in doc["budgets_s"]])
        ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
        ax.yaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(matplotlib.ticker.FormatStrFormatter("%g"))
        ax.yaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel("render time [s] (engine time, mean over seeds)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle("%s: equal-time error vs reference (%d spp), %d seed(s)"
                 % (name, ref_rec["spp"], len(doc["seeds"])))
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# summary
# ----------------------------------------------------------------------------------------------
def ratio(a, b, key):
    return "%.3g" % (a[key] / b[key]) if a and b and b[key] > 0 else "-"


def table(doc, agg, kind, key, label):
    """Markdown table of `key` for every estimator: rows are budgets (or the equal-spp row)."""
    ests = [e for e in doc["estimators"] if any(a["estimator"] == e and a["kind"] == kind for a in agg)]
    base, pair = doc["baseline"], doc.get("pair")
    by = {(a["estimator"], a["budget_s"]): a for a in agg if a["kind"] == kind}
    head = ["budget" if kind == "time" else "samples", *["%s %s (%s)" % (e, label, "spp" if kind == "time"
                                                                         else "s") for e in ests],
            "winner", "margin"]
    head += ["%s / %s" % (e, base) for e in ests if e != base and base in ests]
    if pair and all(p in ests for p in pair):
        head.append("%s / %s" % tuple(pair))
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    budgets = doc["budgets_s"] if kind == "time" else [0.0]
    for budget in budgets:
        cells = [a for a in (by.get((e, budget)) for e in ests) if a is not None]
        if not cells:
            continue
        row = ["%g s" % budget if kind == "time" else "%d spp" % doc["equal_spp"]]
        for e in ests:
            a = by.get((e, budget))
            if a is None:
                row.append("-")
                continue
            extra = "%d" % round(a["samples_done"]) if kind == "time" else "%.1f" % a["seconds"]
            row.append("%.4g (%s)" % (a[key], extra))
        ranked = sorted(cells, key=lambda a: a[key])
        row.append("**%s**" % ranked[0]["estimator"])
        row.append("%.3gx" % (ranked[1][key] / ranked[0][key]) if len(ranked) > 1 and ranked[0][key] > 0 else "-")
        if base in ests:
            row += [ratio(by.get((e, budget)), by.get((base, budget)), key) for e in ests if e != base]
        if pair and all(p in ests for p in pair):
            row.append(ratio(by.get((pair[0], budget)), by.get((pair[1], budget)), key))
        lines.append("| " + " | ".join(row) + " |")
    return lines


def summary(docs, path, args):
    lines = ["# Error against time, every scene and estimator%s" % (" (quick run)" if args.quick else ""), "",
             "Generated by `bench/equal_time.py%s` on %s. Errors are against a converged reference and "
             "averaged over seeds; time is the engine's render time (`time_limit` budget; Blender start-up "
             "and our export excluded). SMAPE = mean |r-e|/(|r|+|e|) (West et al. 2020, Sec. 4.4); "
             "relMSE = mean (e-r)^2/(r^2+eps) with eps = %g; MSE = mean (e-r)^2; all per channel, lower "
             "is better. Ratios are `estimator / baseline` (< 1: better) and the winner's margin "
             "`runner-up / winner`. Equal time tables give each estimator's samples per pixel in "
             "brackets; the equal-samples table gives its seconds."
             % (" --quick" if args.quick else "", datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
                args.eps), ""]
    for doc in docs:
        name, ref = doc["scene"], doc["reference"]
        agg = doc["mean"]
        lines += ["## %s" % name, "",
                  "Reference: %s %d spp (%.0f s); its own estimated noise: relMSE %.3g, MSE %.3g "
                  "(errors near these values are at the reference's floor). Seeds: %s. Threads: %s. "
                  "Load average start/end: %s / %s."
                  % (ref.get("integrator"), ref["spp"], ref["render_seconds"], ref["estimated_noise"]["relmse"],
                     ref["estimated_noise"]["mse"], ", ".join(map(str, doc["seeds"])), doc["threads"],
                     "%.2f" % doc["loadavg_start"][0], "%.2f" % doc["loadavg_now"][0]), ""]
        for est, why in doc["failed"].items():
            lines.append("* **%s skipped**: %s" % (est, why))
        if doc["failed"]:
            lines.append("")
        for key, label in (("smape", "SMAPE"), ("relmse", "relMSE"), ("mse", "MSE")):
            lines += ["### Equal time: %s" % label, ""] + table(doc, agg, "time", key, label) + [""]
        if any(a["kind"] == "spp" for a in agg):
            for key, label in (("smape", "SMAPE"), ("mse", "MSE")):
                lines += ["### Equal samples: %s" % label, ""] + table(doc, agg, "spp", key, label) + [""]
        starved = sorted({"%s at %g s" % (a["estimator"], a["budget_s"]) for a in agg
                          if a["kind"] == "time" and 0 <= a["samples_done"] < 1})
        if starved:
            lines += ["Warning: no complete sample pass within the budget (0 spp, the image is partial): "
                      + ", ".join(starved) + ".", ""]
        lines += ["Plot: `%s`." % os.path.relpath(doc["_png"], ROOT), ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="budgets 2 4 s, seed 1, 512-spp references (unless given explicitly)")
    ap.add_argument("--suite", nargs="+", default=list(SUITES), choices=list(SUITES))
    ap.add_argument("--scenes", nargs="+", default=None, help="only these scenes of the suites")
    ap.add_argument("--estimators", nargs="+", default=None, help="only these estimators")
    ap.add_argument("--budgets", nargs="+", type=float, default=None, help="seconds (default 2 4 8 16 32)")
    ap.add_argument("--seeds", nargs="+", type=int, default=None, help="default 1 2 3")
    ap.add_argument("--ref-spp", type=int, default=None, help="reference spp (default %d)" % REF_SPP)
    ap.add_argument("--force-ref", action="store_true", help="re-render the references")
    ap.add_argument("--no-equal-spp", action="store_true", help="skip the equal-samples runs")
    ap.add_argument("--eps", type=float, default=M.EPS_RELMSE, help="relMSE epsilon (default %(default)g)")
    ap.add_argument("--threads", type=int, default=0, help="render threads, 0 = all cores")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="extra scene.smis setting for every compared render of ours")
    ap.add_argument("--save-images", action="store_true",
                    help="keep the first seed's image of every run (bench/results/equal_time_images/)")
    ap.add_argument("--resume", action="store_true",
                    help="reuse runs from an earlier (partial) JSON made with the same reference "
                         "(it cannot tell whether the engine was rebuilt since)")
    ap.add_argument("--strict", action="store_true", help="abort when an estimator fails")
    args = ap.parse_args()
    args.budgets = args.budgets or (QUICK["budgets"] if args.quick else BUDGETS)
    args.seeds = args.seeds or (QUICK["seeds"] if args.quick else SEEDS)
    args.ref_spp = args.ref_spp or (QUICK["ref_spp"] if args.quick else REF_SPP)
    args.extra = {k: parse_value(v) for k, v in (s.split("=", 1) for s in args.set)}
    suffix = "_quick" if args.quick else ""
    log("suites %s, budgets %s s, seeds %s, reference %d spp, threads %s"
        % (args.suite, args.budgets, args.seeds, args.ref_spp, args.threads or "all"))

    docs, ran = [], set()
    for suite_name in args.suite:
        suite = SUITES[suite_name]
        for name in suite["scenes"]:
            if args.scenes and name not in args.scenes:
                continue
            doc = bench_scene(name, suite, args, suffix)
            doc["_png"] = result_base(name, suffix) + ".png"
            docs.append(doc)
            ran.add(name)
    # scenes not run this time keep their section in the summary if their results exist
    for suite in SUITES.values():
        for name in suite["scenes"]:
            path = result_base(name, suffix) + ".json"
            if name in ran or not os.path.exists(path):
                continue
            with open(path) as f:
                doc = json.load(f)
            if not doc.get("partial"):
                doc["_png"] = path[:-5] + ".png"
                docs.append(doc)
    summary_path = os.path.join(RESULTS, "equal_time_summary%s.md" % suffix)
    summary(docs, summary_path, args)
    log("wrote %s" % os.path.relpath(summary_path, ROOT))


if __name__ == "__main__":
    main()
