"""Render passes: every registered pass reaches a multilayer EXR with plausible values."""
import numpy as np

from conftest import _smis, render

# A camera 5 m above a large plane, looking straight down at it: every pixel sees the plane at
# planar depth 5 (Cycles' Z is the distance along the view axis), with normal +Z.
PLANE_SCENE = """
for obj in list(bpy.data.objects):
    if obj.type == 'MESH':
        bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_plane_add(size=100.0, location=(0.0, 0.0, 0.0))
plane = bpy.context.active_object
mat = bpy.data.materials.new("Plane")
mat.use_nodes = True
bsdf = mat.node_tree.nodes["Principled BSDF"]
mat.node_tree.nodes.remove(bsdf)
diffuse = mat.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
diffuse.inputs["Color"].default_value = (0.5, 0.25, 0.125, 1.0)
mat.node_tree.links.new(diffuse.outputs[0], mat.node_tree.nodes["Material Output"].inputs["Surface"])
plane.data.materials.append(mat)
cam = scene.camera
cam.location = (0.3, -0.2, 5.0)
cam.rotation_euler = (0.0, 0.0, 0.4)
light = bpy.data.objects["Light"]
light.location = (0.0, 0.0, 3.0)
scene.render.resolution_x, scene.render.resolution_y = 48, 32
scene.render.resolution_percentage = 100
scene.smis.samples = 4
scene.smis.seed = 7
scene.smis.integrator = '{integrator}'
"""

PASSES_ON = """
scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
vl = scene.view_layers[0]
vl.use_pass_z = True
vl.use_pass_normal = True
vl.smis.use_pass_albedo = True
vl.smis.use_pass_diagnostic = True
"""


def channels(run):
    assert run.returncode == 0, run.output[-3000:]
    return _smis.read_exr_channels(run.image_path)


def layer_pass(chans, name, ids):
    return np.stack([chans[f"ViewLayer.{name}.{c}"] for c in ids], axis=-1)


def test_multilayer_exr_has_every_pass_with_plausible_values():
    run = render(setup=PLANE_SCENE.format(integrator="PSF_SMIS") + PASSES_ON + "\nscene.smis.psf_max_neighbors = 16\n")
    chans = channels(run)
    layers = {name.rsplit(".", 1)[0] for name in chans}
    assert layers == {"ViewLayer.Combined", "ViewLayer.Depth", "ViewLayer.Normal", "ViewLayer.Albedo",
                      "ViewLayer.PSF Reused"}, sorted(chans)
    depth = chans["ViewLayer.Depth.Z"]
    assert depth.shape == (32, 48)
    np.testing.assert_allclose(depth, 5.0, rtol=1e-5)
    normal = layer_pass(chans, "Normal", "XYZ")
    np.testing.assert_allclose(np.linalg.norm(normal, axis=-1), 1.0, atol=1e-5)
    np.testing.assert_allclose(normal[..., 2], 1.0, atol=1e-5)
    albedo = layer_pass(chans, "Albedo", "RGB")
    np.testing.assert_allclose(albedo, np.broadcast_to([0.5, 0.25, 0.125], albedo.shape), rtol=1e-5)
    reused = chans["ViewLayer.PSF Reused.X"]
    # At most psf_max_neighbors - 1 = 15 other paths per pixel; on a lit plane each pixel finds some.
    assert (reused >= 0).all() and (reused <= 15).all()
    assert reused.mean() > 1.0, reused.mean()
    combined = layer_pass(chans, "Combined", "RGBA")
    assert np.isfinite(combined).all() and combined[..., :3].mean() > 0


def test_passes_do_not_change_the_image():
    """The auxiliary passes use their own random stream: the Combined pass stays bit-identical."""
    with_passes = channels(render(setup=PLANE_SCENE.format(integrator="PATH") + PASSES_ON))
    plain = render(setup=PLANE_SCENE.format(integrator="PATH"))
    assert plain.returncode == 0, plain.output[-3000:]
    # PATH has no diagnostic pass: it is not registered even though the toggle is on.
    assert not any("Reused" in name for name in with_passes)
    np.testing.assert_array_equal(layer_pass(with_passes, "Combined", "RGBA"), plain.image)


def test_depth_alone_is_the_depth_of_every_pass():
    """Blender's default passes (Combined and Z): the engine records only the first hit's depth
    (no shading for Normal or Albedo), which must be the same depth, background pixels included."""
    scene = """
scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
scene.render.resolution_x, scene.render.resolution_y = 48, 32
scene.render.resolution_percentage = 100
scene.smis.samples = 4
vl = scene.view_layers[0]
vl.use_pass_z = True
"""
    alone = channels(render(setup=scene))
    every = channels(render(setup=scene + PASSES_ON))
    assert not any(".Normal." in name for name in alone), sorted(alone)
    depth = alone["ViewLayer.Depth.Z"]
    assert (depth < 100.0).any() and (depth > 100.0).any(), "the cube and the background should both be seen"
    np.testing.assert_array_equal(depth, every["ViewLayer.Depth.Z"])


def test_principled_albedo_counts_the_specular_layer_by_its_reflectance():
    """Default Principled BSDF (base 0.8, Specular 0.5 = IOR 1.5): diffuse 0.8 plus the specular
    layer's F0 = 0.04, as a denoising albedo should read (not 0.8 + 1)."""
    setup = PLANE_SCENE.format(integrator="PATH") + PASSES_ON + """
mat.node_tree.nodes.remove(diffuse)
principled = mat.node_tree.nodes.new("ShaderNodeBsdfPrincipled")
mat.node_tree.links.new(principled.outputs[0], mat.node_tree.nodes["Material Output"].inputs["Surface"])
"""
    albedo = layer_pass(channels(render(setup=setup)), "Albedo", "RGB")
    np.testing.assert_allclose(albedo, 0.84, rtol=1e-4)


def test_restir_and_spectral_diagnostic_passes():
    """ReSTIR writes every auxiliary pass (it used to write none) and its reservoir's M (at least the
    M = 16 initial candidates where the plane is lit); SMIS spectral rendering writes the
    wavelengths alive at each path's end: all 4 on a plane without dispersion."""
    restir = channels(render(setup=PLANE_SCENE.format(integrator="PATH") + PASSES_ON +
                             "scene.smis.direct_light = 'RESTIR'\nscene.smis.ris_candidates = 16\n"))
    np.testing.assert_allclose(restir["ViewLayer.Depth.Z"], 5.0, rtol=1e-5)
    m = restir["ViewLayer.ReSTIR M.X"]
    assert m.min() >= 16.0 - 1e-3 and m.mean() > 16.0, (m.min(), m.mean())  # spatial reuse adds more
    spectral = channels(render(setup=PLANE_SCENE.format(integrator="PATH") + PASSES_ON +
                               "scene.smis.spectral = 'SMIS'\nscene.smis.wavelengths = 4\n"))
    np.testing.assert_array_equal(spectral["ViewLayer.Wavelengths.X"], 4.0)


def test_photon_planes_diagnostic_pass():
    from conftest import scene_path
    run = render(scene_path("volume_planes.blend"), PASSES_ON + """
scene.render.resolution_percentage = 25
scene.smis.samples = 2
scene.smis.volume_estimator = 'PLANES_SMIS_COS'
scene.smis.photon_planes = 4096
""")
    chans = channels(run)
    hits = chans["ViewLayer.Plane Hits.X"]
    assert (hits >= 0).all() and hits.mean() > 1.0, hits.mean()
    assert (chans["ViewLayer.Depth.Z"] < 1e10).any()
