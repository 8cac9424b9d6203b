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


def matched_settings(width, height, samples, max_bounces=8):
    """Setup code under which SMIS and Cycles render the same estimand: the given size, samples and
    bounce limit, Standard view, a 1-px BOX filter, and none of Cycles' biased shortcuts (denoising,
    adaptive sampling, indirect clamping, filter glossy)."""
    return f"""
scene.render.resolution_x, scene.render.resolution_y = {width}, {height}
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = 'Standard'
scene.cycles.samples = scene.smis.samples = {samples}
scene.cycles.pixel_filter_type = scene.smis.filter_type = 'BOX'
scene.cycles.filter_width = scene.smis.filter_width = 1.0
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = scene.smis.max_bounces = {max_bounces}
scene.cycles.sample_clamp_indirect = 0.0
scene.cycles.blur_glossy = 0.0
"""


# Setup code: remove every object but the camera, and `material(name, node type, **inputs)`: a
# material whose Surface is one shader node with those inputs (GGX for Glossy and Glass).
EMPTY_SCENE_AND_MATERIALS = """
import math
for obj in list(bpy.data.objects):
    if obj.type != 'CAMERA':
        bpy.data.objects.remove(obj)
cam = scene.camera

def material(name, kind, **inputs):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    b = nt.nodes.new(kind)
    for k, v in inputs.items():
        b.inputs[k].default_value = v
    if kind in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfGlass"):
        b.distribution = 'GGX'
    nt.links.new(b.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return m
"""


def render_both(setup, timeout=600, frame=1):
    """The same setup rendered by SMIS and by Cycles: their RGBA images (row 0 bottom)."""
    images = []
    for engine in ("SMIS", "CYCLES"):
        run = render(setup=setup, engine=engine, timeout=timeout, frame=frame)
        assert run.returncode == 0, run.output[-3000:]
        images.append(run.image)
    return images
