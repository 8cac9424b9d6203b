"""Rendering behaviour: determinism across thread counts, prompt cancellation, progress."""
import threading
import time

import bpy
import numpy as np

from conftest import _smis, render, scene_path

SETTINGS = """
scene.render.resolution_percentage = 50
scene.smis.samples = 8
scene.smis.seed = {seed}
scene.smis.threads = {threads}
"""


def test_same_seed_same_image_with_one_and_two_threads():
    blend = scene_path("cornell.blend")
    one = render(blend, SETTINGS.format(seed=3, threads=1))
    two = render(blend, SETTINGS.format(seed=3, threads=2))
    other = render(blend, SETTINGS.format(seed=4, threads=2))
    assert one.returncode == 0 and two.returncode == 0, one.output[-2000:] + two.output[-2000:]
    a, b, c = one.image, two.image, other.image
    assert np.isfinite(a).all()
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_cli_thread_flag_is_honoured():
    """`-t 1` (render threads FIXED) is what farms pass; the engine must accept it and render."""
    blend = scene_path("cornell.blend")
    run = render(blend, SETTINGS.format(seed=0, threads=0), extra_args=("-t", "1"))
    assert run.returncode == 0, run.output[-2000:]
    assert np.isfinite(run.image).all()


def open_in_this_process(name, samples, percentage):
    """Opens a scene in the test's own Blender, set to render with SMIS; returns bpy's scene."""
    bpy.ops.wm.open_mainfile(filepath=scene_path(name))
    scene = bpy.context.scene
    scene.render.engine = "SMIS"
    scene.smis.samples = samples
    scene.render.resolution_percentage = percentage
    return scene


def test_cancel_stops_the_render_promptly(monkeypatch):
    """Blender's Esc sets test_break(); the engine must stop its native threads within half a second."""
    scene = open_in_this_process("cornell.blend", samples=100000, percentage=100)
    scene.smis.max_bounces = 64
    import smis_render.engine as eng

    cancel_at = {}

    def test_break(self):
        # Report a cancel one second into rendering; remember when we first said so.
        started = cancel_at.setdefault("start", time.monotonic())
        if time.monotonic() - started > 1.0:
            cancel_at.setdefault("cancel", time.monotonic())
            return True
        return False

    # Blender's RNA test_break() cannot be overridden from Python; the engine polls it through
    # break_requested(), which is what a user's Esc reaches.
    monkeypatch.setattr(eng.SMISRenderEngine, "break_requested", test_break)
    t0 = time.monotonic()
    bpy.ops.render.render()
    done = time.monotonic()
    assert "cancel" in cancel_at, "the engine never polled test_break()"
    # The latency is reported, not asserted (tests do not time things; 4-9 ms measured here against
    # the 0.5 s); the bound below only tells "stopped" from "rendered everything or hung":
    # the full render would take hours.
    latency = done - cancel_at["cancel"]
    print(f"cancel latency: {latency * 1000:.1f} ms")
    assert done - t0 < 60, f"render did not stop ({latency:.1f} s after the cancel)"


def test_region_render_equals_the_crop_of_the_full_render():
    blend = scene_path("cornell.blend")
    base = SETTINGS.format(seed=5, threads=2)
    full = render(blend, base)
    region = render(blend, base + """
scene.render.use_border = True
scene.render.use_crop_to_border = True
scene.render.border_min_x, scene.render.border_max_x = 0.25, 0.75
scene.render.border_min_y, scene.render.border_max_y = 0.5, 1.0
""")
    assert full.returncode == 0 and region.returncode == 0, region.output[-2000:]
    a, b = full.image, region.image
    h, w = a.shape[:2]
    x0, x1, y0, y1 = int(0.25 * w), int(0.75 * w), int(0.5 * h), h
    assert b.shape[:2] == (y1 - y0, x1 - x0)
    assert np.array_equal(a[y0:y1, x0:x1], b)  # row 0 is the bottom row in both


def test_collection_instances_share_one_mesh():
    setup = """
scene.render.resolution_x = scene.render.resolution_y = 32
scene.smis.samples = 2
cube = bpy.data.objects['Cube']
src = bpy.data.collections.new('Src')
for c in list(cube.users_collection):
    c.objects.unlink(cube)
src.objects.link(cube)
for i in range(50):
    inst = bpy.data.objects.new('Inst%d' % i, None)
    inst.instance_type = 'COLLECTION'
    inst.instance_collection = src
    inst.location = ((i % 10) - 5.0, (i // 10) - 2.5, 0.0)
    inst.scale = (0.2, 0.2, 0.2)
    scene.collection.objects.link(inst)
"""
    run = render(setup=setup)
    assert run.returncode == 0, run.output[-2000:]
    done = [l for l in run.output.splitlines() if "Done" in l and "instances" in l][-1]
    assert " 1 meshes" in done and " 50 instances" in done, done


def test_merged_regions_equal_the_full_render():
    """scripts/merge_regions.py: four quadrant renders (two cropped, two full-frame with black
    outside), multilayer with a Depth pass, merge into the full render pixel for pixel."""
    import os
    import subprocess
    from conftest import ROOT, _smis

    blend = scene_path("cornell.blend")
    base = SETTINGS.format(seed=9, threads=2) + """
scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
scene.view_layers[0].use_pass_z = True
"""
    full = render(blend, base)
    assert full.returncode == 0, full.output[-2000:]
    expected = _smis.read_exr_channels(full.image_path)
    h, w = expected["ViewLayer.Combined.R"].shape
    quadrants = [(0.0, 0.5, 0.0, 0.5, True), (0.5, 1.0, 0.0, 0.5, False),
                 (0.0, 0.5, 0.5, 1.0, False), (0.5, 1.0, 0.5, 1.0, True)]
    args = []
    for x0, x1, y0, y1, crop in quadrants:
        run = render(blend, base + f"""
scene.render.use_border = True
scene.render.use_crop_to_border = {crop}
scene.render.border_min_x, scene.render.border_max_x = {x0}, {x1}
scene.render.border_min_y, scene.render.border_max_y = {y0}, {y1}
""")
        assert run.returncode == 0, run.output[-2000:]
        args.append(f"{run.image_path}@{x0},{x1},{y0},{y1}")
    out = os.path.join(os.path.dirname(full.image_path), "merged.exr")
    proc = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "merge_regions.py"),
                           "--resolution", str(w), str(h), "-o", out, *args], capture_output=True, text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "warning" not in proc.stderr, proc.stderr
    merged = _smis.read_exr_channels(out)
    assert sorted(merged) == sorted(expected)
    for name in expected:
        assert np.array_equal(merged[name], expected[name]), name


def test_background_render_writes_only_the_final_image(monkeypatch, tmp_path):
    """Without a UI (blender -b) nobody sees intermediate images and Cycles writes none: the engine
    copies its pixels into the result once. Showing them changes nothing in the final image."""
    import smis_render.engine as eng
    scene = open_in_this_process("cornell.blend", samples=64, percentage=25)
    scene.smis.seed = 7
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    writes = []
    write_pixels = eng.SMISRenderEngine._write_pixels

    def counting(session, combined, exposure=1.0):
        writes.append(session.progress()["samples_done"])
        write_pixels(session, combined, exposure)

    monkeypatch.setattr(eng.SMISRenderEngine, "_write_pixels", staticmethod(counting))
    # An update at every poll, and polls far more often than the render's passes take.
    monkeypatch.setattr(eng, "RESULT_UPDATE_SECONDS", 0.0)
    monkeypatch.setattr(eng, "POLL_SECONDS", 0.0005)

    def render_to(name):
        writes.clear()
        scene.render.filepath = str(tmp_path / name)
        bpy.ops.render.render(write_still=True)
        return _smis.read_exr(str(tmp_path / name) + ".exr"), list(writes)

    assert bpy.app.background
    final, background_writes = render_to("background")
    monkeypatch.setattr(eng, "intermediate_results_shown", lambda: True)
    shown, shown_writes = render_to("shown")
    assert background_writes == [64], background_writes
    assert len(shown_writes) > 1 and shown_writes[-1] == 64, shown_writes
    assert np.array_equal(final, shown)
