"""The Holdout closure (issue 19) against Cycles 3.4 rendered in the same test: where camera rays
meet it, its weight times the path's throughput becomes transparency (alpha goes down, no colour is
added), whatever Film Transparent says; mixed with another closure, that closure still shades with
its share; seen through a transparent surface it still cuts the film; bounce rays see it as black."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(48, 32, 256) + """
cam.location = (0.0, -6.0, 1.0)
cam.rotation_euler = (math.radians(85), 0.0, 0.0)
cam.data.lens = 30
bg = scene.world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (0.9, 0.6, 0.3, 1.0)
bg.inputs["Strength"].default_value = 1.5

def holdout_mix(name, factor, color):
    m = material(name, "ShaderNodeBsdfDiffuse", Color=color)
    nt = m.node_tree
    h = nt.nodes.new("ShaderNodeHoldout")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = factor
    nt.links.new(nt.nodes["Diffuse BSDF"].outputs[0], mix.inputs[1])
    nt.links.new(h.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return m

def add(op, mat, **kw):
    op(**kw)
    bpy.context.active_object.data.materials.append(mat)

# Full holdout, half holdout, and a floor (bounce rays see the holdout spheres as black).
add(bpy.ops.mesh.primitive_uv_sphere_add, holdout_mix("Full", 1.0, (0.8, 0.8, 0.8, 1)), radius=0.7,
    location=(-1.3, 0.0, 0.7))
add(bpy.ops.mesh.primitive_uv_sphere_add, holdout_mix("Half", 0.5, (0.2, 0.7, 0.3, 1)), radius=0.7,
    location=(0.4, 0.0, 0.7))
add(bpy.ops.mesh.primitive_plane_add, material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.6, 0.6, 0.6, 1)),
    size=8.0)
# A coloured Transparent card in front of the half sphere: the holdout is seen through it.
add(bpy.ops.mesh.primitive_plane_add, material("Tinted", "ShaderNodeBsdfTransparent", Color=(0.9, 0.4, 0.1, 1)),
    size=0.8, location=(1.2, -1.5, 0.7), rotation=(math.radians(90), 0, 0))
"""


def _difference(a, b):
    a, b = block_mean(a, 4), block_mean(b, 4)
    return float(np.abs(a - b).mean() / np.abs(b).mean())


def test_holdout_closure_matches_cycles():
    ours, cycles = render_both(SCENE)
    rgb, alpha = _difference(ours[..., :3], cycles[..., :3]), _difference(ours[..., 3:], cycles[..., 3:])
    holes = float((cycles[..., 3] < 0.9).mean())
    print("Holdout closure: colour differs by %.4f, alpha by %.4f (4x4 blocks); Cycles' alpha < 0.9 on %.1f%% "
          "of the image, ours %.1f%%" % (rgb, alpha, 100 * holes, 100 * float((ours[..., 3] < 0.9).mean())))
    assert holes > 0.05  # the scene has holes to compare
    assert rgb < 0.02 and alpha < 0.01, (rgb, alpha)


def test_holdout_closure_in_other_integrators():
    """Path-space filtering, ReSTIR and spectral rendering cut the same holes (alpha against Cycles)."""
    from conftest import render
    _, cycles = render_both(SCENE)
    for setting in ("scene.smis.integrator = 'PSF_SMIS'", "scene.smis.direct_light = 'RESTIR'",
                    "scene.smis.spectral = 'HERO'"):
        run = render(setup=SCENE + setting + "\n")
        assert run.returncode == 0, run.output[-3000:]
        alpha = _difference(run.image[..., 3:], cycles[..., 3:])
        print("%s: alpha differs from Cycles by %.4f" % (setting, alpha))
        assert alpha < 0.01, (setting, alpha)
