"""Image textures (UV mapped, colour-space aware), Object Info colour and tangent-space normal maps,
read back through the Albedo and Normal passes (noise-free), and one warning per untranslatable node."""
import numpy as np

from conftest import _smis, render

# An orthographic camera looking straight down at a 2 x 2 plane it exactly frames, so the plane's
# UV square (0..1) covers the image; a Diffuse BSDF whose Color and Normal the tests feed.
PLANE = """
for obj in list(bpy.data.objects):
    if obj.type == 'MESH':
        bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_plane_add(size=2.0)
plane = bpy.context.active_object
mat = bpy.data.materials.new("Textured")
mat.use_nodes = True
nt = mat.node_tree
nt.nodes.remove(nt.nodes["Principled BSDF"])
diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
nt.links.new(diffuse.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
plane.data.materials.append(mat)
cam = scene.camera
cam.data.type = 'ORTHO'
cam.data.ortho_scale = 2.0
cam.location = (0.0, 0.0, 3.0)
cam.rotation_euler = (0.0, 0.0, 0.0)
scene.render.resolution_x = scene.render.resolution_y = 32
scene.smis.samples = 4
scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
vl = scene.view_layers[0]
vl.use_pass_normal = True
vl.smis.use_pass_albedo = True

def image_node(name, pixels, colorspace, size=2, float_buffer=False):
    img = bpy.data.images.new(name, size, size, alpha=True, float_buffer=float_buffer)
    img.colorspace_settings.name = colorspace
    img.pixels.foreach_set(pixels)
    node = nt.nodes.new("ShaderNodeTexImage")
    node.image = img
    node.interpolation = 'Closest'
    return node
"""

# 2 x 2 texels, bottom row first: dark red, green / blue, light grey.
QUADRANTS = [0.2, 0.0, 0.0, 1.0, 0.0, 0.6, 0.0, 1.0, 0.0, 0.0, 0.4, 1.0, 0.8, 0.8, 0.8, 1.0]


def srgb_to_linear(v):
    v = np.asarray(v, dtype=np.float64)
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def passes(setup):
    run = render(setup=PLANE + setup)
    assert run.returncode == 0, run.output[-3000:]
    ch = _smis.read_exr_channels(run.image_path)
    albedo = np.stack([ch[f"ViewLayer.Albedo.{c}"] for c in "RGB"], axis=-1)
    normal = np.stack([ch[f"ViewLayer.Normal.{c}"] for c in "XYZ"], axis=-1)
    # Edge pixels: the pixel filter's footprint reaches past the plane, which the frame just fits.
    return run, albedo[2:-2, 2:-2], normal[2:-2, 2:-2]


def quadrant_centres(img):
    """The pixel at the centre of each image quadrant, in texel order (bottom row first); the
    passes come without their 2-pixel border."""
    return np.array([img[6, 6], img[6, 22], img[22, 6], img[22, 22]])


def test_image_texture_is_uv_mapped_and_srgb_decoded():
    _, albedo, _ = passes(f"""
tex = image_node("Quadrants", {QUADRANTS}, 'sRGB')
nt.links.new(tex.outputs["Color"], diffuse.inputs["Color"])
""")
    expected = srgb_to_linear(np.array(QUADRANTS).reshape(4, 4)[:, :3])
    np.testing.assert_allclose(quadrant_centres(albedo), expected, rtol=1e-5, atol=1e-6)


def test_non_color_data_is_not_decoded():
    _, albedo, _ = passes(f"""
tex = image_node("Data", {QUADRANTS}, 'Non-Color')
nt.links.new(tex.outputs["Color"], diffuse.inputs["Color"])
""")
    np.testing.assert_allclose(quadrant_centres(albedo), np.array(QUADRANTS).reshape(4, 4)[:, :3],
                               rtol=1e-5, atol=1e-6)


def test_object_info_colour():
    _, albedo, _ = passes("""
info = nt.nodes.new("ShaderNodeObjectInfo")
nt.links.new(info.outputs["Color"], diffuse.inputs["Color"])
plane.color = (0.2, 0.4, 0.6, 1.0)
""")
    np.testing.assert_allclose(albedo, np.broadcast_to([0.2, 0.4, 0.6], albedo.shape), rtol=1e-5)


def test_tangent_space_normal_map_tilts_the_shading_normal():
    # Tangent-space normal (0.6, 0, 0.8) encoded as colour; the plane's U axis is world +X.
    _, _, normal = passes("""
n = [(0.6 + 1) / 2, 0.5, (0.8 + 1) / 2, 1.0]
tex = image_node("Normals", n * 4, 'Non-Color', float_buffer=True)
nmap = nt.nodes.new("ShaderNodeNormalMap")
nt.links.new(tex.outputs["Color"], nmap.inputs["Color"])
nt.links.new(nmap.outputs["Normal"], diffuse.inputs["Normal"])
""")
    np.testing.assert_allclose(normal, np.broadcast_to([0.6, 0.0, 0.8], normal.shape), atol=2e-3)


def test_each_unsupported_node_warned_once():
    # Noise and Bump are evaluated per hit now; Shader to RGB is not (it needs a lighting pass
    # inside the shader): it is named in one warning, whatever the objects and view layers, and
    # its output is taken as 0.
    run, albedo, _ = passes("""
s2r = nt.nodes.new("ShaderNodeShaderToRGB")
emit = nt.nodes.new("ShaderNodeEmission")
nt.links.new(emit.outputs[0], s2r.inputs[0])
nt.links.new(s2r.outputs["Color"], diffuse.inputs["Color"])
noise = nt.nodes.new("ShaderNodeTexNoise")
bump = nt.nodes.new("ShaderNodeBump")
nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
nt.links.new(bump.outputs["Normal"], diffuse.inputs["Normal"])
for i in range(3):  # the material on several objects and a second view layer: still one warning
    bpy.ops.mesh.primitive_plane_add(size=0.1, location=(5.0 + i, 0.0, 0.0))
    bpy.context.active_object.data.materials.append(mat)
scene.view_layers.new("Second")
""")
    lines = [l for l in run.output.splitlines() if l.startswith("Warning")]
    named = [l for l in lines if "ShaderNodeShaderToRGB" in l]
    assert len(named) == 1, run.output[-3000:]
    assert "Material 'Textured'" in named[0] and "not supported" in named[0], named[0]
    assert not any("Noise" in l or "Bump" in l for l in lines), lines
    np.testing.assert_allclose(albedo, 0.0, atol=1e-6)


def test_image_alpha_cuts_out_the_surface():
    # Alpha 0 in the bottom-left and top-right texels: camera rays go through there (no albedo,
    # background depth), the other texels are opaque.
    run = render(setup=PLANE + """
nt.nodes.remove(diffuse)
principled = nt.nodes.new("ShaderNodeBsdfPrincipled")
nt.links.new(principled.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
tex = image_node("Cutout", [1, 1, 1, 0, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 0], 'sRGB')
nt.links.new(tex.outputs["Color"], principled.inputs["Base Color"])
nt.links.new(tex.outputs["Alpha"], principled.inputs["Alpha"])
vl.use_pass_z = True
""")
    assert run.returncode == 0, run.output[-3000:]
    assert "Alpha" not in "".join(l for l in run.output.splitlines() if "Warning" in l or "WARN" in l)
    ch = _smis.read_exr_channels(run.image_path)
    albedo = quadrant_centres(ch["ViewLayer.Albedo.R"][2:-2, 2:-2])
    depth = quadrant_centres(ch["ViewLayer.Depth.Z"][2:-2, 2:-2])
    assert albedo[0] == 0 and albedo[3] == 0 and albedo[1] > 0.5 and albedo[2] > 0.5, albedo
    assert depth[0] == 1e10 and depth[3] == 1e10 and abs(depth[1] - 3.0) < 1e-4, depth


# A plane between the light, the camera and the cube; the world is black so that the plane does not
# change the scene's light selection (the world light's power depends on the scene's size).
OCCLUDER = """
scene.render.resolution_x = scene.render.resolution_y = 32
scene.smis.samples = 4
scene.world.use_nodes = False
scene.world.color = (0.0, 0.0, 0.0)
bpy.ops.mesh.primitive_plane_add(size=3.0, location=(0.0, 0.0, 2.0))
mat = bpy.data.materials.new("Glassless")
mat.use_nodes = True
mat.node_tree.nodes["Principled BSDF"].inputs["Alpha"].default_value = {alpha}
bpy.context.active_object.data.materials.append(mat)
{remove}
"""


def test_transparent_surface_changes_nothing_and_half_alpha_shades():
    """Alpha 0: camera, bounce and shadow rays all pass, so the image is the one without the plane,
    pixel for pixel; alpha 0.5 makes the plane half there (seen and casting a partial shadow)."""
    runs = [render(setup=OCCLUDER.format(alpha=a, remove=r)) for a, r in (
        (0.0, ""), (1.0, "bpy.data.objects.remove(bpy.context.active_object)"), (0.5, ""))]
    for run in runs:
        assert run.returncode == 0, run.output[-3000:]
    transparent, absent, half = (r.image for r in runs)
    assert np.array_equal(transparent, absent)
    assert not np.array_equal(half, absent)


def test_spectral_rendering_uses_the_texture_colours():
    """A D65 light makes the scene spectral (AUTO -> SMIS): the textured lobes are upsampled per
    hit, so every quadrant keeps the colour the RGB render gives it (within 10%: the noise and the
    coefficient table's round-trip error, about 7% for this saturated blue), instead of the node's
    unlinked default colour (0.8 grey, 3 to 60 times off here)."""
    setup = f"""
tex = image_node("Quadrants", {QUADRANTS}, 'sRGB')
nt.links.new(tex.outputs["Color"], diffuse.inputs["Color"])
scene.smis.samples = 64
scene.smis.spectral = '{{mode}}'
bpy.data.lights['Light'].smis.spectrum = 'D65'
"""
    means = {}
    for mode in ("AUTO", "RGB"):
        run = render(setup=PLANE + setup.format(mode=mode))
        assert run.returncode == 0, run.output[-3000:]
        ch = _smis.read_exr_channels(run.image_path)
        img = np.stack([ch[f"ViewLayer.Combined.{c}"] for c in "RGB"], axis=-1)[2:-2, 2:-2]
        means[mode] = np.array([img[2:12, 2:12].mean((0, 1)), img[2:12, 16:26].mean((0, 1)),
                                img[16:26, 2:12].mean((0, 1)), img[16:26, 16:26].mean((0, 1))])
    spec, rgb = means["AUTO"], means["RGB"]
    scale = rgb.max(axis=1, keepdims=True)
    assert np.all(np.abs(spec - rgb) < 0.1 * scale), (spec, rgb)
