"""Film > Transparent (issue 18) against Cycles 3.4 rendered in the same test: the World seen by
camera rays becomes alpha 0 and leaves the colour (premultiplied: nothing is added), yet it still
lights the scene; a cut-out (Principled Alpha) and a coloured Transparent BSDF in front of the sky
give Cycles' fractional alpha, 1 - the mean throughput that reaches the World; the PNG (straight
alpha, written by Blender) agrees too. Passes and the viewport are checked in test_passes.py and
test_viewport.py style: the data passes are unchanged by the setting."""
import os

import bpy
import numpy as np

from conftest import block_mean, render

SCENE = """
import math
for obj in list(bpy.data.objects):
    if obj.type != 'CAMERA':
        bpy.data.objects.remove(obj)
cam = scene.camera
cam.location = (0.0, -6.0, 1.0)
cam.rotation_euler = (math.radians(85), 0.0, 0.0)
cam.data.lens = 30
scene.render.resolution_x, scene.render.resolution_y = 48, 32
scene.render.resolution_percentage = 100
scene.render.film_transparent = True
scene.view_settings.view_transform = 'Standard'
scene.cycles.samples = scene.smis.samples = 256
scene.cycles.pixel_filter_type = scene.smis.filter_type = 'BOX'
scene.cycles.filter_width = scene.smis.filter_width = 1.0
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = scene.smis.max_bounces = 8
scene.cycles.transparent_max_bounces = 64
bg = scene.world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (0.9, 0.6, 0.3, 1.0)
bg.inputs["Strength"].default_value = 1.5

def material(name, build):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    nt.nodes.remove(nt.nodes["Principled BSDF"])
    nt.links.new(build(nt), nt.nodes["Material Output"].inputs["Surface"])
    return m

def diffuse(nt):
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    return d.outputs[0]

def cutout(nt):
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    p.inputs["Base Color"].default_value = (0.2, 0.5, 0.8, 1.0)
    p.inputs["Alpha"].default_value = 0.35
    return p.outputs[0]

def tinted(nt):
    t = nt.nodes.new("ShaderNodeBsdfTransparent")
    t.inputs["Color"].default_value = (0.9, 0.4, 0.1, 1.0)
    return t.outputs[0]

def add(op, mat, **kw):
    op(**kw)
    obj = bpy.context.active_object
    obj.data.materials.append(material(obj.name, mat))

add(bpy.ops.mesh.primitive_uv_sphere_add, diffuse, radius=0.8, location=(-1.2, 0.0, 0.8))
bpy.ops.object.shade_smooth()
add(bpy.ops.mesh.primitive_plane_add, cutout, size=1.6, location=(1.0, -1.0, 1.4), rotation=(math.radians(90), 0, 0))
add(bpy.ops.mesh.primitive_plane_add, tinted, size=1.2, location=(0.6, -2.0, 0.2), rotation=(math.radians(90), 0, 0))
"""


def _both(setup=""):
    images = []
    for engine in ("SMIS", "CYCLES"):
        run = render(setup=SCENE + setup, engine=engine)
        assert run.returncode == 0, run.output[-3000:]
        images.append(run.image)
    return images


def test_film_transparent_alpha_and_colour_match_cycles():
    ours, cycles = _both()
    assert np.isfinite(ours).all()
    a, b = block_mean(ours, 4), block_mean(cycles, 4)
    alpha_err = float(np.abs(a[..., 3] - b[..., 3]).mean())
    colour_err = float(np.abs(a[..., :3] - b[..., :3]).mean() / b[..., :3].mean())
    print("film transparent vs Cycles: mean |alpha difference| %.4f, colour %.4f (4x4 blocks)"
          % (alpha_err, colour_err))
    # The sky is a hole: alpha 0 and no colour, in both.
    sky = cycles[..., 3] < 1e-6
    assert sky.sum() > 200
    assert np.abs(ours[sky]).max() < 1e-6
    # The cut-out (alpha 0.35) and the tinted Transparent BSDF (mean 0.467) give fractional alpha.
    frac = (cycles[..., 3] > 0.2) & (cycles[..., 3] < 0.8)
    assert frac.sum() > 50
    assert abs(float(ours[..., 3][frac].mean() - cycles[..., 3][frac].mean())) < 0.01
    assert alpha_err < 0.01
    assert colour_err < 0.03


def test_film_transparent_png_matches_cycles():
    """Blender writes the PNG with straight alpha from the premultiplied result: the same file from
    both engines (8-bit, within a few levels per block)."""
    png = "\nscene.render.image_settings.file_format = 'PNG'\nscene.render.image_settings.color_mode = 'RGBA'\n"
    pixels = []
    for engine in ("SMIS", "CYCLES"):
        run = render(setup=SCENE + png, engine=engine)
        assert run.returncode == 0, run.output[-3000:]
        path = run.image_path[:-4] + ".png"
        img = bpy.data.images.load(path)
        pixels.append(np.array(img.pixels[:], dtype=np.float32).reshape(img.size[1], img.size[0], 4))
        bpy.data.images.remove(img)
    ours, cycles = pixels
    assert (ours[..., 3] < 1.0 / 255).sum() > 200  # a real hole
    a, b = block_mean(ours, 4), block_mean(cycles, 4)
    assert np.abs(a[..., 3] - b[..., 3]).mean() < 0.01
    opaque = b[..., 3] > 0.1  # straight colour is undefined where nothing covers the pixel
    assert np.abs(a[..., :3] - b[..., :3])[opaque].mean() < 0.03


def test_opaque_film_keeps_the_world_and_alpha_one():
    ours = render(setup=SCENE + "\nscene.render.film_transparent = False\nscene.smis.samples = 16\n").image
    assert (ours[..., 3] == 1.0).all()
    # The World fills the top rows (colour x strength = 1.35, 0.9, 0.45).
    np.testing.assert_allclose(ours[-1, 0, :3], [1.35, 0.9, 0.45], rtol=1e-4)


HOLDOUT = """
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(-0.9, -1.2, 0.9))
bpy.ops.object.shade_smooth()
bpy.context.active_object.is_holdout = True
"""


def test_holdout_object_matches_cycles():
    """A holdout sphere in front of the diffuse sphere: a hole (alpha 0, no colour) where the camera
    sees it, directly or through the cut-out, with the film opaque or transparent; it still shades
    the rest of the scene as an object (a shadow, occlusion of the World's light)."""
    for film in ("True", "False"):
        ours, cycles = _both(HOLDOUT + "scene.render.film_transparent = %s\n" % film)
        a, b = block_mean(ours, 4), block_mean(cycles, 4)
        alpha_err = float(np.abs(a[..., 3] - b[..., 3]).mean())
        colour_err = float(np.abs(a[..., :3] - b[..., :3]).mean() / b[..., :3].mean())
        print("holdout (film transparent %s) vs Cycles: mean |alpha difference| %.4f, colour %.4f (4x4 blocks)"
              % (film, alpha_err, colour_err))
        hole = cycles[..., 3] < 1e-6
        if film == "False":
            assert hole.sum() > 30  # the holdout is a hole, the rest opaque but for its edge pixels
            assert (cycles[..., 3] > 0.999).mean() > 0.9 and (ours[..., 3] > 0.999).mean() > 0.9
        assert np.abs(ours[hole]).max() < 1e-6
        assert alpha_err < 0.01
        assert colour_err < 0.03
