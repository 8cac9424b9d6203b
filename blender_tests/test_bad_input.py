"""Bad input gives a clear message and a valid image (or a clean failure), never a crash or NaN."""
import numpy as np

from conftest import render

SMALL = """
scene.render.resolution_x = 32
scene.render.resolution_y = 24
scene.render.resolution_percentage = 100
scene.smis.samples = 4
"""


def assert_clean_image(run, shape=(24, 32, 4)):
    assert run.returncode == 0, run.output[-3000:]
    img = run.image
    assert img.shape == shape
    assert np.isfinite(img).all()
    return img


def test_scene_without_camera_fails_cleanly():
    run = render(setup=SMALL + "bpy.data.objects.remove(bpy.data.objects['Camera'])\n")
    assert run.returncode == 1, run.output[-3000:]   # an error, reported: a farm sees the failure
    assert "no camera" in run.output.lower()
    assert "Segmentation fault" not in run.output


def test_empty_scene_renders_black_with_a_warning():
    setup = SMALL + """
for ob in list(bpy.data.objects):
    if ob.type != 'CAMERA':
        bpy.data.objects.remove(ob)
scene.world.node_tree.nodes['Background'].inputs['Color'].default_value = (0, 0, 0, 1)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    assert np.all(img[..., :3] == 0.0)
    assert "empty" in run.output.lower()


def test_nan_vertices_are_dropped_and_counted():
    setup = SMALL + """
cube = bpy.data.objects['Cube']
cube.data.vertices[0].co = (float('nan'), 0.0, 0.0)
"""
    run = render(setup=setup)
    assert_clean_image(run)
    assert "dropped" in run.output.lower()


def test_zero_size_and_negative_power_lights_are_skipped_with_a_warning():
    setup = SMALL + """
light = bpy.data.objects['Light']
light.data.energy = -100.0
area = bpy.data.lights.new('Flat', 'AREA')
area.size = 0.0
area.energy = 50.0
ob = bpy.data.objects.new('Flat', area)
scene.collection.objects.link(ob)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    out = run.output
    assert "Light" in out and "negative" in out.lower()
    assert "Flat" in out and "size" in out.lower()
    # Only the world lights the scene now; the image is still valid.
    assert img[..., :3].max() >= 0.0


def test_unsupported_node_falls_back_with_one_warning_naming_it():
    setup = SMALL + """
mat = bpy.data.materials.new('Noisy')
mat.use_nodes = True
nt = mat.node_tree
bsdf = nt.nodes['Principled BSDF']
toon = nt.nodes.new('ShaderNodeBsdfToon')
nt.links.new(toon.outputs[0], nt.nodes['Material Output'].inputs['Surface'])
bpy.data.objects['Cube'].data.materials.clear()
bpy.data.objects['Cube'].data.materials.append(mat)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    lines = [l for l in run.output.splitlines() if "Noisy" in l and "Toon" in l]
    assert len(lines) == 1, run.output[-3000:]
    assert img[..., :3].max() > 0.0  # the fallback diffuse is lit
