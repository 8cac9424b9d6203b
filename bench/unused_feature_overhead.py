"""What features cost a scene that does not use them: interleaved best-of-N render times of
scenes/cornell.blend (no passes, no depth of field, no textures) with a baseline build of the add-on
and with this checkout.

    git archive BASE_COMMIT | tar -x -C /tmp/base && (cd /tmp/base && cmake -S . -B build \\
        -DCMAKE_BUILD_TYPE=Release && cmake --build build -j2 --target _smis)
    mkdir -p /tmp/base/.bl_scripts/addons && ln -sfn /tmp/base/addon/smis_render /tmp/base/.bl_scripts/addons/
    /usr/bin/python3 bench/unused_feature_overhead.py /tmp/base/.bl_scripts [ROUNDS]

Times are Blender's frame time up to the engine's "Done" (export + render). Run it with /usr/bin/python3:
Blender started from another interpreter's environment may not find numpy.
"""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLEND = os.path.join(ROOT, "scenes", "cornell.blend")
SETUP = ("import bpy; s = bpy.context.scene; s.smis.samples = {spp}; s.smis.threads = 2; "
         "s.render.resolution_percentage = 100; s.smis.integrator = '{integrator}'")


def frame_seconds(scripts, integrator, spp):
    env = dict(os.environ, BLENDER_USER_SCRIPTS=scripts)
    proc = subprocess.run(["blender", "-b", "--factory-startup", "--addons", "smis_render", BLEND, "--python-expr",
                           SETUP.format(spp=spp, integrator=integrator), "-E", "SMIS", "-F", "OPEN_EXR",
                           "-o", "/tmp/smis_overhead_####", "-f", "1"], capture_output=True, text=True, env=env)
    done = [l for l in (proc.stdout + proc.stderr).splitlines() if "| Done" in l]
    if not done:
        raise RuntimeError("no render with %s:\n%s" % (scripts, (proc.stdout + proc.stderr)[-2000:]))
    m = re.search(r"Time:(\d+):(\d+\.\d+) \| Done", done[-1])
    return 60 * int(m.group(1)) + float(m.group(2))


def main():
    base = sys.argv[1]
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else 5
    variants = {"baseline": base, "this checkout": os.path.join(ROOT, ".bl_scripts")}
    for integrator, spp in (("PATH", 128), ("PSF_SMIS", 16)):
        best = {name: float("inf") for name in variants}
        for _ in range(rounds):
            for name, scripts in variants.items():  # interleaved: both see the same machine load
                best[name] = min(best[name], frame_seconds(scripts, integrator, spp))
        print("%s %d spp: baseline %.3f s, this checkout %.3f s, ratio %.3f"
              % (integrator, spp, best["baseline"], best["this checkout"], best["this checkout"] / best["baseline"]))


if __name__ == "__main__":
    main()
