#!/usr/bin/python3
"""Reproduce Fig. 2 of West et al. 2020 (Continuous Multiple Importance Sampling), sec. 3.3.

Compiles bench/fig2/fig2_variance.cpp (g++ -O2 -I engine, single-threaded), runs it and writes
  bench/fig2/fig2_variance.csv    variance of the N-sample estimate vs total sample count N
                                  (R independent runs per point), every configuration and estimator,
                                  and SMIS_n for n = 1..64 in the star configuration (panel "f")
  bench/fig2/fig2_per_sample.csv  per-sample variance v = N Var (1M samples per estimator) with
                                  standard errors, and the quadrature values
  bench/fig2/fig2.png             the figure
Configurations and estimators: engine/mis/cmis_1d_experiment.h.

Usage: /usr/bin/python3 bench/fig2/fig2.py [--runs R] [--samples M] [--plot-only]
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
VAR_CSV = os.path.join(HERE, "fig2_variance.csv")
PS_CSV = os.path.join(HERE, "fig2_per_sample.csv")
PNG = os.path.join(HERE, "fig2.png")

CONFIGS = ["b", "c", "d", "e"]
PDF_TEXT = {
    "b": "p(t)=1\np(x|t)=0.1+1.8x",
    "c": "p(t)=0.1+1.8t\np(x|t)=1",
    "d": "p(t)=1+0.9cos(2πt)\np(x|t)=1+0.9t(2x-1)",
    "e": "p(t)=1\np(x|t)=1+0.9(1-2t)(2x-1)",
}
STYLE = {  # estimator: (label, colour, line style, marker)
    "CMIS_u": ("CMIS$_u$", "tab:red", "-", "o"),
    "SMIS_1": ("SMIS$_1$", "#9ecae1", "-", "s"),
    "SMIS_2": ("SMIS$_2$", "#4292c6", "-", "s"),
    "SMIS_4": ("SMIS$_4$", "#08306b", "-", "s"),
    "CMIS_b": ("CMIS$_b$", "black", "--", "^"),
    "SW_4": ("SW$_4$ (stoch. weight)", "tab:green", ":", "x"),
}
STAR = ("f1", "e")


def run(cmd):
    return subprocess.run(cmd, check=True, capture_output=True, text=True).stdout


def generate(runs, samples):
    with tempfile.TemporaryDirectory() as tmp:
        exe = os.path.join(tmp, "fig2_variance")
        src = os.path.join(HERE, "fig2_variance.cpp")
        subprocess.run(["g++", "-O2", "-std=c++17", "-I", os.path.join(ROOT, "engine"), src, "-o", exe], check=True)
        print("running fig2_variance --runs %d ..." % runs, flush=True)
        with open(VAR_CSV, "w") as fh:
            fh.write(run([exe, "--runs", str(runs)]))
        print("running fig2_variance --per-sample --samples %d ..." % samples, flush=True)
        with open(PS_CSV, "w") as fh:
            fh.write(run([exe, "--per-sample", "--samples", str(samples)]))
        return run([exe, "--joint", "96"])


def read_csv(path_or_text, is_text=False):
    fh = io.StringIO(path_or_text) if is_text else open(path_or_text)
    with fh:
        return list(csv.DictReader(fh))


def joint_text():
    with tempfile.TemporaryDirectory() as tmp:
        exe = os.path.join(tmp, "fig2_variance")
        subprocess.run(["g++", "-O2", "-std=c++17", "-I", os.path.join(ROOT, "engine"),
                        os.path.join(HERE, "fig2_variance.cpp"), "-o", exe], check=True)
        return run([exe, "--joint", "96"])


def plot(var_rows, ps_rows, joint_rows):
    fig, axes = plt.subplots(3, 5, figsize=(22, 13))
    ps = {(r["integrand"], r["config"], r["estimator"]): r for r in ps_rows}

    # (a) integrands
    ax = axes[0, 0]
    x = np.linspace(0, 1, 1001)
    ax.plot(x, 3 * x * x, label="f1(x) = 3x²")
    ax.plot(x, np.where(x >= 0.5, 2.0, 0.0), label="f2(x) = 2·[x ≥ 1/2]")
    ax.set_title("(a) integrands (∫ = 1)")
    ax.set_xlabel("x")
    ax.legend(loc="upper left", fontsize=9)

    # (b)-(e) joint densities p(t, x): x horizontal, t vertical, with the marginals
    for k, c in enumerate(CONFIGS):
        ax = axes[0, k + 1]
        rows = [r for r in joint_rows if r["config"] == c]
        g = int(round(len(rows) ** 0.5))
        img = np.array([float(r["p_tx"]) for r in rows]).reshape(g, g)  # [t index, x index]
        ax.imshow(img, origin="lower", extent=[0, 1, 0, 1], cmap="magma", vmin=0, vmax=img.max())
        pt = np.array([float(rows[i * g]["p_t"]) for i in range(g)])
        px = np.array([float(rows[j]["p_x"]) for j in range(g)])
        grid = (np.arange(g) + 0.5) / g
        ax.plot(grid, px / 2.2, color="cyan", lw=1.5, label="p(x) (scaled)")
        ax.plot(pt / 2.2, grid, color="lime", lw=1.5, label="p(t) (scaled)")
        ax.set_xlim(0, 1)
        ax.set_ylim(0, 1)
        ax.set_xlabel("x (sample)")
        ax.set_ylabel("t (technique)")
        ax.set_title("(%s) p(t,x)%s\n%s" % (c, "  ★ with f1" if c == STAR[1] else "", PDF_TEXT[c]), fontsize=10)
        if k == 0:
            ax.legend(loc="upper left", fontsize=8)

    # variance vs N, one row per integrand, one column per configuration
    for row, f in enumerate(["f1", "f2"]):
        for k, c in enumerate(CONFIGS):
            ax = axes[row + 1, k + 1]
            lines = []
            for est, (label, col, ls, mk) in STYLE.items():
                pts = [r for r in var_rows if r["panel"] == "main" and r["integrand"] == f and r["config"] == c
                       and r["estimator"] == est]
                if not pts:
                    continue
                N = np.array([int(r["N"]) for r in pts])
                v = np.array([float(r["variance"]) for r in pts])
                ax.loglog(N, v, ls, color=col, marker=mk, ms=4, lw=1.3, label=label)
                p = ps.get((f, c, est))
                if p:
                    lines.append("%-7s %.3f" % (est.replace("CMIS_", "C").replace("SMIS_", "S"),
                                                float(p["per_sample_variance"])))
            star = " ★" if (f, c) == STAR else ""
            ax.set_title("(%s) %s%s: variance vs total samples N" % (c, f, star), fontsize=10)
            ax.set_xlabel("total samples N")
            ax.set_ylabel("Var[estimate]")
            ax.grid(True, which="both", alpha=0.25)
            ax.text(0.03, 0.03, "N·Var (1M samples):\n" + "\n".join(lines), transform=ax.transAxes, fontsize=8,
                    family="monospace", va="bottom", bbox=dict(fc="white", alpha=0.8, lw=0))
            if row == 0 and k == 0:
                ax.legend(fontsize=8, loc="upper right")

    # (f) SMIS_n in the star configuration: variance vs N ...
    ax = axes[1, 0]
    ns = sorted({int(r["n"]) for r in var_rows if r["panel"] == "f"})
    cmap = plt.get_cmap("viridis")
    for i, n in enumerate(ns):
        pts = [r for r in var_rows if r["panel"] == "f" and int(r["n"]) == n]
        N = np.array([int(r["N"]) for r in pts])
        v = np.array([float(r["variance"]) for r in pts])
        ax.loglog(N, v, "-s", ms=3, color=cmap(i / max(1, len(ns) - 1)), label="SMIS$_{%d}$" % n)
    cb = [r for r in var_rows if r["panel"] == "main" and (r["integrand"], r["config"]) == STAR
          and r["estimator"] == "CMIS_b" and int(r["N"]) >= 64]
    ax.loglog([int(r["N"]) for r in cb], [float(r["variance"]) for r in cb], "--^", color="black", ms=4,
              label="CMIS$_b$")
    ax.set_title("(f) ★ (f1, e): SMIS$_n$ variance vs N", fontsize=10)
    ax.set_xlabel("total samples N")
    ax.set_ylabel("Var[estimate]")
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7, ncol=2)

    # ... and the per-sample variance N·Var against n, with CMIS_b and the large-n limit of SMIS_n
    ax = axes[2, 0]
    star_rows = [r for r in ps_rows if (r["integrand"], r["config"]) == STAR]
    for prefix, label, col, mk in [("SMIS_", "SMIS$_n$ (n samples/realization)", "tab:blue", "s"),
                                   ("SW_", "SW$_n$ (1 sample, n techniques in weight)", "tab:green", "x")]:
        sel = [r for r in star_rows if r["estimator"].startswith(prefix) and r["estimator"][len(prefix):].isdigit()]
        sel.sort(key=lambda r: int(r["estimator"][len(prefix):]))
        n = np.array([int(r["estimator"][len(prefix):]) for r in sel])
        v = np.array([float(r["per_sample_variance"]) for r in sel])
        e = np.array([float(r["per_sample_variance_se"]) for r in sel])
        ax.errorbar(n, v, yerr=2 * e, fmt="-" + mk, color=col, ms=4, capsize=2, label=label)
    r0 = star_rows[0]
    ax.axhline(float(r0["exact_cmis_b"]), color="black", ls="--", label="CMIS$_b$ (quadrature)")
    ax.axhline(float(r0["exact_cmis_u"]), color="tab:red", ls="-", lw=1, label="CMIS$_u$ = SMIS$_1$ (quadrature)")
    ax.axhline(float(r0["smis_large_n_limit"]), color="tab:blue", ls=":",
               label="n→∞ limit: CMIS$_b$ − Var$_t$[μ(t)]")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("n")
    ax.set_ylabel("N·Var  (per-sample variance)")
    ax.set_title("(f) ★ (f1, e): N·Var vs n (±2 s.e.)", fontsize=10)
    ax.grid(True, which="both", alpha=0.25)
    ax.legend(fontsize=7)

    fig.suptitle("CMIS / SMIS 1D experiment (West et al. 2020, Fig. 2): equal total sample count N; "
                 "SMIS$_n$ averages N/n realizations", fontsize=13)
    fig.tight_layout(rect=[0, 0, 1, 0.97])
    fig.savefig(PNG, dpi=80)
    print("wrote", PNG)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=1000, help="independent runs per (estimator, N) point")
    ap.add_argument("--samples", type=int, default=1 << 20, help="samples per estimator for the per-sample table")
    ap.add_argument("--plot-only", action="store_true", help="replot from the existing CSV files")
    args = ap.parse_args()
    if args.plot_only:
        joint = joint_text()
    else:
        joint = generate(args.runs, args.samples)
        print("wrote", VAR_CSV, "and", PS_CSV)
    plot(read_csv(VAR_CSV), read_csv(PS_CSV), read_csv(joint, is_text=True))
    return 0


if __name__ == "__main__":
    sys.exit(main())
