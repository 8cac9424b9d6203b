"""Render a .blend from plain Python (/usr/bin/python3) by spawning Blender, for the benchmarks.

    from render import render_smis, render_cycles
    r = render_smis("scenes/psf_room.blend", {"samples": 100000, "time_limit": 8.0, "seed": 1,
                                               "integrator": "PATH"})
    r.image      # (h, w, 4) float32 scene-linear RGBA, row 0 = bottom
    r.seconds    # the engine's own render time (Blender start-up and scene loading excluded)

SMIS: `blender -b --factory-startup --addons smis_render SCENE -E SMIS -o DIR/out_#### -F OPEN_EXR
--python-expr "<settings>" -f 1`. The settings dict is applied to `scene.smis` (any property:
samples, seed, integrator, time_limit, max_bounces, filter_type, filter_width, psf_radius_px, ...);
a property or enum value the add-on does not have makes Blender exit 1 before rendering (it is never
silently ignored) and raises RenderError. The time is parsed from our engine's final stats line,
`... | Done · 64/64 samples · 1.93 s · export 0.01 s · ...`: render seconds (printed with 0.01 s
resolution), samples done/total. Export time is reported separately (`export_seconds`).

Cycles (peer curves): the scene gets Cycles' unbiased settings (scenes/cycles_settings.py), the given
samples/seed/time_limit, and the time is Blender's final `Time: MM:SS.ss (Saving: ...)` line minus
the saving time (this includes Cycles' scene sync and BVH build, as our export+BVH is not in ours).

Both write a 32-bit float EXR (`r.path`, kept until the temporary folder is removed by the caller
or the OS; pass keep_dir=None for an automatic temporary folder).

If the native module is being rebuilt while Blender starts (the .so is truncated for a moment),
the add-on fails to load (or Blender dies from a signal); such a render is retried a few times,
20 s apart, before giving up.
"""
import json
import os
import re
import shutil
import subprocess
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLENDER = os.environ.get("BLENDER", "blender")

_SMIS_STATS = re.compile(
    r"(Done|Cancelled)\s*\u00b7\s*(\d+)/(\d+) samples\s*\u00b7\s*([0-9.]+) s"
    r"(?:\s*\u00b7\s*export ([0-9.]+) s)?")
_INTEGRATOR_STATS = re.compile(r"SMIS integrator: (.*)")
_BLENDER_TIME = re.compile(r"^\s*Time: ([0-9:.]+)(?: \(Saving: ([0-9:.]+)\))?", re.M)
_LOAD_FAILURE = re.compile(r"could not be loaded|file too short|undefined symbol|engine not found",
                           re.I)


class RenderError(RuntimeError):
    def __init__(self, message, output=""):
        super().__init__(message)
        self.output = output


class RenderRun:
    """One finished render: image, times and Blender's output."""

    def __init__(self, engine, path, seconds, wall_seconds, output, samples_done=None,
                 samples_total=None, export_seconds=None, cancelled=False, settings=None):
        self.engine = engine
        self.path = path
        self.seconds = seconds
        self.wall_seconds = wall_seconds
        self.output = output
        self.samples_done = samples_done
        self.samples_total = samples_total
        self.export_seconds = export_seconds
        self.cancelled = cancelled
        self.settings = dict(settings or {})
        self._image = None

    @property
    def image(self):
        if self._image is None:
            from metrics import load_exr
            self._image = load_exr(self.path)
        return self._image

    def summary(self):
        return {"engine": self.engine, "seconds": self.seconds, "wall_seconds": self.wall_seconds,
                "samples_done": self.samples_done, "samples_total": self.samples_total,
                "export_seconds": self.export_seconds, "settings": self.settings}


def parse_timecode(text):
    """'01:02.50' -> 62.5, '1:00:02.50' -> 3602.5 (Blender's time codes)."""
    seconds = 0.0
    for part in text.strip().split(":"):
        seconds = seconds * 60.0 + float(part)
    return seconds


def parse_smis_stats(output):
    """(done_or_cancelled, samples_done, samples_total, seconds, export_seconds) of the last
    stats line of our engine in Blender's output, or None."""
    found = _SMIS_STATS.findall(output)
    if not found:
        return None
    state, done, total, secs, export = found[-1]
    return state, int(done), int(total), float(secs), (float(export) if export else None)


def integrator_stats(output):
    """The engine's per-integrator measurements (its `SMIS integrator: key value, ...` line) as a
    dict, keys with underscores."""
    found = _INTEGRATOR_STATS.findall(output)
    if not found:
        return {}
    out = {}
    for item in found[-1].split(", "):
        key, _, value = item.rpartition(" ")
        out[key.replace(" ", "_")] = float(value)
    return out


def parse_blender_time(output):
    """Render time from Blender's final 'Time: 00:05.42 (Saving: 00:00.01)' line, saving excluded."""
    found = _BLENDER_TIME.findall(output)
    if not found:
        return None
    total, saving = found[-1]
    return parse_timecode(total) - (parse_timecode(saving) if saving else 0.0)


def parse_value(text):
    """A --set value from the command line: int, float, bool, or the string itself."""
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    if text in ("True", "False"):
        return text == "True"
    return text


def _py_literal(value):
    return repr(value)  # str, int, float, bool: valid Python


def _settings_code(prop_group, settings):
    lines = []
    for key, value in settings.items():
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", key):
            raise ValueError("bad setting name %r" % key)
        # a Blender property of that name, or an error: an engine-only key (e.g. camera_volume_only) or a
        # misspelt one would otherwise be set as a plain attribute and change nothing
        lines.append("assert %r in %s.bl_rna.properties, 'no setting %s on %s'" % (key, prop_group, key, prop_group))
        lines.append("setattr(%s, %r, %s)" % (prop_group, key, _py_literal(value)))
        # read back: a float property rounds, an enum must be what we asked for
        if isinstance(value, str):
            lines.append("assert getattr(%s, %r) == %r, 'setting %s not applied'"
                         % (prop_group, key, value, key))
    return lines


def _run(cmd, out_dir, frame, timeout, retries, check=None, env=None):
    output = ""
    path = os.path.join(out_dir, "out_%04d.exr" % frame)
    for attempt in range(retries + 1):
        if os.path.exists(path):
            os.remove(path)
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, encoding="utf-8", errors="replace",
                              timeout=timeout, env=env)
        wall = time.perf_counter() - t0
        output = proc.stdout + proc.stderr
        if proc.returncode == 0 and os.path.exists(path) and (check is None or check(output)):
            return path, wall, output
        if attempt < retries and (_LOAD_FAILURE.search(output) or proc.returncode < 0):
            # the engine is probably being rebuilt (module missing, truncated, or replaced under
            # a running Blender, which can kill it): wait and try again
            time.sleep(20.0)
            continue
        break
    state = "written" if os.path.exists(path) else "missing"
    raise RenderError("Blender exit code %d (image %s: %s)\n%s"
                      % (proc.returncode, path, state, output[-3000:]), output)


def _command(blend, engine, out_dir, code_lines, threads, frame, addons=True):
    script = os.path.join(out_dir, "settings.py")
    with open(script, "w") as f:
        f.write("\n".join(code_lines) + "\n")
    cmd = [BLENDER, "-b", "--factory-startup"]
    if addons:
        cmd += ["--addons", "smis_render"]
    cmd += [os.path.abspath(blend), "-E", engine, "-o", os.path.join(out_dir, "out_####"),
            "-F", "OPEN_EXR"]
    if threads:
        cmd += ["-t", str(int(threads))]
    # --python-exit-code before --python: an exception in the settings script ends Blender with 1
    # instead of rendering with the wrong settings. Arguments run left to right: settings before -f.
    cmd += ["--python-exit-code", "1", "--python", script, "-f", str(frame)]
    return cmd


_HEADER = ["import bpy", "scene = bpy.context.scene",
           "scene.render.image_settings.file_format = 'OPEN_EXR'",
           "scene.render.image_settings.color_depth = '32'",
           "scene.render.use_compositing = False", "scene.render.use_sequencer = False"]


def render_smis(blend, settings=None, out_dir=None, threads=0, timeout=3600, frame=1, retries=3,
                addon_scripts=None, wrapper=None, render=None, prelude=()):
    """Render `blend` with our engine; `settings` are applied to scene.smis and `render` (e.g.
    resolution_x) to scene.render. Returns a RenderRun.

    `addon_scripts`: a Blender user-scripts folder whose addons/smis_render is the add-on to use
    (another build of the engine, for side-by-side comparisons); default: the installed one.
    `wrapper`: a command Blender runs under (e.g. valgrind and its options)."""
    settings = dict(settings or {})
    out_dir = out_dir or tempfile.mkdtemp(prefix="smis_bench_")
    os.makedirs(out_dir, exist_ok=True)
    code = (_HEADER + list(prelude) + _settings_code("scene.render", render or {})
            + _settings_code("scene.smis", settings))
    cmd = list(wrapper or []) + _command(blend, "SMIS", out_dir, code, threads, frame)
    env = dict(os.environ, BLENDER_USER_SCRIPTS=addon_scripts) if addon_scripts else None
    path, wall, output = _run(cmd, out_dir, frame, timeout, retries,
                              check=lambda out: parse_smis_stats(out) is not None, env=env)
    stats = parse_smis_stats(output)
    if stats is None:
        raise RenderError("no SMIS stats line ('Done · N/M samples · T s') in Blender's output\n"
                          + output[-3000:], output)
    state, done, total, secs, export = stats
    return RenderRun("SMIS", path, secs, wall, output, done, total, export, state == "Cancelled",
                     settings)


def render_cycles(blend, samples, seed=0, time_limit=0.0, max_bounces=None, out_dir=None, threads=0,
                  timeout=3600, frame=1, extra=None, prelude=()):
    """Render `blend` with Cycles, unbiased settings, BOX 1 px filter. Returns a RenderRun.
    `prelude`: Python lines run on the scene first (bpy and scene are defined)."""
    out_dir = out_dir or tempfile.mkdtemp(prefix="cycles_bench_")
    os.makedirs(out_dir, exist_ok=True)
    code = _HEADER + list(prelude) + [
        "import sys", "sys.path.insert(0, %r)" % os.path.join(ROOT, "scenes"),
        "from cycles_settings import make_cycles_unbiased",
        "make_cycles_unbiased(scene, max_bounces=%r)" % max_bounces,
        "scene.cycles.samples = %d" % int(samples),
        "scene.cycles.seed = %d" % int(seed),
        "scene.cycles.time_limit = %r" % float(time_limit),
    ] + _settings_code("scene.cycles", extra or {})
    cmd = _command(blend, "CYCLES", out_dir, code, threads, frame, addons=False)
    path, wall, output = _run(cmd, out_dir, frame, timeout, retries=0)
    secs = parse_blender_time(output)
    if secs is None:
        raise RenderError("no 'Time:' line in Blender's output\n" + output[-3000:], output)
    settings = {"samples": samples, "seed": seed, "time_limit": time_limit, "max_bounces": max_bounces}
    settings.update(extra or {})
    return RenderRun("CYCLES", path, secs, wall, output, settings=settings)


def remove(run):
    """Delete a run's temporary folder (after its image has been read)."""
    shutil.rmtree(os.path.dirname(run.path), ignore_errors=True)


if __name__ == "__main__":
    import argparse
    import sys
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description="Render a scene with SMIS (or Cycles) and print the time.")
    ap.add_argument("blend")
    ap.add_argument("--engine", default="SMIS", choices=["SMIS", "CYCLES"])
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="scene.smis setting (SMIS only), e.g. --set samples=64 --set integrator=PATH")
    ap.add_argument("--samples", type=int, default=64, help="Cycles samples")
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--out", default=None)
    a = ap.parse_args()

    if a.engine == "SMIS":
        kv = dict(s.split("=", 1) for s in a.set)
        run = render_smis(a.blend, {k: parse_value(v) for k, v in kv.items()}, a.out, a.threads)
    else:
        run = render_cycles(a.blend, a.samples, out_dir=a.out, threads=a.threads)
    print(json.dumps(dict(run.summary(), path=run.path)))
