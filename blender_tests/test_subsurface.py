"""Subsurface scattering (issue 19) against Cycles 3.4 rendered in the same test: a Subsurface
Scattering node (Random Walk) sphere, a Principled Subsurface 1.0 sphere and a thin slab lit from
behind (light through it), under a sun and a grey world. The path tracer walks inside each object
(engine/integrators/subsurface_walk.cpp); the other integrators render it as diffuse, with a warning.
The same scene with Christensen-Burley for the three checks the disk sampling
(engine/integrators/subsurface_disk.cpp)."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(96, 48, 1024) + """
cam.location = (0.0, -4.2, 0.6)
cam.rotation_euler = (math.radians(90), 0.0, 0.0)
cam.data.lens = 35
scene.render.film_transparent = True  # alpha marks the objects' pixels
bg = scene.world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
bg.inputs["Strength"].default_value = 1.0
bpy.ops.object.light_add(type='SUN', rotation=(math.radians(60), 0.0, math.radians(160)))
bpy.context.active_object.data.energy = 3.0
bpy.context.active_object.data.angle = 0.0

def add(op, mat, **kw):
    op(**kw)
    obj = bpy.context.active_object
    obj.data.materials.append(mat)
    bpy.ops.object.shade_smooth()
    return obj

node = material("Node", "ShaderNodeSubsurfaceScattering", Color=(0.8, 0.5, 0.3, 1), Scale=0.25,
                Radius=(1.0, 0.6, 0.3))
node.node_tree.nodes["Subsurface Scattering"].falloff = 'RANDOM_WALK'
add(bpy.ops.mesh.primitive_uv_sphere_add, node, radius=0.6, location=(-1.35, 0.0, 0.6), segments=48, ring_count=24)

principled = bpy.data.materials.new("Principled")
principled.use_nodes = True
p = principled.node_tree.nodes["Principled BSDF"]
p.inputs["Base Color"].default_value = (0.3, 0.6, 0.8, 1)
p.inputs["Subsurface"].default_value = 1.0
p.inputs["Subsurface Color"].default_value = (0.9, 0.6, 0.5, 1)
p.inputs["Subsurface Radius"].default_value = (0.3, 0.15, 0.08)
p.inputs["Roughness"].default_value = 0.4
add(bpy.ops.mesh.primitive_uv_sphere_add, principled, radius=0.6, location=(0.0, 0.0, 0.6), segments=48, ring_count=24)

# A thin slab between the camera and the sun's side: light crosses it.
slab = material("Slab", "ShaderNodeSubsurfaceScattering", Color=(0.9, 0.9, 0.9, 1), Scale=0.1,
                Radius=(1.0, 0.5, 0.25))
obj = add(bpy.ops.mesh.primitive_cube_add, slab, size=1.0, location=(1.35, 0.0, 0.6))
obj.scale = (1.1, 0.03, 1.1)
obj.rotation_euler = (0.0, 0.0, math.radians(20))
bpy.ops.object.shade_flat()
"""

BURLEY_SCENE = SCENE + """
node.node_tree.nodes["Subsurface Scattering"].falloff = 'BURLEY'
slab.node_tree.nodes["Subsurface Scattering"].falloff = 'BURLEY'
p.subsurface_method = 'BURLEY'
"""


def _block_error(ours, cycles):
    """Mean relative error over the 8x8 blocks the objects cover entirely (Cycles' alpha)."""
    a, b = block_mean(ours[..., :3], 8), block_mean(cycles[..., :3], 8)
    covered = block_mean(cycles[..., 3:], 8)[..., 0] > 0.999
    assert covered.sum() >= 2
    return float(np.abs(a - b)[covered].mean() / np.abs(b)[covered].mean())


def _errors(ours, cycles):
    """The whole image's block error and each object's third's."""
    thirds = [_block_error(ours[:, k * 32:(k + 1) * 32], cycles[:, k * 32:(k + 1) * 32]) for k in range(3)]
    return _block_error(ours, cycles), thirds


def test_subsurface_matches_cycles():
    err, thirds = _errors(*render_both(SCENE))
    print("Subsurface: mean relative error %.4f over the objects' 8x8 blocks (node sphere %.4f, principled %.4f, "
          "slab %.4f)" % (err, *thirds))
    assert err < 0.02 and max(thirds) < 0.03, (err, thirds)


def test_christensen_burley_matches_cycles():
    err, thirds = _errors(*render_both(BURLEY_SCENE))
    print("Christensen-Burley: mean relative error %.4f over the objects' 8x8 blocks (node sphere %.4f, "
          "principled %.4f, slab %.4f)" % (err, *thirds))
    # Measured 0.0056 (0.0050, 0.0084, 0.0029). Cycles' bssrdf_burley_setup albedo fit, which 3.4
    # never calls, would give 0.0133 (slab 0.0237).
    assert err < 0.01 and max(thirds) < 0.015, (err, thirds)


def test_subsurface_in_other_integrators():
    """Path-space filtering walks per pixel where it does not filter, and says where it does not walk."""
    run = render(setup=SCENE + "scene.smis.integrator = 'PSF_SMIS'\nscene.smis.samples = 16\n")
    assert run.returncode == 0, run.output[-3000:]
    assert "subsurface scattering is path traced per pixel" in run.output, run.output[-3000:]
    assert np.isfinite(run.image).all()


# Coloured subsurface in spectral rendering (issue 19): a skin-like random-walk sphere (radius
# (1, 0.2, 0.1)) against Cycles, rendered RGB and spectral (SMIS, 4 wavelengths). Spectral rendering
# upsamples the albedo and radius to spectra (a smooth reflectance curve each) and walks per
# wavelength, where RGB (and Cycles) walk per channel, so the two differ legitimately for a coloured
# medium; the test states both errors against Cycles and the spectral image's distance from ours RGB.
SKIN_SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(48, 48, 256) + """
cam.location = (0.0, -3.2, 0.6)
cam.rotation_euler = (math.radians(90), 0.0, 0.0)
cam.data.lens = 50
scene.render.film_transparent = True
bg = scene.world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
bpy.ops.object.light_add(type='SUN', rotation=(math.radians(60), 0.0, math.radians(160)))
bpy.context.active_object.data.energy = 3.0
bpy.context.active_object.data.angle = 0.0
skin = material("Skin", "ShaderNodeSubsurfaceScattering", Color=(0.8, 0.55, 0.45, 1), Scale=0.2,
                Radius=(1.0, 0.2, 0.1))
skin.node_tree.nodes["Subsurface Scattering"].falloff = 'RANDOM_WALK'
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.6, location=(0.0, 0.0, 0.6), segments=48, ring_count=24)
bpy.context.active_object.data.materials.append(skin)
bpy.ops.object.shade_smooth()
"""
# Measured at 512 spp (8x8 blocks the sphere covers): RGB 0.56%, spectral 0.47% against Cycles, spectral
# 0.30% from RGB; the README's spectral section.
SKIN_RGB_MAX, SKIN_SPECTRAL_MAX = 0.015, 0.015


def test_coloured_subsurface_spectral_against_cycles():
    rgb, cycles = render_both(SKIN_SCENE + "scene.smis.spectral = 'RGB'\n")
    run = render(setup=SKIN_SCENE + "scene.smis.spectral = 'SMIS'\nscene.smis.wavelengths = 4\n")
    assert run.returncode == 0, run.output[-3000:]
    spectral = run.image
    assert np.isfinite(spectral).all()
    err_rgb, err_spectral = _block_error(rgb, cycles), _block_error(spectral, cycles)
    err_between = _block_error(spectral, rgb)
    covered = cycles[..., 3] > 0.999
    means = [img[covered][:, :3].mean(axis=0) for img in (cycles, rgb, spectral)]
    print("Coloured subsurface (radius 1, 0.2, 0.1): against Cycles RGB %.4f, spectral %.4f; spectral against "
          "RGB %.4f; mean R, G, B: Cycles %s, RGB %s, spectral %s" % (err_rgb, err_spectral, err_between, *means))
    assert err_rgb < SKIN_RGB_MAX, err_rgb
    assert err_spectral < SKIN_SPECTRAL_MAX, err_spectral
