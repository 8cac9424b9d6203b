"""Area light spread (Light > Spread, issue 18) against Cycles 3.4 rendered in the test: a soft box
above a floor confines its light to a cone (Cycles' slatted-grid model, power kept), a rectangle
samples only the part of itself that can reach a point, a disk all of itself. Spread 180 degrees
is the plain Lambertian light; the narrow spreads light the floor very differently from it."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(64, 48, 256, max_bounces=3) + """
cam.location = (0.0, -7.0, 4.0)
cam.rotation_euler = (math.radians(60), 0.0, 0.0)
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
bpy.ops.mesh.primitive_plane_add(size=20.0)
bpy.context.active_object.data.materials.append(material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.6, 0.6, 1)))
bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.8, 0.5, 0.4))
bpy.context.active_object.data.materials.append(material("Box", "ShaderNodeBsdfDiffuse", Color=(0.2, 0.5, 0.8, 1)))
bpy.ops.object.light_add(type='AREA', location=(-0.5, 0.0, 2.0), rotation=(math.radians(20), 0.0, 0.0))
lamp = bpy.context.active_object
lamp.data.energy = 400.0
"""

BOUND = 0.01


def _error(ours, cycles):
    """Mean relative error over 8x8-pixel blocks."""
    a, b = (block_mean(img[..., :3], 8).mean(-1) for img in (ours, cycles))
    return float(np.abs(a - b).mean() / b.mean())


def _check(shape_setup, degrees, what):
    wide_ours, wide_cycles = render_both(SCENE + shape_setup)
    ours, cycles = render_both(SCENE + shape_setup + "lamp.data.spread = math.radians(%g)\n" % degrees)
    err, err_wide = _error(ours, cycles), _error(wide_ours, wide_cycles)
    against_wide = _error(wide_cycles, cycles)
    print("%s: mean relative error against Cycles (8x8 blocks) spread %g: %.4f, 180: %.4f; "
          "Cycles' 180 against its %g: %.4f" % (what, degrees, err, err_wide, degrees, against_wide))
    assert err < BOUND and err_wide < BOUND, (err, err_wide)
    assert against_wide > 10 * BOUND, against_wide  # the spread changes the image: the check has power


def test_rectangle_spread_matches_cycles():
    _check("lamp.data.shape = 'RECTANGLE'\nlamp.data.size, lamp.data.size_y = 2.5, 1.5\n", 30, "rectangle 2.5 x 1.5")


def test_disk_spread_matches_cycles():
    """A disk samples all of itself (as Cycles does): a narrow cone is noisy, so 60 degrees here."""
    _check("lamp.data.shape = 'DISK'\nlamp.data.size = 2.0\n", 60, "disk 2")
