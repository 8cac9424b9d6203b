"""Photon planes (West et al. 2020, Sec. 6, Fig. 11): error of the single-scattering estimators against
a converged reference, at equal plane count, against plane count and against time, and the cost of
SMIS_exact's extra weights over CMIS for the same planes.

    blender -b --factory-startup --addons smis_render --python bench/planes_bench.py -- [--quick | --cost-only]

--cost-only measures just the SMIS_exact / CMIS time ratio (9 interleaved repeats) and prints it;
--replot redraws the plot and the summary from bench/results/planes_bench.json.

Runs inside Blender: scenes/volume_planes.blend (six rectangular lights in homogeneous isotropic fog,
96x96) is exported once through the add-on's sync layer and rendered with native sessions, so no
Blender start-up is timed. Only the camera rays' single scattering is rendered (`camera_volume_only`:
the surfaces come from the path tracer in every estimator and would add the same noise to all), with
one camera ray through each pixel centre per iteration (no antialiasing, as in the authors' code).

The scene renders at 50% (48x48) to keep the run near 10 minutes on 2 shared cores.
Reference: PLANES_SMIS_EXACT with REF_ITERATIONS x 40,960 planes (unbiased; the engine tests check
all five estimators converge to the same image), cached in bench/results keyed by the engine build;
its agreement with PATH (volume only, distance sampling + NEE) is measured and reported.

Writes bench/results/planes_bench.{json,csv}, docs/bench/planes_bench.csv, docs/bench/planes_bench.png (error vs planes and vs
time), docs/bench/planes_fig11.png (one iteration of each estimator next to the reference) and the
summary docs/bench/planes_bench.md (with --quick all of these go to bench/results/ instead). Timings share 2 cores with other jobs: the cost ratio is measured
interleaved, best of REPEATS.
"""
import csv
import json
import os
import sys
import time

import bpy
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from metrics import mse, smape  # noqa: E402

from smis_render import _smis, properties, sync  # noqa: E402

ARGS = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
QUICK = "--quick" in ARGS
ESTIMATORS = ["PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_COS", "PLANES_SMIS_EXACT"]
LABELS = {"PATH": "path tracing (NEE)", "PLANES_UNWEIGHTED": "unweighted (eq. 22)",
          "PLANES_CMIS": "CMIS_w~ (Deng et al., eq. 26)", "PLANES_SMIS_COS": "SMIS_w~ (cosine, eq. 27)",
          "PLANES_SMIS_EXACT": "SMIS_w. (exact, eq. 25+27)"}
PLANES = 40960
SEEDS = 4 if QUICK else 8
REF_ITERATIONS = 32 if QUICK else 128
PLANE_COUNTS = [2560, 10240, 40960, 163840]
COUNT_SEEDS = 1 if QUICK else 2
TIME_ITERATIONS = [1, 2, 4] if QUICK else [1, 2, 4, 8, 16]
PATH_SPP = [1, 4, 16] if QUICK else [1, 4, 16, 64, 256]
PATH_CHECK_SPP = 4096 if QUICK else 16384  # the reference's check against PATH
REPEATS = 3 if QUICK else 5
# Half the scene's 96x96: the error ratios between the weightings do not depend on it, the run
# time (about 10 minutes on 2 shared cores) does.
RESOLUTION_PERCENTAGE = 50
RESULTS = os.path.join(ROOT, "bench", "results")
REF_SHAPE = [0, 0]
DOCS = os.path.join(ROOT, "docs", "bench")


class Reporter:
    def warning(self, message):
        print("WARNING:", message)

    def info(self, message):
        print(message)


def log(msg):
    print("[planes_bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


def export_scene():
    bpy.ops.wm.open_mainfile(filepath=os.path.join(ROOT, "scenes", "volume_planes.blend"))
    bpy.context.scene.render.resolution_percentage = RESOLUTION_PERCENTAGE
    depsgraph = bpy.context.evaluated_depsgraph_get()
    export = sync.export_depsgraph(_smis, depsgraph, Reporter())
    base = properties.session_settings(bpy.context.scene)
    # One camera ray through each pixel centre (a box filter of 1e-4 px), for the estimates and the
    # reference alike, as in the authors' Fig. 11 code (no antialiasing): otherwise the jitter of a
    # single camera sample per pixel across edges adds the same error floor to every estimator.
    base.update({"filter": "BOX", "filter_width": 1e-4, "max_bounces": bpy.context.scene.cycles.max_bounces,
                 "camera_volume_only": True, "threads": 0, "time_limit": 0.0})
    return export.scene, base


def render(scene, base, estimator, samples, seed, planes=PLANES):
    settings = dict(base, volume_estimator=estimator, samples=samples, seed=seed, photon_planes=planes)
    session = _smis.RenderSession(scene, settings)
    t0 = time.perf_counter()
    session.run()
    seconds = time.perf_counter() - t0
    err = session.error()
    if err:
        raise RuntimeError(err)
    return np.array(session.pixels())[..., :3], seconds, dict(session.integrator_stats()), dict(session.counters())


def reference(scene, base):
    path = os.path.join(RESULTS, "planes_reference_%d_%d.npy" % (REF_ITERATIONS, RESOLUTION_PERCENTAGE))
    if os.path.exists(path):
        log("reference from cache " + path)
        return np.load(path)
    log("reference: PLANES_SMIS_EXACT, %d iterations x %d planes" % (REF_ITERATIONS, PLANES))
    img, secs, _, _ = render(scene, base, "PLANES_SMIS_EXACT", REF_ITERATIONS, 9001)
    log("reference done in %.0f s" % secs)
    np.save(path, img)
    return img


def record(rows, experiment, estimator, ref, img, seconds, planes, samples, seed, stats, counters):
    row = {"experiment": experiment, "estimator": estimator, "planes": planes, "iterations": samples,
           "seed": seed, "seconds": seconds, "mse": mse(ref, img), "smape": smape(ref, img),
           "plane_hits": stats.get("plane_hits", 0.0), "parallel_rejected": stats.get("parallel_rejected", 0.0),
           "nonfinite_rejected": stats.get("nonfinite_rejected", 0.0), "nan_caught": counters.get("nan_caught", 0)}
    rows.append(row)
    return row


def mean_of(rows, **match):
    sel = [r for r in rows if all(r[k] == v for k, v in match.items())]
    return ({k: float(np.mean([r[k] for r in sel])) for k in ("mse", "smape", "seconds")},
            {k: float(np.std([r[k] for r in sel], ddof=1) / np.sqrt(len(sel))) if len(sel) > 1 else 0.0
             for k in ("mse", "smape")}, len(sel))


def equal_planes(scene, base, ref, rows):
    """Fig. 11: 40,960 planes, one camera sample per pixel, averaged over seeds. The seeds are shared
    by the estimators: the same plane sets, as in the paper."""
    images = {}
    for seed in range(1, SEEDS + 1):
        for est in ESTIMATORS:
            img, secs, st, ct = render(scene, base, est, 1, seed)
            r = record(rows, "equal_planes", est, ref, img, secs, PLANES, 1, seed, st, ct)
            if seed == 1:
                images[est] = img
        log("equal planes, seed %d: %s" % (seed, "  ".join(
            "%s %.3g" % (e, r["mse"]) for e, r in ((r["estimator"], r) for r in rows[-len(ESTIMATORS):]))))
    for seed in range(1, SEEDS + 1):  # path tracing at one sample per pixel, for scale
        img, secs, st, ct = render(scene, base, "PATH", 1, seed)
        record(rows, "equal_planes", "PATH", ref, img, secs, 0, 1, seed, st, ct)
    return images


def plane_counts(scene, base, ref, rows):
    for planes in PLANE_COUNTS:
        for seed in range(1, COUNT_SEEDS + 1):
            for est in ESTIMATORS:
                img, secs, st, ct = render(scene, base, est, 1, 100 + seed, planes)
                record(rows, "plane_count", est, ref, img, secs, planes, 1, 100 + seed, st, ct)
        log("plane count %d done" % planes)


def error_vs_time(scene, base, ref, rows):
    for est in ESTIMATORS:
        for it in TIME_ITERATIONS:
            img, secs, st, ct = render(scene, base, est, it, 500)
            record(rows, "time", est, ref, img, secs, PLANES, it, 500, st, ct)
    for spp in PATH_SPP:
        img, secs, st, ct = render(scene, base, "PATH", spp, 500)
        record(rows, "time", "PATH", ref, img, secs, 0, spp, 500, st, ct)
    log("error vs time done")


def cost_ratio(scene, base):
    """SMIS_exact against CMIS on the same planes (same seed), interleaved, best of REPEATS."""
    best = {"PLANES_CMIS": float("inf"), "PLANES_SMIS_EXACT": float("inf")}
    for _ in range(REPEATS):
        for est in best:
            _, secs, _, _ = render(scene, base, est, 2, 777)
            best[est] = min(best[est], secs)
    ratio = best["PLANES_SMIS_EXACT"] / best["PLANES_CMIS"]
    log("cost: CMIS %.2f s, SMIS_EXACT %.2f s, ratio %.3f" % (best["PLANES_CMIS"], best["PLANES_SMIS_EXACT"], ratio))
    return {"cmis_seconds": best["PLANES_CMIS"], "smis_exact_seconds": best["PLANES_SMIS_EXACT"], "ratio": ratio,
            "iterations": 2, "planes": PLANES, "repeats": REPEATS}


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 2, figsize=(11, 8.5))
    colors = {e: "C%d" % i for i, e in enumerate(["PATH"] + ESTIMATORS)}
    for est in ["PATH"] + ESTIMATORS:
        for col, metric in enumerate(("mse", "smape")):
            if est != "PATH":
                pts = [(p, mean_of(rows, experiment="plane_count", estimator=est, planes=p)[0][metric])
                       for p in PLANE_COUNTS]
                axes[0, col].loglog(*zip(*pts), "o-", color=colors[est], label=LABELS[est])
            sel = sorted((r["seconds"], r[metric]) for r in rows if r["experiment"] == "time" and r["estimator"] == est)
            axes[1, col].loglog(*zip(*sel), "o-", color=colors[est], label=LABELS[est])
    for col, metric in enumerate(("MSE", "SMAPE")):
        axes[0, col].set_xlabel("photon planes (one iteration, 1 sample per pixel)")
        axes[1, col].set_xlabel("render time (s), 2 shared cores")
        for row in range(2):
            axes[row, col].set_ylabel(metric)
            axes[row, col].grid(True, which="both", alpha=0.3)
            axes[row, col].legend(fontsize=8)
    fig.suptitle("Single scattering from 6 rectangular lights (volume_planes at %d%%, camera rays only)" % RESOLUTION_PERCENTAGE)
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def montage(ref, images, path):
    """Reference and one iteration of each estimator side by side (like Fig. 11)."""
    tiles = [ref] + [images[e] for e in ESTIMATORS]
    strip = np.concatenate(tiles, axis=1)
    rgba = np.concatenate([strip, np.ones(strip.shape[:2] + (1,))], axis=-1).astype(np.float32)
    _smis.write_png(path, np.ascontiguousarray(rgba), "/usr/share/blender/datafiles/colormanagement/config.ocio",
                    "sRGB", "Filmic", "None", 0.0, 1.0)


def summary(rows, cost, ref_check, path):
    eq = {e: mean_of(rows, experiment="equal_planes", estimator=e) for e in ["PATH"] + ESTIMATORS}
    m = {e: eq[e][0]["mse"] for e in eq}
    lines = [
        "# Photon planes with SMIS (West et al. 2020, Sec. 6, Fig. 11)",
        "",
        "Produced by `blender -b --factory-startup --addons smis_render --python bench/planes_bench.py%s`"
        % (" -- --quick" if QUICK else ""),
        "on scenes/volume_planes.blend at %d%% (%dx%d; six rectangular lights in homogeneous isotropic fog), camera"
        % (RESOLUTION_PERCENTAGE, REF_SHAPE[1], REF_SHAPE[0]),
        "rays' single scattering only, one ray through each pixel centre. Reference: PLANES_SMIS_EXACT with %d x %d planes;"
        % (REF_ITERATIONS, PLANES),
        "its mean relative difference to PATH (volume only, %d spp) on 4x4 blocks is %.2f%%, where two PATH renders"
        % (ref_check["path_spp"], 100 * ref_check["block_mre"]),
        "differ by %.2f%% (PATH's own noise); image means: reference / PATH = %.4f. Timings: 2 cores shared with"
        % (100 * ref_check.get("path_noise_mre", float("nan")), ref_check.get("mean_ratio", float("nan"))),
        "other jobs.",
        "",
        "## Equal plane count: 40,960 planes, one camera sample per pixel, mean over %d seeds" % eq["PLANES_CMIS"][2],
        "",
        "| estimator | MSE x 1e4 (+- s.e.) | SMAPE x 1e2 (+- s.e.) | MSE relative to SMIS_exact | seconds |",
        "|---|---|---|---|---|",
    ]
    for e in ESTIMATORS + ["PATH"]:
        mean, se, n = eq[e]
        lines.append("| %s%s | %.3f +- %.3f | %.3f +- %.3f | %.2f | %.2f |" % (
            LABELS[e], " (1 spp, no planes)" if e == "PATH" else "", 1e4 * mean["mse"], 1e4 * se["mse"],
            1e2 * mean["smape"], 1e2 * se["smape"], mean["mse"] / m["PLANES_SMIS_EXACT"], mean["seconds"]))
    # The estimators see the same plane sets and camera rays per seed: compare them pairwise per seed.
    def paired(worse, better):
        d = [r_w["mse"] - r_b["mse"] for r_w in rows for r_b in rows
             if r_w["experiment"] == r_b["experiment"] == "equal_planes" and r_w["seed"] == r_b["seed"]
             and r_w["estimator"] == worse and r_b["estimator"] == better]
        mean, se = float(np.mean(d)), float(np.std(d, ddof=1) / np.sqrt(len(d)))
        return mean, se, mean > 2.0 * se
    pairs = [("PLANES_CMIS", "PLANES_SMIS_EXACT"), ("PLANES_SMIS_COS", "PLANES_SMIS_EXACT"),
             ("PLANES_UNWEIGHTED", "PLANES_SMIS_COS")]
    tests = {p: paired(*p) for p in pairs}
    ordering_ok = all(t[2] for t in tests.values())
    lines += [
        "",
        "Paper (Fig. 11, its own scene and 40,960 planes): SMIS_w. has about 1.3x lower MSE than the analytic",
        "CMIS weighting and about 5x lower than unweighted. Here: CMIS / SMIS_exact = **%.2fx**, SMIS_cos /"
        % (m["PLANES_CMIS"] / m["PLANES_SMIS_EXACT"]),
        "SMIS_exact = **%.2fx**, unweighted / SMIS_exact = **%.2fx**. Ordering SMIS_exact < CMIS, SMIS_exact <"
        % (m["PLANES_SMIS_COS"] / m["PLANES_SMIS_EXACT"], m["PLANES_UNWEIGHTED"] / m["PLANES_SMIS_EXACT"]),
        "SMIS_cos < unweighted (the issue's criterion), each as a paired difference of MSE per seed (same planes)",
        "more than 2 standard errors above zero: **%s**." % ("met" if ordering_ok else "NOT met"),
        "",
        "| pair | mean MSE difference x 1e4 per seed (+- s.e.) | significant |",
        "|---|---|---|",
    ] + ["| %s - %s | %.3f +- %.3f | %s |" % (LABELS[a], LABELS[b], 1e4 * tests[(a, b)][0], 1e4 * tests[(a, b)][1],
                                              "yes" if tests[(a, b)][2] else "no") for a, b in pairs] + [
        "",
        "## Cost of the exact SMIS weights",
        "",
        "Same planes (seed 777, %d iterations x %d planes), interleaved, best of %d: CMIS %.2f s, SMIS_exact"
        % (cost["iterations"], cost["planes"], cost["repeats"], cost["cmis_seconds"]),
        "%.2f s: SMIS_exact costs **%+.1f%%** (criterion: at most +10%%: **%s**)." % (
            cost["smis_exact_seconds"], 100 * (cost["ratio"] - 1), "met" if cost["ratio"] <= 1.10 else "NOT met"),
        "",
        "## Rejected samples",
        "",
        "Crossings too close to parallel to a plane for a finite Jacobian (skipped) over all runs: %d;" % int(
            sum(r["parallel_rejected"] for r in rows)),
        "non-finite contributions: %d; NaN/Inf caught at the film: %d." % (
            int(sum(r["nonfinite_rejected"] for r in rows)), int(sum(r["nan_caught"] for r in rows))),
        "",
        "![error vs planes and time](planes_bench.png)",
        "",
        "Reference, then one iteration (40,960 planes) of unweighted, CMIS, SMIS_cos, SMIS_exact:",
        "",
        "![Fig. 11-like comparison](planes_fig11.png)",
        "",
        "Data: planes_bench.csv here (every run; also bench/results/planes_bench.{csv,json}).",
    ]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    os.makedirs(RESULTS, exist_ok=True)
    os.makedirs(DOCS, exist_ok=True)
    if "--replot" in ARGS:
        with open(os.path.join(RESULTS, "planes_bench.json")) as f:
            data = json.load(f)
        REF_SHAPE[:] = data.get("reference_shape", [48, 48])
        plot(data["rows"], os.path.join(DOCS, "planes_bench.png"))
        summary(data["rows"], data["cost"], data["reference_check"], os.path.join(DOCS, "planes_bench.md"))
        return
    scene, base = export_scene()
    if "--cost-only" in ARGS:
        global REPEATS
        REPEATS = 9
        print("COST " + json.dumps(cost_ratio(scene, base)))
        return
    ref = reference(scene, base)
    REF_SHAPE[:] = ref.shape[:2]
    # PATH at PATH_CHECK_SPP, twice: the reference's difference to PATH next to PATH's own noise (two
    # seeds' difference), which at 64 spp was all of the 6% once reported here.
    path_a, _, _, _ = render(scene, base, "PATH", PATH_CHECK_SPP, 4242)
    path_b, _, _, _ = render(scene, base, "PATH", PATH_CHECK_SPP, 4343)
    k = 4
    h, w = ref.shape[0] // k * k, ref.shape[1] // k * k
    blocks = lambda im: im[:h, :w].reshape(h // k, k, w // k, k, 3).mean(axis=(1, 3)).mean(-1)  # noqa: E731
    b_ref = blocks(ref)
    mask = b_ref > 0.01 * b_ref.mean()
    block_mre = lambda a, b: float(np.abs((blocks(a) - blocks(b))[mask] / blocks(b)[mask]).mean())  # noqa: E731
    ref_check = {"path_spp": PATH_CHECK_SPP, "block_mre": block_mre(path_a, ref),
                 "path_noise_mre": block_mre(path_a, path_b),
                 "mean_ratio": float(ref.mean() / (0.5 * (path_a.mean() + path_b.mean())))}
    log("reference vs PATH: block MRE %.4f (PATH vs PATH %.4f), image mean ratio %.4f" %
        (ref_check["block_mre"], ref_check["path_noise_mre"], ref_check["mean_ratio"]))

    rows = []
    images = equal_planes(scene, base, ref, rows)
    cost = cost_ratio(scene, base)
    plane_counts(scene, base, ref, rows)
    error_vs_time(scene, base, ref, rows)

    # The committed copies in docs/bench/ come from full runs only: a quick run writes its summary,
    # plots and CSV into bench/results/ and leaves the documented results alone.
    out = RESULTS if QUICK else DOCS
    for folder in sorted({RESULTS, out}):
        with open(os.path.join(folder, "planes_bench.csv"), "w", newline="") as f:
            wr = csv.DictWriter(f, fieldnames=list(rows[0]))
            wr.writeheader()
            wr.writerows(rows)
    with open(os.path.join(RESULTS, "planes_bench.json"), "w") as f:
        json.dump({"rows": rows, "cost": cost, "reference_check": ref_check, "quick": QUICK,
                   "reference_shape": list(REF_SHAPE)}, f, indent=1)
    plot(rows, os.path.join(out, "planes_bench.png"))
    montage(ref, images, os.path.join(out, "planes_fig11.png"))
    summary(rows, cost, ref_check, os.path.join(out, "planes_bench.md"))
    log("wrote %s" % os.path.relpath(os.path.join(out, "planes_bench.md"), ROOT))


if __name__ == "__main__":  # bench/plane_shadow_rays.py imports the helpers above
    main()
    sys.stdout.flush()
    os._exit(0)
