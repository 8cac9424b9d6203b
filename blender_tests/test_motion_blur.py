"""Transform motion blur against Cycles 3.4 rendered in the test (issue 18): a keyframed cube that
moves and turns during the shutter, the shutter opening at the frame (Cycles' Start position) or
centred on it, a rising shutter curve, a camera panning past a still scene, and a sphere deformed by an
animated shape key (deformation motion blur). Without motion blur
(or with a flat shutter) the same frames differ from Cycles' at least twice the bound (the check has
power)."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(64, 48, 128, max_bounces=3) + """
cam.location = (0.0, -8.0, 2.5)
cam.rotation_euler = (math.radians(75), 0.0, 0.0)
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
bpy.ops.mesh.primitive_plane_add(size=30.0)
bpy.context.active_object.data.materials.append(material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1)))
bpy.ops.mesh.primitive_cube_add(size=1.2, location=(-1.5, 0.0, 0.8))
cube = bpy.context.active_object
cube.data.materials.append(material("Cube", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.3, 0.1, 1)))
bpy.ops.object.light_add(type='AREA', location=(1.0, -2.0, 5.0))
bpy.context.active_object.data.energy = 600.0
bpy.context.active_object.data.size = 2.0

def keyframes(obj, frames):
    '''frames: {frame: (location, z rotation in degrees)}, linear in between.'''
    for frame, (location, angle) in frames.items():
        obj.location = location
        obj.rotation_euler.z = math.radians(angle)
        obj.keyframe_insert("location", frame=frame)
        obj.keyframe_insert("rotation_euler", frame=frame)
    for curve in obj.animation_data.action.fcurves:
        for key in curve.keyframe_points:
            key.interpolation = 'LINEAR'

scene.render.use_motion_blur = True
"""

# The issue asks for 2%; both engines converge to 0.1-0.2% of each other here.
BOUND = 0.01

MOVING_CUBE = """
keyframes(cube, {1: ((-1.5, 0.0, 0.8), 0.0), 2: ((1.5, 0.0, 0.8), 60.0)})
"""


def _error(ours, cycles):
    """Mean relative error over 8x8-pixel blocks."""
    a, b = (block_mean(img[..., :3], 8).mean(-1) for img in (ours, cycles))
    return float(np.abs(a - b).mean() / b.mean())


def _compare(setup, what, frame=1):
    ours, cycles = render_both(SCENE + setup, frame=frame)
    still = render(setup=SCENE + setup + "scene.render.use_motion_blur = False\n", frame=frame)
    assert still.returncode == 0, still.output[-3000:]
    err, err_still = _error(ours, cycles), _error(still.image, cycles)
    print("%s: mean relative error against Cycles (8x8 blocks) %.4f; without motion blur %.4f"
          % (what, err, err_still))
    assert err < BOUND, err
    assert err_still > 2 * BOUND, err_still
    return ours


def test_moving_cube_matches_cycles():
    """The shutter opens at the frame and lasts a whole frame: the cube sweeps from x = -1.5 to 1.5
    while turning 60 degrees (three motion steps, the rotation slerped as Cycles does)."""
    _compare(MOVING_CUBE + "scene.render.motion_blur_shutter = 1.0\nscene.cycles.motion_blur_position = 'START'\n",
             "moving cube, shutter 1 from the frame")


def test_shutter_centred_on_the_frame_matches_cycles():
    """Centred on the frame (the default position): the shutter spans frames 1.5-2.5, across the
    last keyframe, where the cube stops (the steps at 1.5 and 2.5 and the frame's, as Cycles takes them)."""
    _compare(MOVING_CUBE + "scene.render.motion_blur_shutter = 1.0\n", "moving cube, shutter 1 centred", frame=2)


def test_camera_motion_matches_cycles():
    """The camera pans 1.5 units sideways over the shutter; everything else stands still."""
    _compare("keyframes(cam, {1: ((-0.75, -8.0, 2.5), 0.0), 2: ((0.75, -8.0, 2.5), 0.0)})\n"
             "scene.render.motion_blur_shutter = 1.0\nscene.cycles.motion_blur_position = 'START'\n",
             "panning camera")


def test_motion_blur_off_per_object_leaves_it_sharp():
    """Object > Motion Blur off (obj.cycles.use_motion_blur) renders the cube at the frame in both."""
    setup = SCENE + MOVING_CUBE + ("scene.render.motion_blur_shutter = 1.0\nscene.cycles.motion_blur_position = 'START'\n"
                                   "cube.cycles.use_motion_blur = False\n")
    ours, cycles = render_both(setup)
    blurred = render(setup=setup.replace("cube.cycles.use_motion_blur = False", ""))
    assert blurred.returncode == 0, blurred.output[-3000:]
    err, err_blurred = _error(ours, cycles), _error(blurred.image, cycles)
    print("cube with its motion blur off: mean relative error against Cycles (8x8 blocks) %.4f; blurred %.4f"
          % (err, err_blurred))
    assert err < BOUND and err_blurred > 2 * BOUND, (err, err_blurred)


def test_shutter_curve_matches_cycles():
    """A rising shutter curve (0 at opening, 1 at closing): later times weigh more, drawn by the
    curve's inverse CDF as Cycles' shutter table does; the flat shutter's image differs from it."""
    shutter = MOVING_CUBE + "scene.render.motion_blur_shutter = 1.0\nscene.cycles.motion_blur_position = 'START'\n"
    curve = ("points = scene.render.motion_blur_shutter_curve.curves[0].points\n"
             "points[0].location = (0.0, 0.0)\npoints[-1].location = (1.0, 1.0)\n"
             "for p in list(points)[1:-1]:\n    points.remove(p)\n"
             "scene.render.motion_blur_shutter_curve.update()\n")
    ours, cycles = render_both(SCENE + shutter + curve)
    flat = render(setup=SCENE + shutter)
    assert flat.returncode == 0, flat.output[-3000:]
    err, err_flat = _error(ours, cycles), _error(flat.image, cycles)
    print("moving cube, rising shutter curve: mean relative error against Cycles (8x8 blocks) %.4f; "
          "with a flat shutter %.4f" % (err, err_flat))
    assert err < BOUND and err_flat > 2 * BOUND, (err, err_flat)


# A smooth-shaded sphere sheared by an animated shape key: its top slides 2 units along x while
# its bottom stays (vertices and their normals move within the mesh; the object does not move).
SHEARED_SPHERE = """
bpy.ops.mesh.primitive_uv_sphere_add(segments=24, ring_count=12, radius=0.8, location=(0.0, 0.0, 0.9))
sphere = bpy.context.active_object
sphere.name = "Sphere"
bpy.ops.object.shade_smooth()
sphere.data.materials.append(material("Sphere", "ShaderNodeBsdfDiffuse", Color=(0.1, 0.3, 0.8, 1)))
sphere.shape_key_add(name="Basis")
shear = sphere.shape_key_add(name="Shear")
for point in shear.data:
    point.co.x += 2.0 * (point.co.z + 0.8) / 1.6
shear.value = 0.0
shear.keyframe_insert("value", frame=1)
shear.value = 1.0
shear.keyframe_insert("value", frame=2)
scene.render.motion_blur_shutter = 1.0
scene.cycles.motion_blur_position = 'START'
"""


def _compare_deformation(setup, what):
    """Ours against Cycles with the deformation blurred, and ours with the sphere's Deformation off
    (its mesh at the frame) against the same Cycles image."""
    ours, cycles = render_both(SCENE + SHEARED_SPHERE + setup)
    sharp = render(setup=SCENE + SHEARED_SPHERE + setup + "sphere.cycles.use_deform_motion = False\n")
    assert sharp.returncode == 0, sharp.output[-3000:]
    assert "Deformation motion blur" not in sharp.output
    err, err_sharp = _error(ours, cycles), _error(sharp.image, cycles)
    print("%s: mean relative error against Cycles (8x8 blocks) %.4f; without deformation blur %.4f"
          % (what, err, err_sharp))
    assert err < BOUND, err
    assert err_sharp > 2 * BOUND, err_sharp


def test_deforming_mesh_matches_cycles():
    """The shape key shears the sphere linearly over a whole-frame shutter (three steps)."""
    _compare_deformation("for curve in sphere.data.shape_keys.animation_data.action.fcurves:\n"
                         "    for key in curve.keyframe_points:\n        key.interpolation = 'LINEAR'\n",
                         "shape-key shear, linear")


def test_deformation_steps_follow_the_objects_steps():
    """An eased (Bezier) shear sampled at the object's five steps (Steps 2), linear between them as
    Cycles interpolates its motion vertices; the object also moves up (deformation inside a motion
    instance)."""
    _compare_deformation("sphere.cycles.motion_steps = 2\n"
                         "keyframes(sphere, {1: ((0.0, 0.0, 0.9), 0.0), 2: ((0.0, 0.0, 1.4), 0.0)})\n",
                         "shape-key shear, eased, five steps, rising")


# An emissive card sweeping 3 units along x and turning 90 degrees, 0.9 above the floor, the only
# light but a dim world: its light samples must be taken where the path's rays see it. Hidden from
# the camera: seen directly, its 12x brighter pixels' time noise would swamp the light it casts.
MOVING_EMITTER = """
bpy.data.objects["Area"].hide_render = True
bpy.ops.mesh.primitive_plane_add(size=0.8, location=(-1.5, 0.0, 0.9))
card = bpy.context.active_object
card.name = "Card"
card.data.materials.append(material("Card", "ShaderNodeEmission", Color=(1.0, 0.8, 0.6, 1), Strength=12.0))
keyframes(card, {1: ((-1.5, 0.0, 0.9), 0.0), 2: ((1.5, 0.0, 0.9), 90.0)})
card.visible_camera = False
cube.location.y = 2.0
scene.cycles.samples = scene.smis.samples = 1024  # the time adds noise: 1.4% apart at 128 samples
scene.render.motion_blur_shutter = 1.0
scene.cycles.motion_blur_position = 'START'
"""


def test_moving_emitter_matches_cycles():
    """The card lights the floor and the cube along its path (next-event samples at the path's time,
    weighted against the rays that hit it then); rendered without motion blur it differs."""
    _compare(MOVING_EMITTER, "moving emissive card")


def test_what_is_not_blurred_is_named():
    """A mesh whose vertex count changes over the shutter renders without its deformation blur,
    named in a warning; the render still succeeds, the moving emissive cube blurred without one."""
    setup = SCENE + MOVING_CUBE + """
scene.render.motion_blur_shutter = 1.0
glow = bpy.data.materials.new("Glow")
glow.use_nodes = True
glow.node_tree.nodes["Principled BSDF"].inputs["Emission"].default_value = (1.0, 1.0, 1.0, 1.0)
glow.node_tree.nodes["Principled BSDF"].inputs["Emission Strength"].default_value = 2.0
cube.data.materials[0] = glow
bpy.ops.mesh.primitive_grid_add(x_subdivisions=8, y_subdivisions=8, size=1.0, location=(0.0, 1.5, 1.5))
sheet = bpy.context.active_object
sheet.name = "Sheet"
build = sheet.modifiers.new("Build", 'BUILD')  # faces (and their vertices) appear over frames 1-3
build.frame_start, build.frame_duration = 1.0, 2.0
sheet.modifiers.new("Wave", 'WAVE')
"""
    run = render(setup=setup)
    assert run.returncode == 0, run.output[-3000:]
    assert run.image[..., :3].mean() > 0.0
    warnings = [line for line in run.output.splitlines() if "motion blur" in line.lower()]
    print("\n".join(warnings))
    assert not any("'Cube'" in w for w in warnings), run.output[-3000:]
    assert any("'Sheet'" in w and "topology changes" in w for w in warnings), run.output[-3000:]
