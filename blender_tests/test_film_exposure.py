"""Film > Exposure (Cycles' `scene.cycles.film_exposure`) scales the image as in Cycles.

rendererer/prism.blend sets it to 10: SMIS rendered that scene at 0.1x Cycles' brightness, without a
word, until the add-on applied it. Cycles multiplies the Combined colour (not alpha) and the other
light passes by it, and leaves data passes (Depth, Normal, Albedo) alone. Measured with Cycles 3.4.1
on this set-up: an Emission of strength 0.5 seen straight on at Exposure 4 writes 2.0, alpha 1.
"""
import numpy as np

from conftest import _smis, render
from test_transparent_emission import DARK
from test_textures import PLANE

# The orthographic plane of test_textures, which fills the frame, as an emitter of radiance 0.5.
EMITTER = PLANE + DARK + """
nt.nodes.remove(diffuse)
em = nt.nodes.new("ShaderNodeEmission")
em.inputs["Strength"].default_value = 0.5
nt.links.new(em.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
vl.use_pass_z = True
"""


def channels(setup):
    run = render(setup=EMITTER + setup)
    assert run.returncode == 0, run.output[-3000:]
    ch = _smis.read_exr_channels(run.image_path)
    rgba = np.stack([ch[f"ViewLayer.Combined.{c}"] for c in "RGBA"], axis=-1)[2:-2, 2:-2]
    albedo = np.stack([ch[f"ViewLayer.Albedo.{c}"] for c in "RGB"], axis=-1)[2:-2, 2:-2]
    return rgba, ch["ViewLayer.Depth.Z"][2:-2, 2:-2], albedo


def test_film_exposure_scales_the_colour_as_in_cycles():
    rgba, depth, albedo = channels("scene.cycles.film_exposure = 4.0\n")
    np.testing.assert_allclose(rgba[..., :3], 2.0, rtol=1e-5)
    np.testing.assert_allclose(rgba[..., 3], 1.0, rtol=1e-6)  # alpha is coverage, not light
    plain_rgba, plain_depth, plain_albedo = channels("")
    np.testing.assert_allclose(plain_rgba[..., :3], 0.5, rtol=1e-5)
    np.testing.assert_array_equal(depth, plain_depth)  # data passes are not exposed
    np.testing.assert_array_equal(albedo, plain_albedo)
