"""Shared helpers for the Blender tests.

Most tests render in a separate `blender -b` process, exactly as a user or a render farm would: a
render that reports an error ends Blender with exit code 1, which must not end the test session.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np  # noqa: F401  (tests import it from here too)

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENES = os.path.join(ROOT, "scenes")
REFERENCES = os.path.join(ROOT, "blender_tests", "references")
from smis_render import _smis  # noqa: E402  (the native module, for reading EXRs; the add-on is enabled)


class RenderRun:
    def __init__(self, proc, image_path):
        self.returncode = proc.returncode
        self.output = proc.stdout + proc.stderr
        self.image_path = image_path

    @property
    def image(self):
        if not os.path.exists(self.image_path):
            raise AssertionError(f"no image written; Blender said:\n{self.output[-3000:]}")
        return _smis.read_exr(self.image_path)


def render(blend=None, setup="", engine="SMIS", frame=1, timeout=600, extra_args=(), frames=None):
    """Render `blend` (or Blender's factory scene) after running the Python `setup` code.

    Returns a RenderRun with Blender's exit code, its output and the written EXR (RGBA, row 0 bottom).
    With frames=(start, end) it renders an animation as a farm does (`-s start -e end -a`) and returns
    one RenderRun per frame."""
    out_dir = tempfile.mkdtemp(prefix="smis_test_")
    script = os.path.join(out_dir, "setup.py")
    with open(script, "w") as f:
        f.write("import bpy\nscene = bpy.context.scene\n")
        f.write("scene.render.image_settings.file_format = 'OPEN_EXR'\n")
        f.write("scene.render.image_settings.color_depth = '32'\n")
        f.write(setup + "\n")
    cmd = ["blender", "-b", "--factory-startup", "--addons", "smis_render"]
    if blend:
        cmd.append(blend)
    cmd += ["--python", script, "-E", engine, "-o", os.path.join(out_dir, "out_####"), *extra_args]
    cmd += ["-f", str(frame)] if frames is None else ["-s", str(frames[0]), "-e", str(frames[1]), "-a"]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if frames is None:
        return RenderRun(proc, os.path.join(out_dir, f"out_{frame:04d}.exr"))
    return [RenderRun(proc, os.path.join(out_dir, f"out_{f:04d}.exr")) for f in range(frames[0], frames[1] + 1)]


def scene_path(name):
    path = os.path.join(SCENES, name)
    assert os.path.exists(path), f"{name} is missing: scripts/test.sh builds it with scenes/build_scenes.py"
    return path


def block_mean(img, k):
    h, w = img.shape[0] // k * k, img.shape[1] // k * k
    return img[:h, :w].reshape(h // k, k, w // k, k, -1).mean(axis=(1, 3))
