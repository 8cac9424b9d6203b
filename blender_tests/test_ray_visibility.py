"""Object, light and World Ray Visibility, per-type bounce limits, clamping, the caustics toggles and
Filter Glossy (issue 18, Cycles' Object > Visibility, World > Settings and Light Paths panels), against
Cycles 3.4 rendered in the test.

One small scene: a white diffuse floor and back wall, a red diffuse ball, a glossy (GGX 0.2) panel
turned to show the ball, an area lamp and a grey world; some cases add a rough glass ball in front of
the red one, or make the lamp a sharp sun. Each case changes one setting and compares our render with
Cycles' (mean absolute difference over 8x8-pixel blocks and the three channels, relative to Cycles'
mean). Tolerance 1.5%: two renders of the same engine with different seeds differ by 0.7% at 256
samples (1.3% with the glass ball at 256, so those cases take 512), and ours differs from Cycles by as
much (0.7-1.3%), which is noise; both engines are deterministic, so the outcome does not vary from run
to run. Each case also checks that its setting changes Cycles' image by more than 1.4x the tolerance,
so an engine that ignored the setting would fail."""
import bpy  # noqa: F401
import numpy as np
import pytest

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render, render_both

TOLERANCE = 0.015

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(48, 32, 256, max_bounces=6) + """
cam.location = (1.2, -7.0, 1.8)
cam.rotation_euler = (math.radians(84), 0.0, math.radians(8))
cam.data.lens = 30
import mathutils
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
# Cycles' per-type limits follow the one limit, as in our defaults (a case below sets one).
c = scene.cycles
c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = c.transparent_max_bounces = 6
c.caustics_reflective = c.caustics_refractive = True
c.sample_clamp_direct = 0.0
bpy.ops.mesh.primitive_plane_add(size=14.0)
floor = bpy.context.active_object
floor.data.materials.append(material("White", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.8, 0.8, 1)))
bpy.ops.mesh.primitive_plane_add(size=10.0, location=(0.0, 2.0, 2.0), rotation=(math.radians(90), 0.0, 0.0))
bpy.context.active_object.data.materials.append(bpy.data.materials["White"])
# A glossy panel turned so that the camera sees the red ball in it.
bpy.ops.mesh.primitive_plane_add(size=4.0, location=(2.4, 0.0, 1.8))
mirror = bpy.context.active_object
mirror.rotation_euler = mathutils.Vector((-0.75, -0.65, -0.13)).to_track_quat('Z', 'Y').to_euler()
mirror.data.materials.append(material("Mirror", "ShaderNodeBsdfGlossy", Color=(0.9, 0.9, 0.9, 1), Roughness=0.2))
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.9, location=(0.0, 0.0, 0.9))
bpy.ops.object.shade_smooth()
ball = bpy.context.active_object
ball.data.materials.append(material("Red", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.1, 0.05, 1)))
bpy.ops.object.light_add(type='AREA', location=(-1.5, -2.0, 4.0))
lamp = bpy.context.active_object
lamp.data.energy = 600.0
lamp.data.size = 2.0
"""
# A rough glass ball in front of the red one, for the transmission and caustics cases.
GLASS = """
scene.cycles.samples = scene.smis.samples = 512
bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=(0.45, -2.8, 1.1))
bpy.ops.object.shade_smooth()
bpy.context.active_object.data.materials.append(material("Glass", "ShaderNodeBsdfGlass", Roughness=0.3, IOR=1.45))
"""

SUN = """
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.1
lamp.data.type = 'SUN'
lamp.data.energy = 4.0
lamp.data.angle = 0.0
lamp.rotation_euler = (math.radians(30), 0.0, math.radians(-20))
"""

# A world that lights more than the lamp, for the World's glossy and transmission flags.
BRIGHT_WORLD = """
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 4.0
lamp.data.energy = 150.0
"""

CLAMP = """
c.sample_clamp_direct = scene.smis.clamp_direct = 0.3
c.sample_clamp_indirect = scene.smis.clamp_indirect = 0.5
"""

# case -> (scene variant, setup code)
CASES = {
    "ball_camera": ("", "ball.visible_camera = False\n"),
    "ball_shadow": ("", "ball.visible_shadow = False\n"),
    "ball_diffuse": ("", "ball.visible_diffuse = False\n"),
    "ball_glossy": ("", "ball.visible_glossy = False\n"),
    "ball_transmission": (GLASS, "ball.visible_transmission = False\n"),
    "lamp_glossy": ("", "lamp.visible_glossy = False\n"),
    # Without reflective caustics, so that the floor is not lit through the glossy panel alone (noise).
    "lamp_diffuse": ("c.caustics_reflective = scene.smis.caustics_reflective = False\n",
                     "lamp.visible_diffuse = False\n"),
    # Cycles reads these from its own settings; ours from scene.smis (tested by test_light_path_source).
    "diffuse_bounces_1": ("", "c.diffuse_bounces = scene.smis.diffuse_bounces = 1\n"),
    # Under a sharp sun, whose light samples are the same in both engines: a clamped estimate depends
    # on the estimator (an area light sampled differently, or Russian roulette's boost of surviving
    # paths, clamps differently), so only Cycles' estimator itself would match it anywhere else.
    "clamp": (SUN, CLAMP),
    # The same through ReSTIR's resampled direct light and path-space filtering's per-pixel direct
    # light at x1 (with a sun the only light, their light samples are the path tracer's).
    "clamp_restir": (SUN, CLAMP + "scene.smis.direct_light = 'RESTIR'\n"),
    "clamp_psf": (SUN, CLAMP + "scene.smis.integrator = 'PSF_SMIS'\n"),
    "no_caustics": (GLASS, "c.caustics_reflective = scene.smis.caustics_reflective = False\n"
                           "c.caustics_refractive = scene.smis.caustics_refractive = False\n"),
    # One toggle off: the glass keeps the other closure of Cycles' pair (refraction alone with
    # Reflective Caustics off, reflection alone with Refractive off), in RGB and in the spectral
    # tracer (a smooth glass ball: its Dirac events).
    "caustics_reflective_off": (GLASS, "c.caustics_reflective = scene.smis.caustics_reflective = False\n"),
    "caustics_refractive_off": (GLASS, "c.caustics_refractive = scene.smis.caustics_refractive = False\n"),
    "caustics_refractive_off_smooth_spectral": (
        GLASS.replace("Roughness=0.3", "Roughness=0.0"),
        "c.caustics_refractive = scene.smis.caustics_refractive = False\nscene.smis.spectral = 'HERO'\n"),
    # Filter Glossy, read from the scene's Cycles setting (light_path_source): the panel seen after a
    # diffuse bounce is blurred, which spreads the lamp's reflection on the floor and wall.
    "filter_glossy": ("", "c.blur_glossy = 1.0\n"),
    "filter_glossy_spectral": ("", "c.blur_glossy = 1.0\nscene.smis.spectral = 'HERO'\n"),
    # The World's Ray Visibility beyond Camera: rays of the type see no World, and its light samples
    # light no lobe of the class.
    "world_diffuse": ("", "scene.world.cycles_visibility.diffuse = False\n"),
    "world_glossy": (BRIGHT_WORLD, "scene.world.cycles_visibility.glossy = False\n"),
    "world_transmission": (GLASS + BRIGHT_WORLD, "scene.world.cycles_visibility.transmission = False\n"),
}


def _difference(ours, cycles):
    a, b = (block_mean(img[..., :3], 8) for img in (ours, cycles))
    return float(np.abs(a - b).mean() / b.mean())


_reference = {}


def _cycles_default(variant):
    """Cycles' image of the scene variant without the case's setting (rendered once per session)."""
    if variant not in _reference:
        run = render(setup=SCENE + variant, engine="CYCLES")
        assert run.returncode == 0, run.output[-3000:]
        _reference[variant] = run.image
    return _reference[variant]


@pytest.mark.parametrize("case", sorted(CASES))
def test_matches_cycles(case):
    variant, setting = CASES[case]
    ours, cycles = render_both(SCENE + variant + setting)
    err = _difference(ours, cycles)
    effect = _difference(_cycles_default(variant), cycles)
    print("%s: relative difference to Cycles (8x8 blocks) %.4f; the setting changes Cycles' image by %.4f"
          % (case, err, effect))
    assert effect > 1.4 * TOLERANCE, "the case does not show its setting: %.4f" % effect
    assert err < TOLERANCE, err


def test_light_path_source():
    """Our settings win once set; else the scene's Cycles settings where the scene sets them; else
    our unbiased defaults."""
    from smis_render import properties
    scene = bpy.context.scene
    for name in ("diffuse_bounces", "clamp_indirect", "caustics_refractive"):
        scene.smis.property_unset(name)
    scene.cycles.property_unset("diffuse_bounces")
    scene.cycles.property_unset("sample_clamp_indirect")
    d = properties.light_path_settings(scene)
    scene.cycles.property_unset("blur_glossy")
    assert d["diffuse_bounces"] == 1024 and d["clamp_indirect"] == 0.0 and d["caustics_refractive"]
    assert properties.light_path_settings(scene)["filter_glossy"] == 0.0  # Cycles' default is 1.0
    scene.cycles.diffuse_bounces = 2
    scene.cycles.sample_clamp_indirect = 10.0
    scene.cycles.blur_glossy = 0.5
    d = properties.light_path_settings(scene)
    assert d["diffuse_bounces"] == 2 and d["clamp_indirect"] == 10.0 and d["filter_glossy"] == 0.5
    scene.smis.diffuse_bounces = 5
    assert properties.light_path_settings(scene)["diffuse_bounces"] == 5
    for name in ("diffuse_bounces",):
        scene.smis.property_unset(name)
    scene.cycles.property_unset("diffuse_bounces")
    scene.cycles.property_unset("sample_clamp_indirect")
    scene.cycles.property_unset("blur_glossy")
