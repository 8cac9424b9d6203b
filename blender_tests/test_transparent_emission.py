"""Textured emission (the Emission colour from an Image Texture, at hits and at light samples) and
the Transparent BSDF (straight through, tinted), on the orthographic plane set-up of test_textures."""
import numpy as np

from conftest import _smis, render
from test_textures import PLANE, QUADRANTS, quadrant_centres

# No world light and no lamps: the emissive plane is the only light.
DARK = """
scene.world.use_nodes = False
scene.world.color = (0.0, 0.0, 0.0)
for obj in list(bpy.data.objects):
    if obj.type == 'LIGHT':
        bpy.data.objects.remove(obj)
"""


def combined(run):
    assert run.returncode == 0, run.output[-3000:]
    ch = _smis.read_exr_channels(run.image_path)
    return np.stack([ch[f"ViewLayer.Combined.{c}"] for c in "RGB"], axis=-1)[2:-2, 2:-2]


def emissive_plane(pixels, colorspace="Non-Color"):
    return PLANE + DARK + f"""
nt.nodes.remove(diffuse)
em = nt.nodes.new("ShaderNodeEmission")
em.inputs["Strength"].default_value = 2.0
tex = image_node("Glow", {pixels!r}, '{colorspace}')
nt.links.new(tex.outputs["Color"], em.inputs["Color"])
nt.links.new(em.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
"""


def test_textured_emission_is_seen_by_the_camera():
    run = render(setup=emissive_plane(QUADRANTS))
    img = combined(run)
    texels = np.array(QUADRANTS).reshape(4, 4)[:, :3]
    np.testing.assert_allclose(quadrant_centres(img), 2.0 * texels, rtol=1e-4, atol=1e-5)
    assert not [l for l in run.output.splitlines() if "arning" in l and ("Glow" in l or "Emission" in l)]


# A white diffuse floor lit only by a textured emitter above it (two-sided emission), seen from below
# the emitter: the camera never sees the emitter itself.
RECEIVER = """
bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 0.0, -0.5))
floor = bpy.context.active_object
white = bpy.data.materials.new("WhiteFloor")
white.use_nodes = True
white.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1.0)
floor.data.materials.append(white)
plane.location.z = 0.5
cam.location = (0.0, 0.0, 0.2)  # between emitter and floor, looking down: it sees only the floor
scene.smis.samples = 16
"""


def test_light_samples_read_the_emission_texture():
    """Next-event estimation and BSDF hits on the emitter use the texture: a pure red texture lights
    the white floor red only, a black one not at all (a constant-colour emitter would light it white)."""
    red = [1.0, 0.0, 0.0, 1.0] * 4
    lit = combined(render(setup=emissive_plane(red) + RECEIVER))
    assert lit[..., 0].mean() > 0.05, lit[..., 0].mean()
    assert lit[..., 1].max() == 0.0 and lit[..., 2].max() == 0.0
    dark = combined(render(setup=emissive_plane([0.0, 0.0, 0.0, 1.0] * 4) + RECEIVER))
    assert dark.max() == 0.0


def mix_with_transparent(tree, first, color, fac):
    """Setup code: Mix(`first`, Transparent `color`, fac) into node tree `tree`'s output."""
    return f"""
tr = {tree}.nodes.new("ShaderNodeBsdfTransparent")
tr.inputs["Color"].default_value = ({color[0]}, {color[1]}, {color[2]}, 1.0)
mix = {tree}.nodes.new("ShaderNodeMixShader")
mix.inputs["Fac"].default_value = {fac}
{tree}.links.new({first}.outputs[0], mix.inputs[1])
{tree}.links.new(tr.outputs[0], mix.inputs[2])
{tree}.links.new(mix.outputs[0], {tree}.nodes["Material Output"].inputs["Surface"])
"""


def transparent_in_front(color, fac):
    """An emitter of radiance 1 seen through a plane of Mix(Diffuse white, Transparent color, fac)."""
    return PLANE + DARK + f"""
plane.location.z = -1.0
nt.nodes.remove(diffuse)
em = nt.nodes.new("ShaderNodeEmission")
nt.links.new(em.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
bpy.ops.mesh.primitive_plane_add(size=2.0, location=(0.0, 0.0, 0.0))
pane = bpy.data.materials.new("Pane")
pane.use_nodes = True
pt = pane.node_tree
pt.nodes.remove(pt.nodes["Principled BSDF"])
df = pt.nodes.new("ShaderNodeBsdfDiffuse")
bpy.context.active_object.data.materials.append(pane)
scene.smis.samples = 64
""" + mix_with_transparent("pt", "df", color, fac)


def test_transparent_surface_multiplies_by_its_colour():
    """Fully transparent (fac 1) with colour c: the emitter behind reads c (the grey part 0.2 passes
    by the cut-out, the coloured rest by the straight-through lobe)."""
    c = (0.8, 0.4, 0.2)
    run = render(setup=transparent_in_front(c, 1.0))
    img = combined(run)
    assert "Transparent" not in "".join(l for l in run.output.splitlines() if "arning" in l), run.output[-2000:]
    # 64 spp x 784 pixels: the mean's standard error is below 0.002 per channel.
    np.testing.assert_allclose(img.reshape(-1, 3).mean(0), c, atol=0.01)
    # A white Transparent BSDF is a pure cut-out: exactly the emitter behind, no noise.
    np.testing.assert_array_equal(combined(render(setup=transparent_in_front((1, 1, 1), 1.0))), 1.0)


def half_transparent_emitter(strength, fac):
    """The emissive plane as Mix(Emission strength, Transparent white, fac)."""
    return PLANE + DARK + f"""
nt.nodes.remove(diffuse)
em = nt.nodes.new("ShaderNodeEmission")
em.inputs["Strength"].default_value = {strength}
""" + mix_with_transparent("nt", "em", (1, 1, 1), fac)


def test_half_transparent_emitter_lights_like_half_the_emission():
    """Mix(Emission 2, Transparent, 0.5) emits 1 in expectation, to the camera (hits kept with
    probability 1/2) and to a floor through light samples (which must see the cut-out too):
    the floor is lit as by a plain Emission 1."""
    seen = combined(render(setup=half_transparent_emitter(2.0, 0.5) + "scene.smis.samples = 64\n"))
    np.testing.assert_allclose(seen.mean(), 1.0, atol=0.02)
    floor = lambda setup: combined(render(setup=setup + RECEIVER + "scene.smis.samples = 64\n")).mean()  # noqa: E731
    half, plain = floor(half_transparent_emitter(2.0, 0.5)), floor(half_transparent_emitter(1.0, 0.0))
    assert abs(half / plain - 1.0) < 0.03, (half, plain)
