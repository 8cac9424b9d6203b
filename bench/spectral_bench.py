"""Spectral rendering benchmark (paper §5, Figs. 8-9): colour error of every wavelength-sampling mode
at equal samples per pixel and against time, and what AUTO costs on an RGB-only scene.

    /usr/bin/python3 bench/spectral_bench.py            # full: 128x128, 4 seeds, BRUTE_FORCE 4x64 spp reference
    /usr/bin/python3 bench/spectral_bench.py --quick    # CI-sized: 64x64, 2 seeds, 4x16 spp reference
    /usr/bin/python3 bench/spectral_bench.py --scenes spectral_glass --seeds 16 --keep --no-cost
        # one scene again with more seeds, the other scene's results and the cost kept from the JSON
    /usr/bin/python3 bench/spectral_bench.py --from-json  # rewrite plots and summary, no rendering

Per scene (scenes/spectral_gold.blend = Fig. 8: measured gold under F10; spectral_glass.blend =
Fig. 9: dispersive glasses under D65), one Blender process exports the scene once and renders every
job in-process (bench/spectral_worker.py), so times are the engine's render times only:
  1. reference: BRUTE_FORCE (512 wavelengths per path) in K independent renders (seeds 1000+k),
     averaged. Its own noise is estimated from the spread of the K renders (per pixel variance of
     their mean) and subtracted from every MSE ("MSE - reference variance"), so a mode is not
     credited or blamed for the reference's noise.
  2. every mode (UNIFORM, SPECTRAL_IS, HERO, SMIS, SMIS_INDEPENDENT with n = 4 wavelengths, and
     BRUTE_FORCE) at several spp, with S seeds each, and SMIS_NOSEQ (SMIS without the pixel
     sequence of wavelength offsets). Error = MSE in linear RGB against the reference (all pixels
     and channels), averaged over the seeds. The equal-spp comparison is at 16 spp (4 with --quick).
  3. cost of AUTO against RGB on scenes/cornell.blend (no spectral content): interleaved renders,
     best of N each (the machine is shared; the ratio is what counts).
  4. dispersion on spectral_glass: dispersive glasses against each glass at constant IOR n_d
     (dispersion_demo), and where SMIS's excess over BRUTE_FORCE comes from (excess_section,
     bench/spectral_model.py).
Outputs: bench/results/<scene>.csv (one row per render), bench/results/spectral.json,
bench/results/<scene>.png (error vs spp and vs time), and docs/bench/spectral_summary.md
with the checks of issue 4; the PNGs and CSVs are copied to docs/bench/.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
RESULTS = os.path.join(HERE, "results")
DOCS = os.path.join(ROOT, "docs", "bench")
BLENDER = os.environ.get("BLENDER", "blender")
MODES = ["UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT", "BRUTE_FORCE"]
PRACTICAL = ["UNIFORM", "SPECTRAL_IS", "HERO", "SMIS", "SMIS_INDEPENDENT"]
# Ablation rows: a mode with its wavelength offsets drawn independently per sample instead of from
# the pixel sequence (settings.spectral_pixel_sequence), to show what the stratification brings.
VARIANTS = {"SMIS_NOSEQ": ("SMIS", {"spectral_pixel_sequence": False})}
ROWS = MODES[:-1] + list(VARIANTS) + MODES[-1:]
SCENES = {"spectral_gold": "Fig. 8: measured gold, F10 lights",
          "spectral_glass": "Fig. 9: dispersive glasses, D65 lights"}


def run_jobs(blend, jobs, percentage, *extra):
    """Render `jobs` on `blend` in one Blender process; returns ({name: image}, {name: result})."""
    tmp = tempfile.mkdtemp(prefix="smis_spectral_")
    try:
        with open(os.path.join(tmp, "jobs.json"), "w") as f:
            json.dump(jobs, f)
        cmd = [BLENDER, "-b", "--factory-startup", "--addons", "smis_render", blend, "--python",
               os.path.join(HERE, "spectral_worker.py"), "--", os.path.join(tmp, "jobs.json"), tmp,
               str(percentage), *extra]
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0 or not os.path.exists(os.path.join(tmp, "results.json")):
            raise RuntimeError("worker failed on %s:\n%s" % (blend, (proc.stdout + proc.stderr)[-3000:]))
        with open(os.path.join(tmp, "results.json")) as f:
            results = json.load(f)
        images = {j["name"]: np.load(os.path.join(tmp, j["name"] + ".npy")).astype(np.float64) for j in jobs}
        return images, results
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def job(name, **settings):
    return {"name": name, "settings": settings}


def bench_scene(scene, args):
    blend = os.path.join(ROOT, "scenes", scene + ".blend")
    jobs = [job("ref_%d" % k, samples=args.ref_spp, seed=1000 + k, spectral="BRUTE_FORCE")
            for k in range(args.ref_renders)]
    for row in ROWS:
        mode, extra = VARIANTS.get(row, (row, {}))
        for spp in (args.bf_spp if mode == "BRUTE_FORCE" else args.spp):
            for seed in range(args.seeds):
                jobs.append(job("%s_%d_%d" % (row, spp, seed), samples=spp, seed=seed + 1, spectral=mode,
                                wavelengths=args.wavelengths, **extra))
    images, results = run_jobs(blend, jobs, args.percentage)
    refs = np.stack([images["ref_%d" % k] for k in range(args.ref_renders)])
    ref = refs.mean(axis=0)
    # Variance of the reference's mean per pixel and channel, from the spread of its K renders.
    ref_var = float((refs.var(axis=0, ddof=1) / args.ref_renders).mean())
    rows = []
    for j in jobs[args.ref_renders:]:
        mode, spp, seed = j["name"].rsplit("_", 2)
        img = images[j["name"]]
        mse = float(((img - ref) ** 2).mean())
        rows.append({"scene": scene, "mode": mode, "spp": int(spp), "seed": int(seed),
                     "seconds": results[j["name"]]["seconds"], "mse_raw": mse, "mse": mse - ref_var,
                     "nonfinite": int((~np.isfinite(img)).sum())})
    agg = {}
    for r in rows:
        a = agg.setdefault((r["mode"], r["spp"]), {"mse": [], "seconds": []})
        a["mse"].append(r["mse"])
        a["seconds"].append(r["seconds"])
    summary = {"%s@%d" % k: {"mse": float(np.mean(v["mse"])),
                             "mse_stderr": float(np.std(v["mse"], ddof=1) / np.sqrt(len(v["mse"])))
                             if len(v["mse"]) > 1 else 0.0,
                             "seconds": float(np.mean(v["seconds"]))} for k, v in agg.items()}
    ref_seconds = sum(results["ref_%d" % k]["seconds"] for k in range(args.ref_renders))
    return {"rows": rows, "summary": summary, "seeds": args.seeds, "ref_variance": ref_var,
            "ref_mean": float(ref.mean()),
            "ref_seconds": ref_seconds, "ref_image": ref}


def bench_auto_cost(args):
    """AUTO vs RGB on an RGB-only scene: interleaved, best of N."""
    blend = os.path.join(ROOT, "scenes", "cornell.blend")
    jobs = []
    for i in range(args.cost_repeats):
        for mode in ("AUTO", "RGB"):
            jobs.append(job("%s_%d" % (mode, i), samples=args.cost_spp, seed=1, spectral=mode))
    images, results = run_jobs(blend, jobs, args.percentage)
    out = {}
    for mode in ("AUTO", "RGB"):
        times = [results["%s_%d" % (mode, i)]["seconds"] for i in range(args.cost_repeats)]
        out[mode] = {"best": min(times), "median": float(np.median(times)), "times": times,
                     "resolved": results["%s_0" % mode]["mode"]}
    out["identical_images"] = bool(all(np.array_equal(images["AUTO_%d" % i], images["RGB_%d" % i])
                                       for i in range(args.cost_repeats)))
    out["ratio_best"] = out["AUTO"]["best"] / out["RGB"]["best"]
    return out


def block_chroma(img, size=8):
    """rg chromaticity of each size x size block's summed RGB, and the block's mean RGB sum."""
    h, w = img.shape[0] // size * size, img.shape[1] // size * size
    rgb = img[:h, :w].reshape(h // size, size, w // size, size, 3).sum(axis=(1, 3))
    total = rgb.sum(axis=2)
    return rgb[..., :2] / np.maximum(total, 1e-9)[..., None], total / size ** 2


def block_z(a, b):
    """Per block: |mean chroma of renders a - mean chroma of renders b| in standard errors estimated
    from the spread of each set's independent renders (a, b: (K, H, W, 2))."""
    diff = a.mean(axis=0) - b.mean(axis=0)
    se2 = a.var(axis=0, ddof=1) / len(a) + b.var(axis=0, ddof=1) / len(b)
    return np.sqrt((diff ** 2).sum(axis=2) / np.maximum(se2.sum(axis=2), 1e-30)), np.sqrt((diff ** 2).sum(axis=2))


def dispersion_demo(args):
    """spectral_glass rendered by SMIS with its dispersive glasses ("on") and with each glass replaced
    by a constant IOR equal to its n_d ("off"), K = 4 seeds each.
    Per pixel, the mean squared rg-chromaticity change that dispersion causes, with the noise of the
    renders removed (independent seeds: the cross term carries the noise of one render of each kind,
    the halves of the same-kind terms exactly that):
        signal = E|c(on_1) - c(off_2)|^2 - (E|c(on_1) - c(on_2)|^2 + E|c(off_1) - c(off_2)|^2) / 2.
    Per 8x8 block, the chromaticity of the block's summed RGB, averaged over the K renders of each kind:
    a block changes when on and off differ by more than 4 standard errors (from the spread of the
    renders of each kind). Control: the same test between two halves of 2K constant-IOR renders
    counts the blocks that pass by chance. PNGs side by side (whole frame, and the glasses 3x)."""
    blend = os.path.join(ROOT, "scenes", "spectral_glass.blend")
    k = args.demo_seeds
    on, _ = run_jobs(blend, [job("s%d" % i, samples=args.demo_spp, seed=i + 1, spectral="SMIS")
                             for i in range(k)], args.percentage)
    off, _ = run_jobs(blend, [job("s%d" % i, samples=args.demo_spp, seed=i + 1, spectral="SMIS")
                              for i in range(2 * k)], args.percentage, "no_dispersion")
    on = [on["s%d" % i] for i in range(k)]
    off = [off["s%d" % i] for i in range(2 * k)]

    def chroma(img):
        return img[..., :2] / np.maximum(img.sum(axis=2, keepdims=True), 1e-6)

    lit = np.ones(on[0].shape[:2], bool)
    for img in on[:2] + off[:2]:
        lit &= img.sum(axis=2) > 0.05
    c = [chroma(v) for v in on[:2] + off[:2]]

    def d2(a, b):
        return ((c[a] - c[b]) ** 2).sum(axis=2)

    signal = d2(0, 3) - 0.5 * (d2(0, 1) + d2(2, 3))
    noise = 0.5 * (d2(0, 1) + d2(2, 3))[lit]
    blocks_on = np.stack([block_chroma(v)[0] for v in on])
    blocks_off = np.stack([block_chroma(v)[0] for v in off])
    bright = block_chroma(off[0])[1] > 0.02  # blocks with light enough for a chromaticity
    z, change = block_z(blocks_on, blocks_off[:k])
    z_null, _ = block_z(blocks_off[:k], blocks_off[k:])
    significant = (z > 4.0) & bright
    path = os.path.join(RESULTS, "spectral_glass_dispersion.png")
    crop_path = os.path.join(RESULTS, "spectral_glass_dispersion_crop.png")
    a, b = on[0], off[0]
    save_side_by_side(path, a, b, 1)
    # The band of the image holding the glasses (rows are bottom-up), enlarged 3x.
    rows = slice(int(0.25 * a.shape[0]), int(0.72 * a.shape[0]))
    save_side_by_side(crop_path, a[rows], b[rows], 3)
    return {"spp": args.demo_spp, "seeds": k, "png": path, "crop_png": crop_path,
            "rms_chroma_change": float(np.sqrt(max(signal[lit].mean(), 0.0))),
            "signal_mean_sq": float(signal[lit].mean()),
            "signal_stderr": float(signal[lit].std(ddof=1) / np.sqrt(lit.sum())),
            "rms_noise": float(np.sqrt(noise.mean())),
            "blocks": int(bright.sum()), "blocks_significant": int(significant.sum()),
            "blocks_significant_control": int(((z_null > 4.0) & bright).sum()),
            "significant_block_change": float(change[significant].mean()) if significant.any() else 0.0}


def save_side_by_side(path, a, b, scale):
    """PNG of images a | b (linear RGB, row 0 = bottom), each enlarged `scale` times (nearest)."""
    from metrics import save_png
    both = np.concatenate([a, np.zeros((a.shape[0], 2, 3)), b], axis=1).repeat(scale, 0).repeat(scale, 1)
    save_png(path, np.concatenate([both, np.ones(both.shape[:2] + (1,))], axis=2).astype(np.float32),
             view="Standard")


def write_csv(path, rows):
    keys = ["scene", "mode", "spp", "seed", "seconds", "mse", "mse_raw", "nonfinite"]
    with open(path, "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows:
            f.write(",".join(str(r[k]) for k in keys) + "\n")


def plot(path, scene, res):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for mode in ROWS:
        pts = sorted((int(k.split("@")[1]), v) for k, v in res["summary"].items() if k.split("@")[0] == mode)
        spp = [p[0] for p in pts]
        mse = [max(p[1]["mse"], 1e-12) for p in pts]
        secs = [p[1]["seconds"] for p in pts]
        style = "--" if mode == "BRUTE_FORCE" else ":" if mode in VARIANTS else "-"
        axes[0].loglog(spp, mse, style, marker="o", label=mode)
        axes[1].loglog(secs, mse, style, marker="o", label=mode)
    axes[0].set_xlabel("samples (paths) per pixel")
    axes[1].set_xlabel("render seconds (shared 2-core machine)")
    for ax in axes:
        ax.set_ylabel("MSE, linear RGB (reference noise subtracted)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("%s: %s" % (scene, SCENES[scene]))
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def checks(name, res, equal_spp):
    s = res["summary"]
    m = {mode: s["%s@%d" % (mode, equal_spp)]["mse"] for mode in MODES if "%s@%d" % (mode, equal_spp) in s}
    out = []
    if name == "spectral_gold":
        order = m["UNIFORM"] > m["SPECTRAL_IS"] > m["HERO"] > m["SMIS"]
        out.append(("UNIFORM > SPECTRAL_IS > HERO > SMIS at %d spp" % equal_spp, order,
                    " > ".join("%s %.4g" % (k, m[k]) for k in ("UNIFORM", "SPECTRAL_IS", "HERO", "SMIS"))))
        for spp in sorted({int(k.split("@")[1]) for k in s if k.startswith("BRUTE_FORCE@")}):
            ratio = s["SMIS@%d" % spp]["mse"] / s["BRUTE_FORCE@%d" % spp]["mse"]
            out.append(("SMIS within 1.25x of BRUTE_FORCE at %d spp" % spp, ratio <= 1.25,
                        "SMIS / BRUTE_FORCE = %.3f" % ratio))
    else:
        best = min(PRACTICAL, key=lambda k: m[k])
        runner_up = min((k for k in PRACTICAL if k != "SMIS"), key=lambda k: m[k])
        d, se = paired_difference(res, runner_up, "SMIS", equal_spp)
        out.append(("SMIS lowest of the practical modes at %d spp" % equal_spp, best == "SMIS",
                    ", ".join("%s %.4g" % (k, m[k]) for k in PRACTICAL) +
                    "; paired per seed: %s - SMIS = %.4g ± %.2g" % (runner_up, d, se)))
    return out


def paired_difference(res, a, b, spp):
    """Mean and standard error over seeds of MSE(a) - MSE(b) at `spp`, render by render with the same
    seed: UNIFORM, SPECTRAL_IS, HERO and SMIS draw their paths from the same random numbers at equal
    seed (their wavelength offsets come from the pixel sequence), up to where the wavelength changes
    the path (dispersion, Russian roulette), so the paired difference is less noisy than the MSEs."""
    mse = {(r["mode"], r["seed"]): r["mse"] for r in res["rows"] if r["spp"] == spp}
    d = [mse[(a, seed)] - mse[(b, seed)] for (mode, seed) in mse if mode == a and (b, seed) in mse]
    return float(np.mean(d)), float(np.std(d, ddof=1) / np.sqrt(len(d))) if len(d) > 1 else 0.0


def excess_section(res, args):
    """Where SMIS's error above BRUTE_FORCE comes from on the Fig. 8 scene: the per-path model of
    bench/spectral_model.py, and the measured excess MSE(mode) - MSE(BRUTE_FORCE) at equal spp."""
    from spectral_model import model
    s = res["summary"]
    lines = ["## Where SMIS's excess colour error comes from (spectral_gold)", "",
             "BRUTE_FORCE evaluates 512 stratified wavelengths per path, so its error is the path's own "
             "variance; a mode's error above it at equal spp is the variance of its wavelength estimate "
             "given the path (law of total variance). Per-path model (`bench/spectral_model.py`: a path "
             "reflecting F10 off gold, variance over wavelength sets / squared value, n = 4):", "",
             "| density p(l) | jittered strata (before) | shared offset (SMIS now) | independent (SMIS_i) |",
             "| --- | --- | --- | --- |"]
    rows = {}
    for name, n, pattern, v in model():
        if n == 4:
            rows.setdefault(name, {})[pattern] = v
    for name, v in rows.items():
        lines.append("| %s | %.3f | %.3f | %.3f |" % (name, v["jittered"], v["shared"], v["independent"]))
    lines += ["", "Measured excess over BRUTE_FORCE (MSE difference / BRUTE_FORCE MSE):", "",
              "| spp | SMIS_NOSEQ (shared offset, independent per sample) | SMIS (offsets from the pixel sequence) |",
              "| --- | --- | --- |"]
    for spp in args.bf_spp:
        bf = s.get("BRUTE_FORCE@%d" % spp)
        if not bf:
            continue
        cells = ["%.3f" % ((s[k]["mse"] - bf["mse"]) / bf["mse"]) if k in s else "-"
                 for k in ("SMIS_NOSEQ@%d" % spp, "SMIS@%d" % spp)]
        lines.append("| %d | %s |" % (spp, " | ".join(cells)))
    return lines + [""]


def write_summary(path, args, scenes, cost):
    lines = ["# Spectral rendering benchmark (issue 4, paper §5)", "",
             "Generated by `/usr/bin/python3 bench/spectral_bench.py%s`. Resolution %d%% of 128x128, "
             "%s seeds per point, n = %d wavelengths for HERO / SMIS / SMIS_INDEPENDENT. Error = MSE "
             "in linear RGB against a BRUTE_FORCE reference (%d renders x %d spp, averaged), minus the "
             "reference's own variance (estimated from the spread of its renders). Times are engine "
             "render times on a 2-core machine shared with other jobs (load varies): compare ratios. "
             "The wavelength offsets of UNIFORM, SPECTRAL_IS, HERO and SMIS come from a sequence "
             "stratified over each pixel's samples (`engine/core/pixel_sequence.h`); SMIS_NOSEQ is SMIS "
             "with independent offsets per sample (`spectral_pixel_sequence` off), for comparison."
             % (" --quick" if args.quick else "", args.percentage,
                ", ".join("%d (%s)" % (res.get("seeds", args.seeds), name) for name, res in scenes.items()),
                args.wavelengths,
                args.ref_renders, args.ref_spp), ""]
    for name, res in scenes.items():
        lines += ["## %s (%s)" % (name, SCENES[name]), "",
                  "Reference: mean %.4g, variance of its mean %.3g (subtracted), %.0f s."
                  % (res["ref_mean"], res["ref_variance"], res["ref_seconds"]), "",
                  "| mode | " + " | ".join("MSE @%d spp" % spp for spp in args.spp) + " | s @%d spp |"
                  % args.equal_spp, "| --- |" + " --- |" * (len(args.spp) + 1)]
        for mode in ROWS:
            cells = []
            for spp in args.spp:
                v = res["summary"].get("%s@%d" % (mode, spp))
                cells.append("%.4g ± %.2g" % (v["mse"], v["mse_stderr"]) if v else "-")
            t = res["summary"].get("%s@%d" % (mode, args.equal_spp))
            lines.append("| %s | %s | %s |" % (mode, " | ".join(cells), "%.2f" % t["seconds"] if t else "-"))
        lines += [""]
        for what, ok, detail in checks(name, res, args.equal_spp):
            lines.append("- %s: **%s** (%s)" % (what, "met" if ok else "NOT met", detail))
        lines += ["", "![%s](%s.png)" % (name, name), ""]
    if "spectral_gold" in scenes:
        lines += excess_section(scenes["spectral_gold"], args)
    if cost:
        lines += ["## AUTO on an RGB-only scene (cornell.blend)", "",
                  "AUTO resolves to `%s`; %d interleaved renders of %d spp each: best AUTO %.3f s, "
                  "best RGB %.3f s, ratio %.3f (medians %.3f / %.3f s). Images identical: %s."
                  % (cost["AUTO"]["resolved"], args.cost_repeats, args.cost_spp, cost["AUTO"]["best"],
                     cost["RGB"]["best"], cost["ratio_best"], cost["AUTO"]["median"], cost["RGB"]["median"],
                     cost["identical_images"]), ""]
    if args.dispersion:
        d = args.dispersion
        lines += ["## Dispersion in spectral_glass", "",
                  "SMIS, %d spp, left with the dispersive glasses, right with each glass at a constant IOR "
                  "equal to its n_d. Mean squared per-pixel rg-chromaticity change that dispersion causes, "
                  "noise of the renders removed (see `dispersion_demo`): %.3g ± %.2g (RMS %.4f; the "
                  "renders' own chromaticity noise RMS is %.4f). Per 8x8-pixel block (chromaticity of the "
                  "block's summed RGB, %d renders of each kind): %d of %d lit blocks change by more than 4 "
                  "standard errors, by %.3f in rg on average; the same test between two sets of "
                  "constant-IOR renders (no change) passes %d blocks."
                  % (d["spp"], d["signal_mean_sq"], d["signal_stderr"], d["rms_chroma_change"],
                     d["rms_noise"], d["seeds"], d["blocks_significant"], d["blocks"],
                     d["significant_block_change"], d["blocks_significant_control"]),
                  "", "![dispersion on / off, glasses enlarged 3x](spectral_glass_dispersion_crop.png)", "",
                  "Whole frame: ![dispersion on / off](spectral_glass_dispersion.png)", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="CI-sized run")
    ap.add_argument("--scenes", nargs="*", default=list(SCENES))
    ap.add_argument("--no-cost", action="store_true", help="skip the AUTO vs RGB cost measurement")
    ap.add_argument("--seeds", type=int, help="seeds per point (default 4, --quick 2)")
    ap.add_argument("--keep", action="store_true",
                    help="keep the other scenes' results of bench/results/spectral[_quick].json in the summary")
    ap.add_argument("--from-json", action="store_true",
                    help="no rendering: rewrite plots and summary from bench/results/spectral[_quick].json")
    args = ap.parse_args()
    if args.from_json:
        return rewrite_from_json(args.quick)
    if args.quick:
        args.percentage, args.ref_renders, args.ref_spp = 50, 4, 16
        args.spp, args.bf_spp, args.equal_spp = [4, 16], [4], 4
        args.cost_repeats, args.cost_spp, args.demo_spp, args.demo_seeds = 3, 8, 16, 3
    else:
        args.percentage, args.ref_renders, args.ref_spp = 100, 4, 64
        args.spp, args.bf_spp, args.equal_spp = [4, 16, 64], [4, 16], 16
        args.cost_repeats, args.cost_spp, args.demo_spp, args.demo_seeds = 5, 32, 256, 4
    args.seeds = args.seeds or (2 if args.quick else 4)
    args.wavelengths = 4
    os.makedirs(RESULTS, exist_ok=True)
    os.makedirs(DOCS, exist_ok=True)
    scenes, saved = {}, None
    if args.keep:
        with open(json_path(args.quick)) as f:
            saved = json.load(f)
        scenes = {k: dict(v, seeds=v.get("seeds", saved["args"]["seeds"]))
                  for k, v in saved["scenes"].items() if k not in args.scenes}
    for name in args.scenes:
        print("== %s" % name, flush=True)
        res = bench_scene(name, args)
        scenes[name] = res
        write_csv(os.path.join(RESULTS, "%s.csv" % name), res["rows"])
        plot(os.path.join(RESULTS, "%s.png" % name), name, res)
        for what, ok, detail in checks(name, res, args.equal_spp):
            print("  %s: %s (%s)" % (what, "met" if ok else "NOT met", detail), flush=True)
    cost = None if args.no_cost else bench_auto_cost(args)
    if cost is None and saved:
        cost = saved["cost"]
    args.dispersion = dispersion_demo(args) if "spectral_glass" in args.scenes else None
    if args.dispersion is None and saved:
        args.dispersion = saved["args"].get("dispersion")
    if cost:
        print("AUTO / RGB best-time ratio %.3f, identical images %s" % (cost["ratio_best"], cost["identical_images"]))
    with open(json_path(args.quick), "w") as f:
        json.dump({"scenes": {k: {kk: vv for kk, vv in v.items() if kk != "ref_image"} for k, v in scenes.items()},
                   "cost": cost, "args": vars(args)}, f, indent=1)
    publish(args, scenes, cost)
    return 0


def json_path(quick):
    return os.path.join(RESULTS, "spectral_quick.json" if quick else "spectral.json")


def rewrite_from_json(quick):
    with open(json_path(quick)) as f:
        saved = json.load(f)
    args = argparse.Namespace(**saved["args"])
    args.quick = quick
    for name, res in saved["scenes"].items():
        plot(os.path.join(RESULTS, "%s.png" % name), name, res)
    publish(args, saved["scenes"], saved["cost"])
    return 0


def publish(args, scenes, cost):
    """Summary into bench/results; for a full run also into docs/bench with the plots, CSVs, PNGs."""
    suffix = "_quick" if args.quick else ""
    write_summary(os.path.join(RESULTS, "spectral_summary%s.md" % suffix), args, scenes, cost)
    if not args.quick:
        shutil.copy(os.path.join(RESULTS, "spectral_summary.md"), os.path.join(DOCS, "spectral_summary.md"))
        for name in scenes:
            for ext in ("png", "csv"):
                shutil.copy(os.path.join(RESULTS, "%s.%s" % (name, ext)), DOCS)
        if args.dispersion:
            shutil.copy(args.dispersion["png"], DOCS)
            shutil.copy(args.dispersion["crop_png"], DOCS)


if __name__ == "__main__":
    sys.path.insert(0, HERE)
    sys.exit(main())
