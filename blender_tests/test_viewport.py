"""The interactive viewport in a real window (Xvfb + Mesa's software OpenGL): Rendered shading with
SMIS draws the render, a move re-syncs without re-exporting meshes, a mesh edit re-exports that one
mesh, material and lamp edits update the engine scene in place, and each edit changes what the 3D
view shows."""
import os
import shutil
import subprocess
import tempfile

import bpy
import numpy as np
import pytest

from conftest import ROOT


def load_png(path):
    img = bpy.data.images.load(path)
    px = np.empty(len(img.pixels), dtype=np.float32)
    img.pixels.foreach_get(px)
    w, h = img.size
    bpy.data.images.remove(img)
    return px.reshape(h, w, 4)[..., :3]


@pytest.mark.skipif(shutil.which("xvfb-run") is None, reason="needs xvfb-run (Debian xvfb, xauth)")
def test_rendered_viewport_updates_after_edits():
    out = tempfile.mkdtemp(prefix="smis_viewport_")
    cmd = ["xvfb-run", "-a", "-s", "-screen 0 1280x800x24", "blender", "--factory-startup", "--addons",
           "smis_render", "--python", os.path.join(ROOT, "blender_tests", "viewport_ui.py"), "--", out]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    log = proc.stdout + proc.stderr
    assert "FAILED" not in log and "Traceback" not in log, log[-3000:]
    syncs = [l for l in log.splitlines() if l.startswith("SMIS viewport: scene sync")]
    print("\n".join(syncs))
    # The first sync exports the cube; moving it exports nothing; editing its mesh exports it again;
    # the material and lamp edits export no mesh; every edit updates the engine scene in place.
    assert len(syncs) == 5, log[-3000:]
    exported = [int(s.split(" meshes exported")[0].rsplit(", ", 1)[1]) for s in syncs]
    assert exported == [1, 0, 1, 0, 0], syncs
    assert ["new engine scene" in syncs[0]] + ["in place" in s for s in syncs[1:]] == [True] * 5, syncs
    solid, before, moved, edited, recolored, relit = (
        load_png(os.path.join(out, n + ".png")) for n in ("solid", "before", "moved", "edited", "recolored", "relit"))
    changed = lambda a, b: np.mean(np.abs(a - b).sum(axis=-1) > 0.1)  # noqa: E731
    # Our render replaced Solid shading (the world background it draws is a lighter grey than
    # Solid's theme colour, so most of the view changes), and each edit changed the view where the
    # cube was and went (about 2% of the view each).
    fractions = (changed(solid, before), changed(before, moved), changed(moved, edited), changed(edited, recolored),
                 changed(recolored, relit))
    print("fraction of the 3D view changed: solid->rendered %.4f, move %.4f, mesh edit %.4f, material %.4f, "
          "lamp %.4f" % fractions)
    assert min(fractions) > 0.005, fractions
    print("screenshots in", out)
    # The material preview icon was rendered, by SMIS: the only SMIS render() call of this session
    # (the viewport draws without one) reports SMIS' counters. (Blender's buffered report output
    # does not keep its order relative to the script's prints.)
    assert "SMIS counters: paths" in log, log[-3000:]
    preview = [l for l in log.splitlines() if "material preview " in l and "mean" in l]
    assert preview and " 0x0 " not in preview[0], log[-3000:]
    assert float(preview[0].split("range ")[1]) > 0.2, preview  # a shaded ball, not a flat icon
    print(preview[0])
