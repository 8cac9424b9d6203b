"""What an unused feature costs: this build against a build of the engine without the feature.

    /usr/bin/python3 bench/skip_bench.py [--baseline REV] [--repeats 5] [--quick]
    /usr/bin/python3 bench/skip_bench.py --instructions     # load-independent: callgrind counts
    /usr/bin/python3 bench/skip_bench.py --per-feature [--rev HEAD] [--jobs 1]   # each feature on its own

The engine analyses each scene before rendering and switches off what the scene does not use
(media tracking without media, spectral sampling without spectral content in AUTO mode, the
filtering grid when the integrator does not filter, ...). This benchmark checks that the switch
really makes the feature free: it builds the engine at REV, a commit from before the features were
added (default BASELINE below), into a temporary folder, and renders scenes that do not use them
with both builds, interleaved, best of --repeats, at a fixed sample count. The cost of a feature
that is present but unused is `this / baseline - 1` of the engine's render time (the goal is at most
1%; the timing noise on a shared machine is larger than that, so read small values as "no
measurable cost" and use --instructions or --per-feature for the claim). Writes bench/results/skip_bench.{json,csv,md}.

Render times are the engine's own (from its stats line, 0.01 s resolution): the sample counts are
chosen so that each render takes several seconds (the baseline build prints 0.1 s).

--instructions counts instead the instructions the render executes (valgrind's callgrind, collecting
only inside RenderSession::render_loop, one thread so that the count does not depend on scheduling):
repeatable to a few parts per million and independent of the machine's load, which timing on a
shared machine is not. Both builds trace the same rays (the random streams are the same), so the
difference is the cost of the code around them. Instructions are not time (a cache miss costs more
than an add), so both measures are reported. Writes bench/results/skip_bench_instructions.{json,csv,md}.

--per-feature measures each feature on its own, in instructions: the engine at --rev is built (into
/tmp, once per commit and feature set) with every feature, without all of them, and without each one
(cmake -DSMIS_WITHOUT=<feature>, engine/core/features.h: the feature's hot-path checks become
compile-time constants and its code is dropped). The cost of a feature is the build with every
feature against the build with every feature but that one, on scenes that do not use it; the last
rows compare against the build with none. Every build renders with the random sampling pattern (the
stratified one is a feature). Writes bench/results/skip_bench_features.{json,csv,md}.
"""
import argparse
import csv
import datetime
import hashlib
import json
import os
import re
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from callgrind import callgrind_wrapper  # noqa: E402
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
# --per-feature: the features of engine/core/features.h (as cmake -DSMIS_WITHOUT spells them), what
# they are, and the cases beyond FEATURE_CASES where they have code on the hot path.
FEATURES = [
    ("volumes", "media tracking, single scattering, photon planes", []),
    ("spectral", "spectral path tracer (per-sample hook)", []),
    ("resampled_lights", "RIS / ReSTIR at the first vertex", ["many_lights"]),
    ("textures", "image textures, normal maps, Object Info colour", ["psf_glossy"]),
    ("textured_emission", "emission colour from an image", []),
    ("cutouts", "Principled Alpha < 1", []),
    ("principled_extras", "clearcoat, sheen, Burley diffuse, Transparent BSDF", []),
    ("closures", "Oren-Nayar, Velvet, Translucent, Refraction, Beckmann, Toon, multiscatter GGX, anisotropic lobes", []),
    ("depth_of_field", "thin-lens camera", []),
    ("aux_passes", "Depth / Normal / Albedo / diagnostic passes", []),
    ("stratified", "stratified sampling pattern", ["psf_glossy"]),
]
FEATURE_CASES = ["cornell", "psf_room"]
# Every feature unused: the random sampling pattern, since the stratified one is a feature too (a
# build without it refuses STRATIFIED; both patterns trace the same number of rays).
FEATURE_SETTINGS = {"cornell": {"integrator": "PATH", "samples": 8}, "psf_room": {"integrator": "PATH", "samples": 2},
                    "many_lights": {"integrator": "PATH", "samples": 4},
                    "psf_glossy": {"integrator": "PSF_SMIS", "samples": 2}}
FEATURE_COMMON = dict(COMMON, sampling_pattern="RANDOM")
# Every feature costs at most 1% when unused (issue 21).
GOAL_PERCENT = 1.0


def log(msg):
    print("[skip_bench %s] %s" % (time.strftime("%H:%M:%S"), msg), flush=True)


def git(*args, cwd=ROOT):
    return subprocess.run(["git", "-C", cwd, *args], check=True, capture_output=True, text=True).stdout.strip()


def build_tree(rev, without=(), prefix="smis_skip_", jobs=None):
    """Builds the engine at `rev` without the features `without` (cmake -DSMIS_WITHOUT, engine/core/
    features.h) into /tmp, once (cached by commit and feature set), and returns (commit, user-scripts
    folder). Each build has its own source tree: the module is written into the add-on's folder."""
    commit = git("rev-parse", "--short", rev)
    base = os.path.join("/tmp", prefix + commit + ("_without_" + "-".join(sorted(without)) if without else ""))
    src = os.path.join(base, "src")
    if not os.path.exists(os.path.join(src, "CMakeLists.txt")):
        os.makedirs(src, exist_ok=True)
        archive = subprocess.run(["git", "-C", ROOT, "archive", commit], check=True, capture_output=True).stdout
        subprocess.run(["tar", "-x", "-C", src], input=archive, check=True)
    build = os.path.join(base, "build")
    log("building %s%s in %s" % (commit, " without " + ", ".join(without) if without else "", build))
    options = ["-DSMIS_WITHOUT=" + ";".join(without)] if without else []
    subprocess.run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release", *options], check=True,
                   capture_output=True)
    subprocess.run(["cmake", "--build", build, "-j", str(jobs or os.cpu_count()), "--target", "_smis"], check=True,
                   capture_output=True)
    scripts = os.path.join(base, "scripts")
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "smis_render")
    if not os.path.islink(link):
        os.symlink(os.path.join(src, "addon", "smis_render"), link)
    return commit, scripts


def build_baseline(rev, jobs=None):
    """The baseline build (before the features existed): see build_tree."""
    return build_tree(rev, prefix="smis_skip_baseline_", jobs=jobs)


def current_scripts():
    """A user-scripts folder whose add-on is this checkout (independent of what is installed). One
    folder per checkout, so runs from two worktrees at once do not measure each other's build."""
    checkout = hashlib.sha1(os.path.realpath(ROOT).encode()).hexdigest()[:10]
    scripts = os.path.join("/tmp", "smis_skip_current_" + checkout)
    os.makedirs(os.path.join(scripts, "addons"), exist_ok=True)
    link = os.path.join(scripts, "addons", "smis_render")
    if os.path.islink(link):
        os.remove(link)
    os.symlink(os.path.join(ROOT, "addon", "smis_render"), link)
    return scripts


def count_instructions(blend, settings, scripts):
    """Instructions executed by the engine's render loop (callgrind, one thread), the run, and the
    image's SHA-1 (two builds that trace the same rays write the same image)."""
    run = render_smis(blend, settings, threads=1, addon_scripts=scripts, wrapper=callgrind_wrapper(), retries=0)
    digest = hashlib.sha1(run.image.tobytes()).hexdigest()[:12]
    remove(run)
    found = re.findall(r"Collected\s*:\s*(\d+)", run.output)
    if not found:
        raise RuntimeError("no callgrind total in Blender's output:\n" + run.output[-2000:])
    return int(found[-1]), run, digest


def write_files(name, doc, rows, csv_fields, markdown):
    """bench/results/<name>.{json,csv,md}: the document, the rows' `csv_fields`, the Markdown lines."""
    out = os.path.join(HERE, "results")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, name + ".json"), "w") as f:
        json.dump(doc, f, indent=2)
    with open(os.path.join(out, name + ".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=csv_fields, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(out, name + ".md"), "w") as f:
        f.write("\n".join(markdown) + "\n")
    log("wrote bench/results/%s.{json,csv,md}" % name)


def write_results(name, doc, rows, unit, title, intro, value_format):
    """The baseline comparison's files: one CSV row per case, a Markdown table whose baseline / this /
    cost cells are formatted by `value_format` (rows hold baseline_<unit>, this_<unit>)."""
    header = "baseline instructions | this" if unit == "instructions" else "baseline s | this s"
    lines = [title, "", intro, "", "| scene | integrator, spp | unused here | %s | cost | stats line |" % header,
             "|---|---|---|---|---|---|---|"]
    for r in rows:
        values = value_format % (r["baseline_" + unit], r["this_" + unit], r["cost_percent"])
        lines.append("| %s | %s, %d | %s %s %s |"
                     % (r["scene"], r["settings"]["integrator"], r["settings"]["samples"], r["unused"], values,
                        r["stats_line_skipped"].replace("|", "/")[:160] or "-"))
    write_files(name, doc, rows, ["scene", "unused", "baseline_" + unit, "this_" + unit, "cost_percent"], lines)


def instructions_main(args):
    commit, base_scripts = build_baseline(args.baseline, args.jobs)
    builds = {"baseline": base_scripts, "this": current_scripts()}
    rows = []
    this_only = dict(kv.split("=", 1) for kv in args.this_set)
    for scene, settings, unused in INSTRUCTION_CASES:
        blend = os.path.join(ROOT, "scenes", scene + ".blend")
        s = dict(COMMON, **settings)
        counts, skipped_line = {}, ""
        for name, scripts in builds.items():
            counts[name], run, _ = count_instructions(blend, dict(s, **this_only) if name == "this" else s, scripts)
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


def per_feature_main(args):
    """Each feature's cost when present but unused: the build with every feature (the one that ships)
    against the build with every feature but that one, on the scenes where it has hot-path code; and
    the build with none of them, for the total."""
    features = [f for f in FEATURES if not args.features or f[0] in args.features.split(",")]
    names = [f for f, _, _ in FEATURES]
    builds = {"all": build_tree(args.rev, jobs=args.jobs)[1], "none": build_tree(args.rev, names, jobs=args.jobs)[1]}
    for f, _, _ in features:
        builds["without " + f] = build_tree(args.rev, [f], jobs=args.jobs)[1]
    commit = git("rev-parse", "--short", args.rev)
    cases = {f: FEATURE_CASES + extra for f, _, extra in features}
    scenes = list(dict.fromkeys(c for f, _, _ in features for c in cases[f]))
    counts, digests, skipped, refused = {}, {}, {}, {}

    def count(build, scene):
        if (build, scene) not in counts:
            s = dict(FEATURE_COMMON, **FEATURE_SETTINGS[scene])
            n, run, digest = count_instructions(os.path.join(ROOT, "scenes", scene + ".blend"), s, builds[build])
            counts[build, scene], digests[build, scene] = n, digest
            # The add-on replaces what a build refuses (a material, ...) and warns: the scene uses the feature.
            refused[build, scene] = "is not in this build" in run.output
            skipped[scene] = skipped.get(scene) or next(
                (ln.strip().split("skipped: ")[-1] for ln in run.output.splitlines() if "skipped: " in ln), "")
            log("%s, %s: %d instructions, image %s" % (scene, build, n, digest))
        return counts[build, scene]

    def row(feature, what, scene, absent_build):
        present, absent = count("all", scene), count(absent_build, scene)
        cost = 100.0 * (present / absent - 1.0)
        return {"feature": feature, "what": what, "scene": scene, "settings": dict(FEATURE_COMMON, **FEATURE_SETTINGS[scene]),
                "present_instructions": present, "absent_instructions": absent, "cost_percent": cost,
                "scene_uses_it": refused[absent_build, scene], "meets_goal": cost <= GOAL_PERCENT,
                "same_image": digests["all", scene] == digests[absent_build, scene]}

    rows = [row(f, what, scene, "without " + f) for f, what, _ in features for scene in cases[f]]
    rows += [row("all of them", "every feature above", scene, "none") for scene in scenes]
    doc = {"commit": commit, "measure": "callgrind Ir of RenderSession::render_loop, 1 thread",
           "compared": "every feature present (the shipped build) against every feature but one absent "
                       "(cmake -DSMIS_WITHOUT=<feature>); last rows: against all of them absent",
           "goal_percent": GOAL_PERCENT, "written": datetime.datetime.now().isoformat(timespec="seconds"),
           "stats_line_skipped": skipped, "rows": rows}
    lines = ["# Cost of each present-but-unused feature, in instructions", "",
             "Generated by `bench/skip_bench.py --per-feature` on %s (commit %s): instructions executed by the "
             "render loop (callgrind, 1 thread) of the build with every feature against the build without the "
             "feature (cmake -DSMIS_WITHOUT=<feature>, engine/core/features.h), on scenes that do not use it, "
             "same settings and seed (sampling pattern RANDOM, %s). Cost = present / absent - 1; goal <= %.0f%%. "
             "Same image: both builds wrote the identical image (the same rays were traced); where the build "
             "without the feature refused part of the scene (the add-on substitutes it and warns), the scene "
             "uses the feature and the row measures nothing."
             % (doc["written"], commit, ", ".join("%s %s" % kv for kv in sorted(COMMON.items())), GOAL_PERCENT), "",
             "| feature | what | scene | integrator, spp | present | absent | cost | <= %.0f%% | same image |"
             % GOAL_PERCENT, "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append("| %s | %s | %s | %s, %d | %d | %d | %+.3f%% | %s | %s |"
                     % (r["feature"], r["what"], r["scene"], r["settings"]["integrator"], r["settings"]["samples"],
                        r["present_instructions"], r["absent_instructions"], r["cost_percent"],
                        "(scene uses it)" if r["scene_uses_it"] else "yes" if r["meets_goal"] else "**no**",
                        "yes" if r["same_image"] else "no"))
    lines += ["", "Stats line of the build with every feature (skipped work):", ""]
    lines += ["* %s: `skipped: %s`" % kv for kv in skipped.items()]
    write_files("skip_bench_features", doc, rows, ["feature", "scene", "present_instructions", "absent_instructions",
                                                   "cost_percent", "meets_goal", "same_image"], lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--baseline", default=BASELINE, help="git revision without the features (default %(default)s)")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="2 repeats, quarter sample counts")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--instructions", action="store_true",
                    help="count instructions with callgrind instead of timing (load-independent)")
    ap.add_argument("--per-feature", action="store_true",
                    help="instructions of the build with every feature against the build without each one "
                         "(built from --rev into /tmp, cached)")
    ap.add_argument("--features", default="", help="--per-feature: a comma-separated subset of the features")
    ap.add_argument("--rev", default="HEAD", help="--per-feature: the commit to build (default %(default)s)")
    ap.add_argument("--jobs", type=int, default=0, help="parallel compile jobs (default: every core)")
    ap.add_argument("--this-set", action="append", default=[], metavar="KEY=VALUE",
                    help="--instructions: a scene.smis setting for this build only (one the baseline does not "
                         "have), e.g. sampling_pattern=RANDOM to leave a default-on feature unused")
    args = ap.parse_args()
    if args.per_feature:
        return per_feature_main(args)
    if args.instructions:
        return instructions_main(args)
    repeats = 2 if args.quick else args.repeats
    commit, base_scripts = build_baseline(args.baseline, args.jobs)
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
