"""What an unused feature costs: this build against a build of the engine without the feature.

    /usr/bin/python3 bench/skip_bench.py [--baseline REV] [--repeats 5] [--quick]
    /usr/bin/python3 bench/skip_bench.py --instructions     # load-independent: callgrind counts

The engine analyses each scene before rendering and switches off what the scene does not use
(media tracking without media, spectral sampling without spectral content in AUTO mode, the
filtering grid when the integrator does not filter, ...). This benchmark checks that the switch
really makes the feature free: it builds the engine at REV, a commit from before the features were
added (default BASELINE below), into a temporary folder, and renders scenes that do not use them
with both builds, interleaved, best of --repeats, at a fixed sample count. The cost of a feature
that is present but unused is `this / baseline - 1` of the engine's render time (the goal is at most
2%; the timing noise on a shared machine is about that large, so read small values as "no
measurable cost"). Writes bench/results/skip_bench.{json,csv,md}.

Render times are the engine's own (from its stats line, 0.01 s resolution): the sample counts are
chosen so that each render takes several seconds (the baseline build prints 0.1 s).

--instructions counts instead the instructions the render executes (valgrind's callgrind, collecting
only inside RenderSession::render_loop, one thread so that the count does not depend on scheduling):
repeatable to a few parts per million and independent of the machine's load, which timing on a
shared machine is not. Both builds trace the same rays (the random streams are the same), so the
difference is the cost of the code around them. Instructions are not time (a cache miss costs more
than an add), so both measures are reported. Writes bench/results/skip_bench_instructions.{json,csv,md}.
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

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from render import remove, render_smis  # noqa: E402

# The last commit before spectral rendering and participating media were added (path tracer and
# path-space filtering only).
BASELINE = "e4eb3ce"
# (scene, settings, what the scene leaves unused)
CASES = [
    ("cornell", {"integrator": "PATH", "samples": 768}, "no media, no spectral content"),
    ("psf_room", {"integrator": "PATH", "samples": 288}, "no media, no spectral content"),
    ("psf_glossy", {"integrator": "PSF_SMIS", "samples": 64}, "no media, no spectral content (filtering on)"),
]
COMMON = {"max_bounces": 8, "filter_type": "BOX", "filter_width": 1.0, "seed": 1}
# --instructions: the same scenes at sample counts valgrind runs in about a minute each, plus the
# many-light scene with plain NEE (RIS/ReSTIR present but unused).
INSTRUCTION_CASES = [
    ("cornell", {"integrator": "PATH", "samples": 8}, "no media, no spectral content"),
    ("psf_room", {"integrator": "PATH", "samples": 2}, "no media, no spectral content"),
    ("psf_glossy", {"integrator": "PSF_SMIS", "samples": 2}, "no media, no spectral content (filtering on)"),
    ("many_lights", {"integrator": "PATH", "samples": 4}, "no media, no spectral content, NEE (no RIS/ReSTIR)"),
]
CALLGRIND = ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", "--collect-atstart=no",
             "--toggle-collect=smis::RenderSession::render_loop*"]


def log(msg):
    print("[skip_bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


def git(*args, cwd=ROOT):
    return subprocess.run(["git", "-C", cwd, *args], check=True, capture_output=True, text=True).stdout.strip()


def build_baseline(rev):
    """Builds the engine at `rev` (once; cached by commit) and returns its user-scripts folder."""
    commit = git("rev-parse", "--short", rev)
    base = os.path.join("/tmp", "smis_skip_baseline_" + commit)
    src = os.path.join(base, "src")
    if not os.path.exists(os.path.join(src, "CMakeLists.txt")):
        os.makedirs(src, exist_ok=True)
        archive = subprocess.run(["git", "-C", ROOT, "archive", commit], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", src], input=archive, check=True)
    build = os.path.join(base, "build")
    log("building the baseline %s in %s" % (commit, build))
    subprocess.run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"], check=True,
                   capture_output=True)
    subprocess.run(["cmake", "--build", build, "-j", str(os.cpu_count()), "--target", "_smis"], check=True,
                   capture_output=True)
    scripts = os.path.join(base, "scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "smis_render")
    if not os.path.islink(link):
        os.symlink(os.path.join(src, "addon", "smis_render"), link)
    return commit, scripts


def current_scripts():
    """A user-scripts folder whose add-on is this checkout (independent of what is installed)."""
    scripts = os.path.join("/tmp", "smis_skip_current")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "smis_render")
    if os.path.islink(link):
        os.remove(link)
    os.symlink(os.path.join(ROOT, "addon", "smis_render"), link)
    return scripts


def count_instructions(blend, settings, scripts):
    """Instructions executed by the engine's render loop (callgrind, one thread)."""
    run = render_smis(blend, settings, threads=1, addon_scripts=scripts, wrapper=CALLGRIND, retries=0)
    remove(run)
    found = re.findall(r"Collected\s*:\s*(\d+)", run.output)
    if not found:
        raise RuntimeError("no callgrind total in Blender's output:\n" + run.output[-2000:])
    return int(found[-1]), run


def write_results(name, doc, rows, unit, title, intro, value_format):
    """bench/results/<name>.{json,csv,md}: the document, one CSV row per case, a Markdown table whose
    baseline / this / cost cells are formatted by `value_format` (rows hold baseline_<unit>, this_<unit>)."""
    out = os.path.join(HERE, "results")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, name + ".json"), "w") as f:
        json.dump(doc, f, indent=2)
    with open(os.path.join(out, name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["scene", "unused", "baseline_" + unit, "this_" + unit, "cost_percent"],
                           extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    header = "baseline instructions | this" if unit == "instructions" else "baseline s | this s"
    lines = [title, "", intro, "", "| scene | integrator, spp | unused here | %s | cost | stats line |" % header,
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        values = value_format % (r["baseline_" + unit], r["this_" + unit], r["cost_percent"])
        lines.append("| %s | %s, %d | %s %s %s |"
                     % (r["scene"], r["settings"]["integrator"], r["settings"]["samples"], r["unused"], values,
                        r["stats_line_skipped"].replace("|", "/")[:160] or "-"))
    with open(os.path.join(out, name + ".md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    log("wrote bench/results/%s.{json,csv,md}" % name)


def instructions_main(args):
    commit, base_scripts = build_baseline(args.baseline)
    builds = {"baseline": base_scripts, "this": current_scripts()}
    rows = []
    this_only = dict(kv.split("=", 1) for kv in args.this_set)
    for scene, settings, unused in INSTRUCTION_CASES:
        blend = os.path.join(ROOT, "scenes", scene + ".blend")
        s = dict(COMMON, **settings)
        counts, skipped_line = {}, ""
        for name, scripts in builds.items():
            counts[name], run = count_instructions(blend, dict(s, **this_only) if name == "this" else s, scripts)
            if name == "this":
                skipped_line = next((ln.strip() for ln in run.output.splitlines() if "skipped" in ln), "")
        cost = counts["this"] / counts["baseline"] - 1.0
        rows.append({"scene": scene, "settings": s, "unused": unused, "baseline_instructions": counts["baseline"],
                     "this_instructions": counts["this"], "cost_percent": 100.0 * cost,
                     "stats_line_skipped": skipped_line})
        log("%s (%s): baseline %d, this %d instructions: %+.2f%%" % (scene, unused, counts["baseline"],
                                                                      counts["this"], 100.0 * cost))
    doc = {"baseline": commit, "this": git("rev-parse", "--short", "HEAD"), "measure": "callgrind Ir, 1 thread",
           "this_only_settings": this_only,
           "written": datetime.datetime.now().isoformat(timespec="seconds"), "cases": rows}
    suffix = "_" + "_".join("%s_%s" % kv for kv in sorted(this_only.items())).lower() if this_only else ""
    write_results("skip_bench_instructions" + suffix, doc, rows, "instructions",
                  "# Cost of present-but-unused features, in instructions",
                  "Generated by `bench/skip_bench.py --instructions` on %s: instructions executed by the render "
                  "loop (callgrind, 1 thread) of this build (%s) against the baseline build %s (before spectral "
                  "rendering, media, ReSTIR, textures, depth of field and passes existed), same scenes, settings "
                  "and seed%s." % (doc["written"], doc["this"], commit,
                                   "; this build only: " + ", ".join("%s = %s" % kv for kv in this_only.items())
                                   if this_only else ""),
                  "| %d | %d | %+.2f%% |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", default=BASELINE, help="git revision without the features (default %(default)s)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="2 repeats, quarter sample counts")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--instructions", action="store_true",
                    help="count instructions with callgrind instead of timing (load-independent)")
    ap.add_argument("--this-set", action="append", default=[], metavar="KEY=VALUE",
                    help="--instructions: a scene.smis setting for this build only (one the baseline does not "
                         "have), e.g. sampling_pattern=RANDOM to leave a default-on feature unused")
    args = ap.parse_args()
    if args.instructions:
        return instructions_main(args)
    repeats = 2 if args.quick else args.repeats
    commit, base_scripts = build_baseline(args.baseline)
    builds = {"baseline": base_scripts, "this": current_scripts()}
    rows = []
    load_start = os.getloadavg()
    for scene, settings, unused in CASES:
        blend = os.path.join(ROOT, "scenes", scene + ".blend")
        s = dict(COMMON, **settings)
        if args.quick:
            s["samples"] = max(1, s["samples"] // 4)
        best = {}
        skipped_line = ""
        for rep in range(repeats):
            for name, scripts in builds.items():  # interleaved: a load change hits both builds
                run = render_smis(blend, s, threads=args.threads, addon_scripts=scripts)
                best[name] = min(best.get(name, float("inf")), run.seconds)
                if name == "this":
                    skipped_line = next((ln.strip() for ln in run.output.splitlines() if "skipped" in ln), "")
                remove(run)
        cost = best["this"] / best["baseline"] - 1.0
        rows.append({"scene": scene, "settings": s, "unused": unused, "baseline_seconds": best["baseline"],
                     "this_seconds": best["this"], "cost_percent": 100.0 * cost,
                     "stats_line_skipped": skipped_line})
        log("%s (%s): baseline %.1f s, this %.1f s: %+.1f%%" % (scene, unused, best["baseline"], best["this"],
                                                                100.0 * cost))
    doc = {"baseline": commit, "this": git("rev-parse", "--short", "HEAD"), "repeats": repeats,
           "quick": args.quick, "loadavg_start": load_start, "loadavg_end": os.getloadavg(),
           "written": datetime.datetime.now().isoformat(timespec="seconds"), "cases": rows}
    write_results("skip_bench" + ("_quick" if args.quick else ""), doc, rows, "seconds",
                  "# Cost of present-but-unused features",
                  "Generated by `bench/skip_bench.py%s` on %s: this build (%s) against the baseline build %s "
                  "(before spectral rendering and media existed), same scenes and settings, interleaved, best of "
                  "%d. Load average start/end %.2f / %.2f." % (" --quick" if args.quick else "",
                                                               doc["written"], doc["this"], commit, repeats,
                                                               load_start[0], doc["loadavg_end"][0]),
                  "| %.1f | %.1f | %+.1f%% |")


if __name__ == "__main__":
    main()
