"""Hair parity with Cycles (issue 19): scenes/hair.py's field of 3,600 particle-hair strands (a plane
emitter under a sun and a grey world) rendered by our engine as Embree round Catmull-Rom curves
matches the Cycles 3.4 references in blender_tests/references/hair_*.exr
(scenes/make_hair_references.sh):
  * diffuse, diffuse_curves: the geometry (a Diffuse BSDF on the strands, sun and world, 8 bounces),
    as particle hair and as a Curves object (the same strands converted);
  * hair_bsdf_direct, principled_*_direct: the Hair BSDF and the Principled Hair BSDF's three colour
    parametrisations lit by the sun alone (max bounces 0);
  * principled_random_direct, principled_random_curves_direct: the Principled Hair BSDF with Random
    Color and Random Roughness, each strand's melanin and roughness varied by Hair Info's Random (the
    hash of the strand's index, as Cycles), as particle hair and as a Curves object; without the
    variation the image is 25-30% off Cycles' (test_principled_hair_random_is_seen);
  * info_intercept_direct, info_geometry_direct (and _curves_): Hair Info's Intercept through a
    colour ramp, and its Length, Thickness and Tangent Normal, as the strands' diffuse colour (node
    parity; they were 0 before, with a warning);
  * hair_bsdf: Cycles' Hair BSDF through 8 bounces under sun and world; with hair_cycles_sampling we
    sample it as Cycles (whose sampler and eval disagree) and match, the default is darker;
  * uv_direct, uv_curves_direct: hair UVs, each strand's Texture Coordinate > UV the emitter's UV
    map at its root (particle hair: uv_on_emitter; the Curves object: its surface_uv_coordinate),
    as the strands' diffuse colour (u, v, 0.3), sun-lit without bounces; without the UVs the image
    is far off Cycles' (test_hair_uv_is_seen); vcol_direct: the emitter's colour layer at each
    strand's root read by an Attribute node (particle hair: mcol_on_emitter, sRGB to linear);
  * diffuse_ribbons_close: Cycles' "Rounded Ribbons" curve shape (flat strips facing the ray with
    the round tube's normal faked) in a close view (strands several pixels wide), the diffuse
    strands under sun and world through 8 bounces; rendered as 3D curves instead, the image is
    further off (test_hair_ribbons_match_cycles);
  * diffuse_close_moving, diffuse_curves_close_moving: transform motion blur of a hair object (the
    emitter with its particle hair, and a Curves object, sliding 5 cm per frame, shutter 0.5, close
    view), diffuse strands under sun and world; without the blur the image is far off
    (test_hair_motion_blur_is_seen);
  * emissive_sun: glowing strands (an Emission on hair) lighting the floor and each other;
  * principled_color_sun, principled_color: the Principled Hair BSDF through 8 bounces, lit by the sun
    alone and by the sun and the world. Cycles draws the longitudinal sample of every bounce from an
    LCG seeded 16 apart per bounce, so its samples along a path are correlated and its light bounced
    between strands is brighter than the converged integral (lobes/principled_hair.h,
    cycles_bounce_lcg). With the setting hair_cycles_sampling we draw the same numbers and match
    Cycles' image; without (the default, unbiased) the sun-lit scene's mean is about 20% darker.
    The setting also returns Cycles' pdf (M_p N_p at the tilted angle, not the sampler's density):
    the full scene against its 2 x 2048 spp reference is then 1.60% at 768 spp (mean +0.9%; with the
    density +1.7%), the sun-lit one against 2 x 1024 spp +1.0 +- 0.3% (4 seeds x 512); at the
    test's 128 spp they check the image mean per channel, within 2% (the sun-lit one 3%: our noise),
    and the block error against a looser bar.

Error: mean relative error over 8x8-pixel blocks and R, G, B (as test_closures.py, EPS 0.02), at
most 2% (the issue's bar for hair).

Run alone:
    blender -b --factory-startup --addons smis_render --python blender_tests/run.py -- -k hair -s
"""
import os
import subprocess

import numpy as np
import pytest

from conftest import REFERENCES, ROOT, _smis, block_mean, render

EPS = 0.02
THRESHOLD = 0.02
BLOCK = 8
SPP = int(os.environ.get("SMIS_HAIR_SPP", "128"))
SCENES = ["diffuse", "diffuse_curves", "hair_bsdf_direct", "principled_color_direct", "principled_melanin_direct",
          "principled_absorption_direct", "principled_random_direct", "principled_random_curves_direct"]
# Hair Info's Intercept (through a colour ramp), Length, Thickness and Tangent Normal as the strands'
# diffuse colour, sun-lit without bounces, as particle hair and as a Curves object (node parity).
INFO_SCENES = ["info_intercept_direct", "info_geometry_direct", "info_intercept_curves_direct",
               "info_geometry_curves_direct"]
INFO_THRESHOLD = 0.01  # measured 0.63-0.74% at 128 spp
# Hair UVs (the emitter's UV map at each strand's root) as the strands' diffuse colour, sun-lit.
UV_SCENES = ["uv_direct", "uv_curves_direct", "vcol_direct"]
UV_THRESHOLD = 0.01
UV_UNSEEN_MIN = 0.20
# Rounded Ribbons in a close view, 8 bounces under sun and world.
RIBBON_SCENE = "diffuse_ribbons_close"
RIBBON_THRESHOLD = 0.02
RIBBON_UNSEEN_MIN = 0.03
# Transform motion blur of hair objects (sun and world, 8 bounces).
MOTION_SCENES = ["diffuse_close_moving", "diffuse_curves_close_moving"]
MOTION_UNSEEN_MIN = 0.10
# Samples per scene where not SPP: the varied strands' speckle is noisier (the Curves object's 64 spp
# against its 256 spp reference: 3.1%).
SCENE_SPP = {"principled_random_direct": 2 * SPP, "principled_random_curves_direct": 2 * SPP}
# What Random Color and Random Roughness change: without them the mean strand (roughness 0.4, melanin
# 0.35) is far from Cycles' image (29% at 64 spp).
RANDOM_UNSEEN_MIN = 0.10
# Multiple bounces between Principled Hair strands: the mean within MEAN_THRESHOLD, the 8x8 blocks
# within their noise. The full scene's reference is 2 x 2048 spp (8x8 noise 0.6% rms): ours 1.60% at
# 768 spp (3 seeds x 256, mean +0.9 +- 0.3%), 2.3-2.7% per 256 spp seed; the sun-lit scene's
# reference is 2 x 1024 spp (8x8 noise 2.2% rms; its mean is the former 2 x 256 one's within 0.3%).
BOUNCE_SCENES = ["principled_color_sun", "principled_color"]
MEAN_THRESHOLD = 0.02
# The sun-lit scene's mean is limited by our own render's noise (one sun, narrow lobes): against the
# 2 x 1024 reference, seeds 1-4 at 512 spp give +1.6 / +0.7 / +0.3 / +1.3% (mean +1.0 +- 0.3%, the
# full scene's residual; seed 1 is a high one at every count: +2.0% at 128 spp, the test's), so a
# 128 spp mean scatters by about 1.3% and is checked within 3%.
SCENE_MEAN_THRESHOLD = {"principled_color_sun": 0.03}
NOISY_THRESHOLD = 0.10
# Emissive strands in spectral rendering: the per-hit upsampling's round trip (the table's, up to a
# few 1e-2 for the saturated orange) plus the noise of 64 spp.
EMISSIVE_SPECTRAL_THRESHOLD = 0.03
EMISSION_UNSEEN_MIN = 0.30
_BUILT = {}


def _blend(tmp_path_factory, name):
    if "dir" not in _BUILT:
        _BUILT["dir"] = str(tmp_path_factory.mktemp("hair"))
    path = os.path.join(_BUILT["dir"], "hair_%s.blend" % name)
    if not os.path.exists(path):
        proc = subprocess.run(["blender", "-b", "--factory-startup", "--python", os.path.join(ROOT, "scenes", "hair.py"),
                               "--", _BUILT["dir"], name], capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0 and os.path.exists(path), (proc.stdout + proc.stderr)[-3000:]
    return path


def block_mre(ours, ref):
    a, b = block_mean(ours[..., :3], BLOCK), block_mean(ref[..., :3], BLOCK)
    return float((np.abs(a - b) / np.maximum(b, EPS)).mean())


def _render_and_reference(tmp_path_factory, name, cycles_sampling=False, setup=""):
    run = render(_blend(tmp_path_factory, name), f"""
scene.smis.samples = {SCENE_SPP.get(name, SPP)}
scene.smis.seed = 1
scene.smis.integrator = 'PATH'
scene.smis.hair_cycles_sampling = {cycles_sampling}
""" + setup, timeout=600)
    assert run.returncode == 0, run.output[-3000:]
    bad = [ln for ln in run.output.splitlines() if ln.startswith("Warning") and "not supported" in ln]
    assert not bad, "\n".join(bad)
    ours = run.image
    assert np.isfinite(ours).all()
    ref = _smis.read_exr(os.path.join(REFERENCES, "hair_%s.exr" % name))
    assert ref.shape[:2] == ours.shape[:2]
    err = block_mre(ours, ref)
    print("%-24s MRE %6.3f %%  ref mean %s  ours %s" % (name, 100 * err, ref[..., :3].mean(axis=(0, 1)),
                                                     ours[..., :3].mean(axis=(0, 1))))
    return ours, ref, err


@pytest.mark.parametrize("name", SCENES)
def test_hair_matches_cycles(tmp_path_factory, name):
    _, _, err = _render_and_reference(tmp_path_factory, name)
    assert err <= THRESHOLD, "%s: MRE %.3f%%" % (name, 100 * err)


@pytest.mark.parametrize("name", INFO_SCENES)
def test_hair_info_matches_cycles(tmp_path_factory, name):
    _, _, err = _render_and_reference(tmp_path_factory, name)
    assert err <= INFO_THRESHOLD, "%s: MRE %.3f%%" % (name, 100 * err)


@pytest.mark.parametrize("name", UV_SCENES)
def test_hair_uv_matches_cycles(tmp_path_factory, name):
    _, _, err = _render_and_reference(tmp_path_factory, name)
    assert err <= UV_THRESHOLD, "%s: MRE %.3f%%" % (name, 100 * err)


def test_hair_uv_is_seen(tmp_path_factory):
    """The UV scene tells the strands' UVs from none: with the emitter's UV map removed (every
    strand then reads UV (0, 0)) the image is far from Cycles' (so the bar above checks the UVs)."""
    _, _, err = _render_and_reference(tmp_path_factory, "uv_direct", setup="""
scene.smis.samples = 16
emitter = bpy.data.objects["emitter"].data
while emitter.uv_layers:
    emitter.uv_layers.remove(emitter.uv_layers[0])
""")
    assert err > UV_UNSEEN_MIN, "without the UVs: MRE %.3f%%" % (100 * err)


def test_hair_ribbons_match_cycles(tmp_path_factory):
    """Rounded Ribbons against Cycles' ribbons; the same strands as 3D curves are further off (the
    two shapes differ by a few percent: the ribbons' flat depth where strands cross and shadow)."""
    _, _, err = _render_and_reference(tmp_path_factory, RIBBON_SCENE)
    assert err <= RIBBON_THRESHOLD, "%s: MRE %.3f%%" % (RIBBON_SCENE, 100 * err)
    _, _, thick = _render_and_reference(tmp_path_factory, RIBBON_SCENE, setup="""
scene.cycles_curves.shape = 'THICK'
""")
    assert thick > RIBBON_UNSEEN_MIN, "as 3D curves: MRE %.3f%%" % (100 * thick)


@pytest.mark.parametrize("name", MOTION_SCENES)
def test_hair_motion_blur_matches_cycles(tmp_path_factory, name):
    _, _, err = _render_and_reference(tmp_path_factory, name)
    assert err <= THRESHOLD, "%s: MRE %.3f%%" % (name, 100 * err)


def test_hair_motion_blur_is_seen(tmp_path_factory):
    """The moving hair rendered without motion blur is far from Cycles' blurred image."""
    _, _, err = _render_and_reference(tmp_path_factory, "diffuse_close_moving", setup="""
scene.smis.samples = 16
scene.render.use_motion_blur = False
""")
    assert err > MOTION_UNSEEN_MIN, "without motion blur: MRE %.3f%%" % (100 * err)


def test_curves_material_index_is_ignored_as_in_cycles(tmp_path_factory):
    """Cycles 3.4 renders a Curves object with its first material slot whatever its curves'
    material_index (blender/curves.cpp exports every curve with shader 0; measured: Cycles' image of
    diffuse_curves with every other curve given a red second material is the reference's within its
    noise). So do we: the same edit leaves our image at the plain reference."""
    _, _, err = _render_and_reference(tmp_path_factory, "diffuse_curves", setup="""
import numpy as np
hair = next(o for o in bpy.data.objects if o.type == 'CURVES')
red = bpy.data.materials.new("red")
red.use_nodes = True
red.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (1.0, 0.0, 0.0, 1.0)
hair.data.materials.append(red)
index = hair.data.attributes.new("material_index", 'INT', 'CURVE')
index.data.foreach_set("value", (np.arange(len(hair.data.curves)) % 2).astype(np.int32))
""")
    assert err <= THRESHOLD, "diffuse_curves with material_index: MRE %.3f%%" % (100 * err)


def test_principled_hair_random_is_seen(tmp_path_factory):
    """The random scene tells varied strands from the mean strand: with Random Color and Random
    Roughness zeroed the image is far from Cycles' (so the 2% above checks the variation)."""
    _, _, err = _render_and_reference(tmp_path_factory, "principled_random_direct", setup="""
for m in bpy.data.materials:
    for n in (m.node_tree.nodes if m.use_nodes else []):
        if n.bl_idname == 'ShaderNodeBsdfHairPrincipled':
            n.inputs['Random Color'].default_value = 0.0
            n.inputs['Random Roughness'].default_value = 0.0
""")
    assert err > RANDOM_UNSEEN_MIN, "without the variation: MRE %.3f%%" % (100 * err)


def test_hair_bsdf_bounces_are_cycles_sampler(tmp_path_factory):
    """Cycles' Hair BSDF through 8 bounces under sun and world (hair_bsdf, 2 x 256 spp reference):
    Cycles' sampler counts directions its own eval gives nothing (R below N or on the far azimuth)
    with value/pdf 1 and never samples TT's outer azimuths (lobes/hair.h), so its image is brighter
    than its BSDF's integral. Sampling as Cycles does (hair_cycles_sampling) gives Cycles' image
    (0.56% at 256 spp); the default, one consistent BSDF, is darker (-22/-14/-9% R/G/B)."""
    ours, ref, err = _render_and_reference(tmp_path_factory, "hair_bsdf", cycles_sampling=True)
    bias = ours[..., :3].mean(axis=(0, 1)) / ref[..., :3].mean(axis=(0, 1)) - 1.0
    assert np.all(np.abs(bias) <= MEAN_THRESHOLD), "mean bias %s %%" % np.round(100 * bias, 2)
    assert err <= THRESHOLD, "hair_bsdf with Cycles' sampler: MRE %.3f%%" % (100 * err)
    unbiased, _, _ = _render_and_reference(tmp_path_factory, "hair_bsdf")
    gap = unbiased[..., :3].mean() / ref[..., :3].mean() - 1.0
    print("%-24s consistent BSDF: mean %+.2f %% against Cycles" % ("hair_bsdf", 100 * gap))
    assert -0.30 < gap < -0.08, gap


@pytest.mark.parametrize("name", BOUNCE_SCENES)
def test_principled_hair_bounces_match_cycles(tmp_path_factory, name):
    """With Cycles' per-bounce numbers (hair_cycles_sampling) the image is Cycles'; the default,
    independent sampling, is darker where light bounces between strands: Cycles' bias."""
    ours, ref, err = _render_and_reference(tmp_path_factory, name, cycles_sampling=True)
    bias = ours[..., :3].mean(axis=(0, 1)) / ref[..., :3].mean(axis=(0, 1)) - 1.0
    print("%-24s mean bias %s" % (name, np.round(100 * bias, 2)))
    bound = SCENE_MEAN_THRESHOLD.get(name, MEAN_THRESHOLD)
    assert np.all(np.abs(bias) <= bound), "%s: mean bias %s %%" % (name, np.round(100 * bias, 2))
    assert err <= NOISY_THRESHOLD, "%s: MRE %.3f%%" % (name, 100 * err)
    if name == "principled_color_sun":
        unbiased, _, _ = _render_and_reference(tmp_path_factory, name)
        gap = unbiased[..., :3].mean() / ref[..., :3].mean() - 1.0
        print("%-24s independent sampling: mean %+.2f %% against Cycles" % (name, 100 * gap))
        assert -0.30 < gap < -0.10, gap


def test_emission_on_hair_matches_cycles(tmp_path_factory):
    """Glowing strands (emissive_sun: an Emission coloured along each strand by Hair Info's Intercept,
    plus a Diffuse BSDF, under the sun, no world, 8 bounces): a ray that hits a strand adds its emission
    with MIS weight 1, as Cycles 3.4 weighs curve emission (strands are no lights: no light sample
    reaches them, in Cycles either). The strands' glow lights the floor and each other. RGB against
    Cycles' 2 x 1024 spp within 2%; the spectral path tracer (SMIS, 4 wavelengths; the hit's RGB
    emission upsampled per hit) at half the samples within EMISSIVE_SPECTRAL_THRESHOLD of it. Without
    the strands' emission the image is far off (EMISSION_UNSEEN_MIN)."""
    ours, ref, err = _render_and_reference(tmp_path_factory, "emissive_sun")
    assert err <= THRESHOLD, "emissive_sun: MRE %.3f%%" % (100 * err)
    spectral, _, spectral_err = _render_and_reference(tmp_path_factory, "emissive_sun", setup=f"""
scene.smis.samples = {SPP // 2}
scene.smis.spectral = 'SMIS'
scene.smis.wavelengths = 4
""")
    assert spectral_err <= EMISSIVE_SPECTRAL_THRESHOLD, "emissive_sun spectral: MRE %.3f%%" % (100 * spectral_err)
    # The strands' emission switched off (Strength 0): what the strands rendered before (no glow).
    _, _, dark_err = _render_and_reference(tmp_path_factory, "emissive_sun", setup="""
scene.smis.samples = 16
for m in bpy.data.materials:
    for n in (m.node_tree.nodes if m.use_nodes else []):
        if n.bl_idname == 'ShaderNodeEmission':
            n.inputs['Strength'].default_value = 0.0
""")
    assert dark_err > EMISSION_UNSEEN_MIN, "without the emission: MRE %.3f%%" % (100 * dark_err)
