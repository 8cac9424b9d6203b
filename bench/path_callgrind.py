"""Instructions of the plain path tracer's render loop per scene, and the image's hash (a refactor must
keep it): callgrind, 240x135, 4 spp, one thread, PATH, box filter 1 px, Cycles' max bounces.

    /usr/bin/python3 bench/path_callgrind.py LABEL cornell textured_plane [lenna principled_coat ...]

SCRIPTS (default: this checkout's .bl_scripts) chooses the add-on, so two builds compare side by side.
Writes bench/results/callgrind_LABEL_SCENE.cg and prints `LABEL SCENE Ir N sha HASH`."""
import hashlib
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from render import remove, render_smis  # noqa: E402
from callgrind import callgrind_wrapper  # noqa: E402

SCENES = {"lenna": "/work/shared/real_scenes/gltf-blender-io/tests/scenes/04_lenna.blend"}


def scene_path(name):
    return SCENES.get(name) or os.path.join(ROOT, "scenes", name + ".blend")


def main():
    label, names = sys.argv[1], sys.argv[2:]
    os.makedirs(os.path.join(HERE, "results"), exist_ok=True)
    for name in names:
        out = os.path.join(HERE, "results", "callgrind_%s_%s.cg" % (label, name))
        run = render_smis(scene_path(name), {"samples": 4, "seed": 0, "integrator": "PATH", "filter_type": "BOX",
                                             "filter_width": 1.0},
                          threads=1, wrapper=callgrind_wrapper(out),
                          addon_scripts=os.environ.get("SCRIPTS", os.path.join(ROOT, ".bl_scripts")),
                          render={"resolution_x": 240, "resolution_y": 135, "resolution_percentage": 100},
                          retries=0, prelude=["scene.smis.max_bounces = scene.cycles.max_bounces"])
        found = re.findall(r"Collected\s*:\s*(\d+)", run.output)
        print(label, name, "Ir", found[-1] if found else None,
              "sha", hashlib.sha1(run.image.tobytes()).hexdigest()[:12], flush=True)
        remove(run)


if __name__ == "__main__":
    main()
