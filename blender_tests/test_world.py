"""The World through the shader evaluator (issue 18): an HDRI through a Mapping node lights a scene as
Cycles does (against a committed Cycles reference), the export of node Worlds (program, images,
Cycles' importance map resolution), warnings for what is not evaluated, Cycles' magenta for a missing
image, the camera-only backplate (Light Path), and a world edit in a viewport scene in place."""
import json
import os

import bpy
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, REFERENCES, ROOT, _smis, block_mean, matched_settings, render, render_both
from smis_render.sync import world as sync_world

SPP = int(os.environ.get("SMIS_WORLD_SPP", "1024"))
BUILD = f"exec(open({os.path.join(ROOT, 'scenes', 'world_hdri.py')!r}).read())\nbuild(scene)\n"
HDRI = "/usr/share/blender/datafiles/studiolights/world/sunset.exr"


def test_hdri_world_matches_cycles():
    """scenes/world_hdri.py (a diffuse and a glossy sphere on a floor, lit only by sunset.exr turned by
    a Mapping node) against Cycles 3.4 (scenes/make_world_reference.sh, 2 x 4096 spp): mean relative
    error over 8x8 blocks within 1%."""
    ref = _smis.read_exr(os.path.join(REFERENCES, "world_hdri.exr"))[..., :3]
    setup = BUILD + f"""
scene.smis.samples = {SPP}
scene.smis.seed = 1
scene.smis.max_bounces = 8
scene.smis.filter_type = 'BOX'
scene.smis.filter_width = 1.0
"""
    run = render(setup=setup, timeout=1800)
    assert run.returncode == 0, run.output[-3000:]
    ours = run.image[..., :3]
    assert ours.shape == ref.shape
    assert np.isfinite(ours).all()
    a, b = block_mean(ours, 8).mean(-1), block_mean(ref, 8).mean(-1)
    mask = b > 0.01 * b.mean()
    rel = (a - b)[mask] / b[mask]
    # The environment seen by camera rays (the top rows: sky, no geometry) is not noisy at all.
    sky = np.abs(ours[-4:] - ref[-4:]).mean() / ref[-4:].mean()
    report = {"spp": SPP, "blocks": int(mask.sum()), "mean_relative_error": float(np.abs(rel).mean()),
              "mean_signed_error": float(rel.mean()), "worst_block": float(np.abs(rel).max()),
              "sky_rows_error": float(sky)}
    print(json.dumps(report))
    assert report["mean_relative_error"] <= 0.01, report
    assert abs(report["mean_signed_error"]) < 0.003, report
    assert report["sky_rows_error"] < 0.01, report


def _hdri_world(rotation_z=0.0):
    w = bpy.data.worlds.new("HDRI")
    w.use_nodes = True
    nt = w.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(HDRI, check_existing=True)
    coords, mapping = nt.nodes.new("ShaderNodeTexCoord"), nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, rotation_z)
    nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    return w


def test_node_world_exports_a_program_with_its_image_and_cycles_map_resolution():
    warnings = []
    w = _hdri_world()
    desc = sync_world.export_world(w, warnings.append)
    assert warnings == []
    ops = [op[0] for op in desc["program"]["ops"]]
    assert {"texcoord", "mapping", "tex_environment", "background"} <= set(ops), ops
    assert len(desc["images"]) == 1 and desc["images"][0]["rgba"].shape == (512, 1024, 4)
    # Cycles' automatic resolution: at least 4096 x 2048 without a Nishita sun.
    assert desc["map_resolution"] == (4096, 2048)
    w.cycles.sampling_method = 'MANUAL'
    w.cycles.sample_map_resolution = 512
    assert sync_world.export_world(w, warnings.append)["map_resolution"] == (512, 256)
    # A plain Background still compiles (the engine folds it to the uniform light); no nodes: the colour.
    plain = bpy.data.worlds.new("Plain")
    plain.use_nodes = True
    assert "program" in sync_world.export_world(plain, warnings.append)
    plain.use_nodes = False
    plain.color = (0.1, 0.2, 0.3)
    d = sync_world.export_world(plain, warnings.append)
    assert "program" not in d and tuple(d["color"]) == tuple(np.float32([0.1, 0.2, 0.3]))


def test_world_nodes_without_meaning_warn():
    warnings = []
    w = bpy.data.worlds.new("Sky")
    w.use_nodes = True
    nt = w.node_tree
    sky = nt.nodes.new("ShaderNodeTexSky")
    nt.links.new(sky.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    for sky_type in ("NISHITA", "HOSEK_WILKIE", "PREETHAM"):  # every sky type is evaluated
        sky.sky_type = sky_type
        sync_world.export_world(w, warnings.append)
        assert warnings == []
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(bsdf.outputs[0], nt.nodes["World Output"].inputs["Surface"])
    sync_world.export_world(w, warnings.append)
    assert any("not a World shader" in m for m in warnings), warnings


BACKGROUND_ONLY = """
for obj in list(bpy.data.objects):
    if obj.type != 'CAMERA':
        bpy.data.objects.remove(obj)
scene.render.resolution_x = scene.render.resolution_y = 16
scene.smis.samples = 4
nt = scene.world.node_tree
bg = nt.nodes["Background"]
"""


def test_missing_environment_image_renders_magenta():
    run = render(setup=BACKGROUND_ONLY + """
env = nt.nodes.new("ShaderNodeTexEnvironment")
nt.links.new(env.outputs["Color"], bg.inputs["Color"])
bg.inputs["Strength"].default_value = 2.0
""")
    assert run.returncode == 0, run.output[-3000:]
    np.testing.assert_allclose(run.image[..., :3], np.broadcast_to([2.0, 0.0, 2.0], (16, 16, 3)), atol=1e-6)


def test_backplate_is_seen_by_camera_rays_only():
    """Mix(Is Camera Ray, lighting, plate): the sky shows the plate, a white sphere the lighting."""
    run = render(setup=BACKGROUND_ONLY + """
bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0.0, 0.0, 0.0))
bpy.ops.object.shade_smooth()
mat = bpy.data.materials.new("White")
mat.use_nodes = True
mnt = mat.node_tree
mnt.nodes.remove(mnt.nodes["Principled BSDF"])
white = mnt.nodes.new("ShaderNodeBsdfDiffuse")
white.inputs["Color"].default_value = (1, 1, 1, 1)
mnt.links.new(white.outputs[0], mnt.nodes["Material Output"].inputs["Surface"])
bpy.context.active_object.data.materials.append(mat)
cam = scene.camera
cam.location = (0.0, 0.0, 6.0)
cam.rotation_euler = (0.0, 0.0, 0.0)
cam.data.lens = 50.0
scene.smis.samples = 64
scene.smis.filter_type = 'BOX'
scene.smis.filter_width = 1.0
lp = nt.nodes.new("ShaderNodeLightPath")
mix = nt.nodes.new("ShaderNodeMixRGB")
mix.inputs[1].default_value = (0.25, 0.5, 0.125, 1.0)
mix.inputs[2].default_value = (4.0, 0.0, 2.0, 1.0)
nt.links.new(lp.outputs["Is Camera Ray"], mix.inputs[0])
nt.links.new(mix.outputs[0], bg.inputs["Color"])
bg.inputs["Strength"].default_value = 1.0
""")
    assert run.returncode == 0, run.output[-3000:]
    img = run.image[..., :3]
    for corner in (img[0, 0], img[0, -1], img[-1, 0], img[-1, -1]):
        np.testing.assert_allclose(corner, [4.0, 0.0, 2.0], atol=1e-6)
    centre = img[6:10, 6:10].reshape(-1, 3).mean(axis=0)
    # A white diffuse sphere under a uniform World reflects the World: the lighting colour.
    np.testing.assert_allclose(centre, [0.25, 0.5, 0.125], rtol=0.05)


def test_world_edit_updates_a_viewport_scene_in_place():
    """Rotating the environment's Mapping: replace_lights takes the new World without a new scene."""
    scene = _smis.Scene()
    scene.set_fast_build(True)
    scene.set_camera({"matrix": np.eye(4), "width": 8, "height": 8, "lens": 20.0})
    scene.set_world(sync_world.export_world(_hdri_world(0.0), print))
    scene.commit()

    def pixels():
        session = _smis.RenderSession(scene, {"samples": 2, "seed": 1})
        session.run()
        return np.asarray(session.pixels())[..., :3].copy()

    before = pixels()
    assert scene.replace_lights([], sync_world.export_world(_hdri_world(1.5), print))
    after = pixels()
    assert np.isfinite(after).all() and after.mean() > 0.0
    assert np.abs(after - before).mean() > 0.05 * before.mean()


# The World seen directly by a perspective camera (no objects), rendered by both engines.
SKY_VIEW = """
import math, mathutils
for obj in list(bpy.data.objects):
    if obj.type != 'CAMERA':
        bpy.data.objects.remove(obj)
cam = scene.camera
cam.location = (0.3, -0.2, 0.5)
cam.rotation_euler = (math.radians(70), math.radians(10), math.radians(30))
cam.data.lens = 18
bpy.context.view_layer.update()
scene.render.resolution_x, scene.render.resolution_y = 48, 32
scene.view_settings.view_transform = 'Standard'
scene.cycles.samples = scene.smis.samples = 128
scene.cycles.pixel_filter_type = scene.smis.filter_type = 'BOX'
scene.cycles.filter_width = scene.smis.filter_width = 1.0
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
nt = scene.world.node_tree
bg = nt.nodes["Background"]
"""


def _both_engines(setup):
    images = []
    for engine in ("SMIS", "CYCLES"):
        run = render(setup=SKY_VIEW + setup, engine=engine)
        assert run.returncode == 0, run.output[-3000:]
        images.append(run.image[..., :3])
    a, b = (block_mean(img, 4) for img in images)
    return float(np.abs(a - b).mean() / b.mean())


def test_environment_projections_match_cycles():
    """Equirectangular through a Mapping node, and mirror ball, as Cycles maps them."""
    for projection in ("EQUIRECTANGULAR", "MIRROR_BALL"):
        err = _both_engines(f"""
env = nt.nodes.new("ShaderNodeTexEnvironment")
env.image = bpy.data.images.load({HDRI!r})
env.projection = '{projection}'
coords, mapping = nt.nodes.new("ShaderNodeTexCoord"), nt.nodes.new("ShaderNodeMapping")
mapping.inputs["Rotation"].default_value = (0.4, -0.3, 1.2)
nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
nt.links.new(env.outputs["Color"], bg.inputs["Color"])
bg.inputs["Strength"].default_value = 1.7
""")
        print(projection, "relative difference to Cycles (4x4 blocks): %.5f" % err)
        assert err < 0.01, (projection, err)


def test_preetham_sky_matches_cycles():
    err = _both_engines("""
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'PREETHAM'
fwd = cam.matrix_world.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))
sky.sun_direction = (fwd + mathutils.Vector((0.15, -0.1, 0.05))).normalized()
sky.turbidity = 3.0
nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
""")
    print("Preetham sky: relative difference to Cycles (4x4 blocks): %.5f" % err)
    assert err < 0.002, err


def _sun_towards_view(offset_elevation=0.0, offset_azimuth=0.0):
    """Nishita sun elevation and rotation (Blender's node values) that put the sun near the middle of
    SKY_VIEW's camera (Cycles: sun direction = (elevation, 2 pi - rotation + pi / 2) in latitude and
    longitude)."""
    return f"""
cam.rotation_euler = (math.radians(100), 0.0, math.radians(30))  # 10 degrees up: sky, horizon, ground
bpy.context.view_layer.update()
fwd = cam.matrix_world.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))
sky.sun_elevation = math.asin(fwd.z) + {offset_elevation}
sky.sun_rotation = (math.pi / 2 - math.atan2(fwd.y, fwd.x) + {offset_azimuth}) % (2 * math.pi)
"""


def test_nishita_sky_matches_cycles():
    """Blender 3.4's default sky seen by the camera: the sky and a widened sun disc (5 degrees, so the
    disc covers pixels) with limb darkening, at a non-default altitude, air, dust and ozone."""
    err = _both_engines("""
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'NISHITA'
sky.sun_size = math.radians(5.0)
sky.sun_intensity = 0.02
sky.altitude = 1500.0
sky.air_density, sky.dust_density, sky.ozone_density = 1.3, 2.0, 0.7
nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
""" + _sun_towards_view(-0.1, 0.15))
    print("Nishita sky: relative difference to Cycles (4x4 blocks): %.5f" % err)
    assert err < 0.005, err


def test_nishita_sky_without_disc_and_below_horizon_matches_cycles():
    for setup in ("sky.sun_disc = False\nsky.sun_elevation = 0.05\n",
                  "sky.sun_elevation = -0.03\nsky.sun_size = 0.2\n"):
        err = _both_engines("""
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'NISHITA'
sky.sun_rotation = 4.0
nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
""" + setup)
        print("Nishita sky (%s): relative difference to Cycles: %.5f" % (setup.strip(), err))
        assert err < 0.005, (setup, err)


def test_hosek_wilkie_sky_matches_cycles():
    err = _both_engines("""
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'HOSEK_WILKIE'
fwd = cam.matrix_world.to_3x3() @ mathutils.Vector((0.0, 0.0, -1.0))
sky.sun_direction = (fwd + mathutils.Vector((0.15, -0.1, 0.05))).normalized()
sky.turbidity = 3.7
sky.ground_albedo = 0.45
nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
""")
    print("Hosek-Wilkie sky: relative difference to Cycles (4x4 blocks): %.5f" % err)
    assert err < 0.002, err


def test_nishita_sky_lights_a_scene_as_in_cycles():
    """A diffuse, a glossy and a glass sphere on a floor under Blender's default Nishita sky (sun at 35 degrees,
    the default 0.545-degree disc, sampled on its own by both engines), sky in view: 8x8 block means
    against Cycles rendered in the test."""
    lit = EMPTY_SCENE_AND_MATERIALS + matched_settings(64, 48, 512) + """
cam.location = (0.0, -7.0, 2.2)
cam.rotation_euler = (math.radians(80), 0.0, 0.0)
cam.data.lens = 28
scene.cycles.caustics_reflective = scene.cycles.caustics_refractive = True
nt = scene.world.node_tree
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'NISHITA'
sky.sun_elevation = math.radians(35.0)
sky.sun_rotation = math.radians(200.0)
nt.links.new(sky.outputs["Color"], nt.nodes["Background"].inputs["Color"])
nt.nodes["Background"].inputs["Strength"].default_value = 0.2

bpy.ops.mesh.primitive_plane_add(size=30.0)
bpy.context.active_object.data.materials.append(material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1)))
bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0, location=(-1.2, 0.0, 1.0))
bpy.ops.object.shade_smooth()
bpy.context.active_object.data.materials.append(material("Diffuse", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.6, 0.4, 1)))
bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0, location=(1.2, 0.5, 1.0))
bpy.ops.object.shade_smooth()
bpy.context.active_object.data.materials.append(material("Metal", "ShaderNodeBsdfGlossy", Color=(0.9, 0.8, 0.6, 1), Roughness=0.3))
bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=0.6, location=(0.2, -1.6, 0.6))
bpy.ops.object.shade_smooth()
bpy.context.active_object.data.materials.append(material("Glass", "ShaderNodeBsdfGlass", IOR=1.45, Roughness=0.0))
"""
    images = render_both(lit, timeout=900)
    a, b = (block_mean(img[..., :3], 8).mean(-1) for img in images)
    rel = (a - b) / b
    report = {"mean_relative_error": float(np.abs(rel).mean()), "mean_signed_error": float(rel.mean()),
              "worst_block": float(np.abs(rel).max())}
    print("Nishita-lit scene against Cycles (8x8 blocks, 512 spp each):", json.dumps(report))
    assert report["mean_relative_error"] < 0.01, report
    assert abs(report["mean_signed_error"]) < 0.005, report


def test_keyed_world_and_sky_strength_follow_the_frame():
    """The Background strength and the Nishita sun intensity keyed over frames: each frame renders
    with its own values, as in Cycles (the same frame rendered by both engines)."""
    setup = EMPTY_SCENE_AND_MATERIALS + matched_settings(24, 16, 512) + """
cam.location = (0.0, 0.0, 0.0)
cam.rotation_euler = (math.radians(95), 0.0, 0.0)
cam.data.lens = 20
nt = scene.world.node_tree
bg = nt.nodes["Background"]
sky = nt.nodes.new("ShaderNodeTexSky")
sky.sky_type = 'NISHITA'
sky.sun_elevation = math.radians(5.0)
sky.sun_rotation = 0.0
sky.sun_size = math.radians(4.0)
nt.links.new(sky.outputs["Color"], bg.inputs["Color"])
for frame, strength, intensity in ((1, 0.5, 0.2), (5, 2.0, 1.5)):
    bg.inputs["Strength"].default_value = strength
    bg.inputs["Strength"].keyframe_insert("default_value", frame=frame)
    sky.sun_intensity = intensity
    sky.keyframe_insert("sun_intensity", frame=frame)
"""
    means = {}
    for frame in (1, 3, 5):
        ours, cycles = (img[..., :3] for img in render_both(setup, frame=frame))
        means[frame] = ours
        # The sky away from the disc pixel by pixel; the disc (512 spp of its edge) by its total light.
        sky = (ours.max(-1) < 50.0) & (cycles.max(-1) < 50.0)
        err = float(np.abs(ours - cycles)[sky].mean() / cycles[sky].mean())
        disc = float(ours.sum() / cycles.sum() - 1.0)
        print("keyed strength, frame %d: sky relative difference to Cycles %.5f, total light %+.4f" % (frame, err, disc))
        assert err < 0.01 and abs(disc) < 0.03, (frame, err, disc)
    assert means[5].mean() > 3.0 * means[1].mean()
