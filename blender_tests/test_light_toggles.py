"""A light's Cast Shadow and Multiple Importance toggles (issue 18, Cycles' Light panel), against
Cycles 3.4 rendered in the test: with Cast Shadow off the sphere leaves no shadow on the floor; with
Multiple Importance off only light samples find the lamp, unweighted (the same image in
expectation), and the lamp is no longer seen in the glossy floor's reflection."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(48, 32, 256, max_bounces=4) + """
cam.location = (0.0, -6.0, 3.0)
cam.rotation_euler = (math.radians(62), 0.0, 0.0)
cam.data.lens = 30
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
bpy.ops.mesh.primitive_plane_add(size=12.0)
floor = bpy.context.active_object
floor.data.materials.append(material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.6, 0.6, 1)))
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(0.0, 0.0, 0.8))
bpy.ops.object.shade_smooth()
bpy.context.active_object.data.materials.append(material("Ball", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.4, 0.2, 1)))
bpy.ops.object.light_add(type='AREA', location=(0.0, 0.0, 3.0))
lamp = bpy.context.active_object
lamp.data.energy = 300.0
lamp.data.size = 1.0
"""


def _both(setup):
    images = [img[..., :3] for img in render_both(SCENE + setup)]
    return images, _difference(*images)


def _difference(ours, cycles):
    a, b = (block_mean(img, 4).mean(-1) for img in (ours, cycles))
    return float(np.abs(a - b).mean() / b.mean())


def _ris_difference(setup, cycles):
    """The same scene with RIS direct lighting (its own shadow rays and MIS weights) against Cycles."""
    run = render(setup=SCENE + setup + "scene.smis.direct_light = 'RIS'\n")
    assert run.returncode == 0, run.output[-3000:]
    return _difference(run.image[..., :3], cycles)


def test_cast_shadow_off_matches_cycles():
    (ours, cycles), err = _both("lamp.data.cycles.cast_shadow = False\n")
    (shadowed, _), _ = _both("")
    ris = _ris_difference("lamp.data.cycles.cast_shadow = False\n", cycles)
    print("Cast Shadow off: relative difference to Cycles (4x4 blocks) %.4f, with RIS %.4f" % (err, ris))
    assert err < 0.01 and ris < 0.01, (err, ris)
    # The sphere's shadow on the floor is gone: pixels there are much brighter than with the shadow.
    lit = ours.mean(-1) > 1.5 * shadowed.mean(-1) + 0.01
    assert lit.sum() > 20, lit.sum()


def test_multiple_importance_off_matches_cycles():
    """Light samples alone are unbiased on a diffuse floor; a sharp mirror no longer shows the lamp
    (its Dirac lobe cannot take light samples and BSDF rays no longer see the lamp), in both engines."""
    off = "lamp.data.cycles.use_multiple_importance_sampling = False\n"
    mirror = "floor.data.materials[0] = material('Mirror', 'ShaderNodeBsdfGlossy', Roughness=0.0)\n"
    (_, cycles), err = _both(off)
    ris = _ris_difference(off, cycles)
    print("Multiple Importance off: relative difference to Cycles (4x4 blocks) %.4f, with RIS %.4f" % (err, ris))
    assert err < 0.01 and ris < 0.01, (err, ris)
    (ours, cycles), err_mirror = _both(off + mirror)
    (with_mis, _), _ = _both(mirror)
    print("Multiple Importance off, sharp mirror: relative difference to Cycles %.4f; brightest pixel %.3f "
          "(Cycles %.3f, with MIS %.3f)" % (err_mirror, ours.max(), cycles.max(), with_mis.max()))
    assert err_mirror < 0.01, err_mirror
    assert with_mis.max() > 10.0 * ours.max()
