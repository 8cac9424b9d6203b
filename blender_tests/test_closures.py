"""Closure parity with Cycles (issue 19): the scene scenes/closures.py builds (one sphere per
closure: Oren-Nayar (constant and textured roughness), Velvet, Translucent, Refraction, Beckmann,
Toon diffuse and glossy, multiscatter GGX, anisotropic GGX and Beckmann (Anisotropic BSDF and
Principled Anisotropic), with Lambert, GGX glossy and glass as controls) rendered by our engine matches the Cycles reference scenes/make_closure_references.sh
rendered into blender_tests/references/closures.exr, sphere by sphere; likewise the Principled set
(closures_principled: its transmission with Transmission Roughness and Specular Tint, Multiscatter
GGX) against closures_principled.exr, the Multiscatter GGX glass set (closures_multiglass) against
closures_multiglass.exr, the Beckmann glass set (closures_beckmann) against closures_beckmann.exr, and
the anisotropic set (closures_aniso: Ashikhmin-Shirley, Mix shaders of anisotropic closures with their
own rotations and tangents) against closures_aniso.exr, and the anisotropic Multiscatter GGX set
(closures_msaniso) against closures_msaniso.exr.

The error measure of a sphere's 32 x 32 px tile, as in test_node_parity.py:

    MRE = mean over its 8x8-pixel blocks b and channels c in {R, G, B} of
          |mean_ours(b, c) - mean_ref(b, c)| / max(mean_ref(b, c), EPS),     EPS = 0.02

and every tile must have MRE <= 1% (the GGX Glass control: see KNOWN). Path-space filtering and spectral
rendering render all five sets, the Albedo pass the first one (quick checks of each sphere's mean, looser bounds, plus a KNOWN control's
own: filtering is biased, spectral upsampling changes coloured products slightly).

Run alone:
    blender -b --factory-startup --addons smis_render --python blender_tests/run.py -- -k closures -s
SMIS_CLOSURE_SPP overrides the sample count of the parity render.
"""
import json
import os
import subprocess

import numpy as np

from conftest import REFERENCES, ROOT, _smis, block_mean, render

EPS = 0.02
THRESHOLD = 0.01
BLOCK = 8
SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "512"))
# Spheres allowed more than THRESHOLD, with the error they must not exceed (so that a regression
# still fails). The GGX Glass control weights reflection and refraction as Cycles does (lobes/dielectric.h): its
# caustic-like noise leaves 1.17% at 512 spp and 0.66% at 2048 spp (SMIS_CLOSURE_SPP); the earlier
# per-microfacet Fresnel weighting measured 2.1-2.9% at 512 spp and fails this bound.
# The coloured multiscatter GGX at roughness 0.8: Cycles' walk tints each further bounce by the colour
# again, its sampling once per bounce but its eval (light samples) twice (mf_eval's glossy phase is
# multiplied by the throughput, and then the throughput multiplies it again), so Cycles' image is darker
# than its own walk where light sampling dominates: 3-5.4% per channel, growing as the colour darkens
# (0.9 / 0.7 / 0.5), while the white sphere of the same roughness is within 1%. Anisotropic Beckmann:
# Cycles 3.4 samples it with alpha_x in both directions (microfacet_sample_stretched(..., alpha_x,
# alpha_x, ...) in bsdf_microfacet.h) but returns the anisotropic pdf, so Cycles' image is biased
# there; ours is not: 1.5% (with the setting beckmann_cycles_sampling, Cycles' sampler, within 1%:
# test_anisotropic_beckmann_matches_cycles_with_its_sampler).
KNOWN = {"glass_ggx_0p3": 0.015, "glossy_multi_0p8_tinted": 0.06, "anisotropic_beckmann": 0.02}
# The anisotropic Beckmann sphere (Roughness 0.4, Anisotropy -0.5: alpha 0.32 / 0.08) with the setting
# beckmann_cycles_sampling (lobes/anisotropic.h, kCyclesSampler: Cycles' visible normals of the isotropic
# alpha_x weighed by the anisotropic pdf, and Cycles 3.4's light choice), rendered alone through a render
# border on its tile. Measured at 1024 spp: 0.48% (by default 1.42%; the default sampler with Cycles' light
# choice 1.07%, so the bound is 0.75%, not the 1% bar, which would barely tell the two apart).
BECKMANN_CYCLES_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
BECKMANN_CYCLES_BOUND = 0.0075
# The Principled set (closures_principled, 3 x 2 spheres): small, so rendered at more samples; its rough
# glass converges slowly (the sharp reflection over rough refraction: 0.99% at 1024 spp, 0.56% at 4096).
# The metal with Multiscatter GGX: Cycles' walk colours each bounce by the Fresnel colour at its
# microfacet, and its eval (light samples) starts from the single scattering's Fresnel colour and tints
# twice, as for the coloured Glossy above; ours gives every further bounce one effective colour
# (shader_program.cpp, metal_multiple_scattering): 1.75% brighter than Cycles (without the multiple
# scattering, 18.9% darker).
PRINCIPLED_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "2048"))
PRINCIPLED_KNOWN = {"principled_multi_metal": 0.025}
# Multiscatter GGX glass (closures_multiglass, 3 x 2 spheres): the Glass BSDF and the Principled rough
# transmission with Multiscatter GGX (lobes/multi_glass.h, glass_multiple.h), which follow Cycles' sampled
# random walk. Cycles' own estimator is inconsistent (README, the material table): its eval (light
# samples) of a refraction lacks the eta^2 its sampling walk carries and evaluates the more grazing
# transmissions with the directions swapped at the same IOR, so where the sun is light-sampled Cycles'
# image differs from its own walk's: under the grey world alone ours is within 0.4-1.3% of Cycles (IOR 2
# at roughness 1: 5.4%), under the sun alone Cycles' mean is 0.23x to 2.7x ours. The bounds are the
# measured errors (1024 spp, against Cycles at 2 x 1024 spp) plus a margin, so that a regression fails.
MULTIGLASS_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
# The Principled glass with Specular Tint 1 (base (0.3, 0.6, 0.9)): 6.1%, and 5.0% with the reflections'
# tint left out of the multiple scattering: under the sun Cycles' eval is not its walk (its single
# scattering's eval multiplies even the refraction by the interpolated Fresnel colour at wi + wo), so
# the tint is checked under the world alone (MULTIGLASS_WORLD_KNOWN below).
MULTIGLASS_KNOWN = {"glass_multi_0p3": 0.125, "glass_multi_0p8": 0.035, "glass_multi_0p6_tinted": 0.07,
                    "glass_multi_1_ior2": 0.33, "principled_multi_glass_0p5": 0.22,
                    "principled_multi_glass_tinted": 0.10, "principled_multi_glass_specular_tint": 0.075}
# The Principled multiscatter glass colours (base; base and Specular Tint 1) under the grey world alone,
# which Cycles reaches only by BSDF samples (closures_multiglass_world, 2 x 1 spheres): Cycles' image is
# its sampled walk, which ours follows. Measured at 1024 spp against Cycles at 2 x 1024 (noise 0.05% rms):
# 0.56% (base (0.9, 0.7, 0.5)) and 0.60% (Specular Tint 1, R/G/B 0.71 / 0.59 / 0.49%); with the tint left
# out of the multiple scattering the latter is 0.83% (R 0.99%; mean +0.6%): under the world the walks'
# further reflections carry little of the sphere's light, so its bound is 0.75%, below the 1% bar.
MULTIGLASS_WORLD_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
MULTIGLASS_WORLD_KNOWN = {"principled_multi_glass_specular_tint": 0.0075}
# The anisotropic set (closures_aniso, 3 x 2 spheres): Ashikhmin-Shirley (Glossy and Anisotropic BSDF) and
# materials mixing anisotropic closures about different tangents and rotations (before each lobe had its
# own tangent: 12.3%, 4.6% and 14.1%). The rough Ashikhmin-Shirley spheres: where Cycles 3.4's sampled
# half vector faces away from wo it flips H but reflects with the unflipped H.I
# (bsdf_ashikhmin_shirley_sample), a non-unit direction that is often above the surface and is valued by
# eval: about 6% of its samples at roughness 0.7 add 2.8% of the true albedo in a furnace (0.2% at
# roughness 0.3). Ours loses those samples, as the BRDF says: 0.77% / 0.79% darker at 4096 spp (a steady
# bias, not noise), 0.79% / 0.90% at 1024; allowed 1.25% so that a change of noise does not fail them.
ANISO_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
ANISO_KNOWN = {"glossy_ashikhmin_0p7": 0.0125, "anisotropic_ashikhmin": 0.0125}
# Anisotropic Multiscatter GGX (closures_msaniso, 3 x 2 spheres: lobes/multiscatter_aniso_ggx.h), white
# Anisotropic BSDFs and Principled metal and dielectric, against Cycles' walk on the stretched
# microsurface; the single-scatter anisotropic GGX sphere of the same alphas is the control (0.23%).
# Under a white world with Cycles' world sampling off (a furnace in the scene: Cycles' sampled walk alone)
# every sphere is within 0.14-0.75% of Cycles: the energy is the walk's. The table's view axis is in theta
# with normal incidence a node (ggx_aniso_layout.h; before, flat beyond cos 0.9375: 2.4% on the 0.6 / 0.9
# sphere, now 1.00%). What is left is Cycles' own inconsistency: its light samples (mf_eval) walk from
# the shallower of the two directions, and its walk is not reciprocal (94.4% of a white furnace at normal
# view against 100% for its sampled walk), so under the sun Cycles' image is neither its sampled walk nor
# one BRDF. Evaluating our table from the shallower direction instead (10 theta nodes) gave 2.3% / 1.4% / 2.4% / 1.7% /
# 0.65% (better on the first sphere, worse on the third): no single deterministic lobe matches both.
# Measured at 1024 spp against Cycles at 2 x 4096: 5.0% (0.8 / 0.7), 1.8%, 1.00%, 1.44% (metal), 0.44%
# (dielectric); allowed those plus a margin so that a regression fails; not the 1% issue 19 asks for.
MSANISO_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
MSANISO_KNOWN = {"aniso_multi_0p8_0p7": 0.055, "aniso_multi_1_m0p5": 0.021, "aniso_multi_0p6_0p9_tangent": 0.014,
                 "principled_multi_aniso_metal": 0.018}
# The same set with the setting multiscatter_cycles_walk (lobes/multiscatter_walk.h): the Anisotropic BSDFs'
# Multiscatter GGX as Cycles' own estimator (its stochastic light-sample eval from the shallower direction,
# its sampled walk's throughput for BSDF samples, its approximate MIS density), and the Principled BSDF's
# specular layer and metal as Cycles' one reflection closure with its interpolated Fresnel colour per bounce
# (kFresnel), with Cycles 3.4's light choice (scene/light_selection.h). Measured at 1024 spp against Cycles
# at 2 x 4096: 0.34% (0.8 / 0.7; 5.0% by default), 0.44% (1 / -0.5; 1.8%), 0.29% (radial-X tangent; 1.00%),
# the Principled metal 0.23% (1.44%; 1.36% before its conversion), the dielectric 0.82% (0.44%: Cycles'
# estimator is not one BSDF, so its image depends on the MIS weights; bound 1.25%). With our own light
# choice: 0.38 / 0.50 / 0.34 / 0.29 / 0.82%.
MSANISO_WALK_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
MSANISO_WALK_KNOWN = {"principled_multi_aniso_dielectric": 0.0125}
# The multiscatter glass set with the setting (lobes/multi_glass_walk.h): Cycles' own glass estimator (its
# stochastic light-sample eval mf_eval_glass, its sampled walk's colours, its MIS density mf_glass_pdf), the
# Principled rough transmission the same closure with Fresnel colours on its reflections, and Cycles 3.4's
# light choice (scene/light_selection.h, Cycles34: the sun always, the grey World never light-sampled, as
# Cycles disables background MIS for a World without variation). Cycles draws the walks of a vertex from one
# LCG seeded 16 further at each bounce, so the walks along a path are correlated (lobes/multi_glass_walk.h,
# seed_cycles_glass_walk; its light sample's eval moves the LCG on before the BSDF sample), and a walk
# lobe's bumped sample keeps the walk's weight (Bsdf::shadowed_value). Measured against Cycles at 2 x 1024
# (default in brackets), 1024 spp: 0.12% (roughness 0.3; 11.1%), 0.69% (0.8; 2.8%), 0.33% (0.6 coloured;
# 5.7%), 0.48% (1, IOR 2; 30.1%), Principled 0.43% (0.5 white; 19.7%), 0.65% (0.8 coloured; 8.9%), 0.66%
# (Specular Tint 1; 6.1%); 512 spp: 0.14 / 0.90 / 0.35 / 0.44 / 0.69 / 0.86 / 0.73%. Before the LCG (each
# walk its own numbers) 0.37 / 1.71 / 1.40 / 1.80 / 3.86 / 3.06 / 1.66% at 1024: one IOR-2 sphere under the
# World alone was 7% darker than Cycles at 1 bounce and 10.6% brighter at 8. At 512 spp the roughness-0.8
# sphere's 0.90% leaves the 1% bar no room for the noise between scene builds (their float rounding moves
# the walks' hashed keys), so the test renders 1024 (about 8 s more).
MULTIGLASS_WALK_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
MULTIGLASS_WALK_KNOWN = {}
# The Principled set with the setting: its Multiscatter GGX metal (Metallic 1) as Cycles' one reflection
# closure: 0.28% at 1024 spp with Cycles' light choice (0.32% with ours; 1.87% by default at 2048). The sharp-reflection glass (not converted) converges
# slowly (0.93% at 2048 spp, 0.99% at 1024): bound 1.25%.
PRINCIPLED_WALK_SPP = int(os.environ.get("SMIS_CLOSURE_SPP", "1024"))
PRINCIPLED_WALK_KNOWN = {"principled_glass_sharp_reflection": 0.0125}
_BUILT = {}


def _scene(tmp_path_factory, set_name="closures"):
    if set_name not in _BUILT:
        out = str(tmp_path_factory.mktemp(set_name))
        proc = subprocess.run(["blender", "-b", "--factory-startup", "--python",
                               os.path.join(ROOT, "scenes", "closures.py"), "--", out, set_name],
                              capture_output=True, text=True, timeout=300)
        assert proc.returncode == 0 and os.path.exists(os.path.join(out, set_name + ".blend")), \
            (proc.stdout + proc.stderr)[-3000:]
        _BUILT[set_name] = out
    with open(os.path.join(_BUILT[set_name], set_name + ".json")) as f:
        return os.path.join(_BUILT[set_name], set_name + ".blend"), json.load(f)["tiles"]


def _render(blend, spp, extra=""):
    run = render(blend, f"""
scene.smis.samples = {spp}
scene.smis.seed = 1
scene.smis.max_bounces = scene.cycles.max_bounces
scene.smis.filter_type = 'BOX'
scene.smis.filter_width = 1.0
scene.smis.integrator = 'PATH'
""" + extra, timeout=600)
    assert run.returncode == 0, run.output[-3000:]
    # Every closure of the scene is translated: nothing falls back to a grey diffuse.
    bad = [ln for ln in run.output.splitlines() if ln.startswith("Warning") and "not supported" in ln]
    assert not bad, "\n".join(bad)
    return run


def block_mre(ours, ref):
    a, b = block_mean(ours[..., :3], BLOCK), block_mean(ref[..., :3], BLOCK)
    return float((np.abs(a - b) / np.maximum(b, EPS)).mean())


def _tile(img, t):
    return img[t["y0"]:t["y0"] + t["size"], t["x0"]:t["x0"] + t["size"]]


def _tile_errors(ours, ref, tiles):
    errors = {}
    for t in tiles:
        o, r = _tile(ours, t)[..., :3], _tile(ref, t)[..., :3]
        errors[t["name"]] = block_mre(o, r)
        per_channel = [block_mre(o[..., c:c + 1], r[..., c:c + 1]) for c in range(3)]
        print("%-24s MRE %6.3f %% (R/G/B %s)  ref mean %.4f  ours %.4f" % (
            t["name"], 100 * errors[t["name"]], " / ".join("%.2f" % (100 * e) for e in per_channel), r.mean(), o.mean()))
    return errors


def _reference(shape, set_name="closures"):
    ref = _smis.read_exr(os.path.join(REFERENCES, set_name + ".exr"))
    assert ref.shape[:2] == shape[:2], (ref.shape, shape)
    return ref


def _set_matches_cycles(tmp_path_factory, set_name, spp, known, extra=""):
    """Every sphere of `set_name` rendered at `spp` (with `extra` settings) within THRESHOLD (or its
    `known` bound) of Cycles."""
    blend, tiles = _scene(tmp_path_factory, set_name)
    ours = _render(blend, spp, extra).image
    assert np.isfinite(ours).all()
    errors = _tile_errors(ours, _reference(ours.shape, set_name), tiles)
    failing = {k: round(100 * v, 3) for k, v in errors.items() if v > known.get(k, THRESHOLD)}
    assert not failing, "spheres over %.0f%% (MRE in %%): %s" % (100 * THRESHOLD, failing)


def test_every_closure_sphere_matches_cycles(tmp_path_factory):
    _set_matches_cycles(tmp_path_factory, "closures", SPP, KNOWN)


def test_every_closure_sphere_matches_cycles_with_its_estimators(tmp_path_factory):
    """The main set with Cycles' own estimators (multiscatter_cycles_walk, beckmann_cycles_sampling): the
    Glossy BSDFs' Multiscatter GGX as Cycles estimates it (lobes/multiscatter_walk.h: its light-sample eval
    tints each further bounce twice) and the anisotropic Beckmann as Cycles samples it, so the two spheres
    KNOWN exempts by default (4.5% and 1.5%) are held to the 1% bar with every other; only the GGX glass'
    noise keeps its bound. Measured at 512 spp: the coloured sphere 0.46%, the anisotropic Beckmann 0.51%
    (1.51% with multiscatter_cycles_walk alone), the worst the glass 0.93%."""
    known = {"glass_ggx_0p3": KNOWN["glass_ggx_0p3"]}
    _set_matches_cycles(tmp_path_factory, "closures", SPP, known,
                        "scene.smis.multiscatter_cycles_walk = True\nscene.smis.beckmann_cycles_sampling = True\n")


def test_anisotropic_beckmann_matches_cycles_with_its_sampler(tmp_path_factory):
    """The anisotropic Beckmann sphere with the setting beckmann_cycles_sampling: Cycles' own (biased)
    sampler gives Cycles' image, within 0.75% (by default, unbiased, 1.5%: KNOWN)."""
    blend, tiles = _scene(tmp_path_factory)
    tile = next(t for t in tiles if t["name"] == "anisotropic_beckmann")
    ref = _smis.read_exr(os.path.join(REFERENCES, "closures.exr"))
    height, width = ref.shape[:2]
    # The border's pixel window is int(border * size) in single precision: half a pixel in.
    x0, y0, size = tile["x0"], tile["y0"], tile["size"]
    ours = _render(blend, BECKMANN_CYCLES_SPP, f"""
scene.smis.beckmann_cycles_sampling = True
scene.render.use_border = True
scene.render.use_crop_to_border = False
scene.render.border_min_x = {(x0 + 0.5) / width!r}
scene.render.border_max_x = {(x0 + size + 0.5) / width!r}
scene.render.border_min_y = {(y0 + 0.5) / height!r}
scene.render.border_max_y = {(y0 + size + 0.5) / height!r}
""").image
    assert ours.shape[:2] == ref.shape[:2] and np.isfinite(ours).all()
    error = _tile_errors(ours, ref, [tile])["anisotropic_beckmann"]
    assert error <= BECKMANN_CYCLES_BOUND, "anisotropic_beckmann MRE %.3f%% over %.2f%%" % (
        100 * error, 100 * BECKMANN_CYCLES_BOUND)


def test_principled_transmission_and_multiscatter_match_cycles(tmp_path_factory):
    """The Principled set: Transmission Roughness, Specular Tint on the glass, the base colour on the
    refraction only, Multiscatter GGX (smooth glass, metal)."""
    _set_matches_cycles(tmp_path_factory, "closures_principled", PRINCIPLED_SPP, PRINCIPLED_KNOWN)


def test_multiscatter_glass_matches_cycles(tmp_path_factory):
    """Multiscatter GGX glass: the Glass BSDF (white at roughness 0.3, 0.8, 1 with IOR 2; coloured)
    and the Principled rough transmission (white, coloured base)."""
    _set_matches_cycles(tmp_path_factory, "closures_multiglass", MULTIGLASS_SPP, MULTIGLASS_KNOWN)


def test_multiscatter_glass_colours_match_cycles_walk(tmp_path_factory):
    """The Principled multiscatter glass' colours under the world alone (Cycles' sampled walk): the base
    at each refraction, and with Specular Tint the interpolated Fresnel colour at each reflection."""
    _set_matches_cycles(tmp_path_factory, "closures_multiglass_world", MULTIGLASS_WORLD_SPP, MULTIGLASS_WORLD_KNOWN)


def test_beckmann_glass_and_refraction_match_cycles(tmp_path_factory):
    """Glass and Refraction with the Beckmann distribution (closures_beckmann, 2 spheres): Beckmann's D
    and rational G1, the glass weighted by the Fresnel term at the normal as Cycles' pair of closures."""
    _set_matches_cycles(tmp_path_factory, "closures_beckmann", PRINCIPLED_SPP, {})


def test_ashikhmin_shirley_and_per_closure_tangents_match_cycles(tmp_path_factory):
    """The anisotropic set: Ashikhmin-Shirley glossy and anisotropic; Mix shaders of anisotropic closures
    with different rotations and tangents, each about its own (Cycles' per-closure tangent)."""
    _set_matches_cycles(tmp_path_factory, "closures_aniso", ANISO_SPP, ANISO_KNOWN)


def test_anisotropic_multiscatter_ggx_matches_cycles(tmp_path_factory):
    """Anisotropic Multiscatter GGX: the Anisotropic BSDF (Roughness / Anisotropy 0.8 / 0.7, 1 / -0.5
    turned, 0.6 / 0.9 about a radial-X tangent) and the Principled BSDF (metal, dielectric) with
    Anisotropic, each within 1% of Cycles or its measured bound (MSANISO_KNOWN)."""
    _set_matches_cycles(tmp_path_factory, "closures_msaniso", MSANISO_SPP, MSANISO_KNOWN)


def test_anisotropic_multiscatter_ggx_matches_cycles_with_its_estimator(tmp_path_factory):
    """The same set with the setting multiscatter_cycles_walk (lobes/multiscatter_walk.h): the Anisotropic
    BSDFs' Multiscatter GGX as Cycles estimates it (its stochastic light-sample eval, its walk for BSDF
    samples, its MIS density), each sphere within 1% of Cycles or its bound (MSANISO_WALK_KNOWN)."""
    _set_matches_cycles(tmp_path_factory, "closures_msaniso", MSANISO_WALK_SPP, MSANISO_WALK_KNOWN,
                        "scene.smis.multiscatter_cycles_walk = True\n")


def test_multiscatter_glass_matches_cycles_with_its_estimator(tmp_path_factory):
    """The multiscatter glass set with the setting multiscatter_cycles_walk (lobes/multi_glass_walk.h): the
    Glass BSDF's and the Principled transmission's Multiscatter GGX as Cycles estimates them, each sphere
    within 1% of Cycles or its bound (MULTIGLASS_WALK_KNOWN)."""
    _set_matches_cycles(tmp_path_factory, "closures_multiglass", MULTIGLASS_WALK_SPP, MULTIGLASS_WALK_KNOWN,
                        "scene.smis.multiscatter_cycles_walk = True\n")


def test_principled_multiscatter_matches_cycles_with_its_estimator(tmp_path_factory):
    """The Principled set with the setting multiscatter_cycles_walk: the Multiscatter GGX metal as Cycles' one
    reflection closure with its Fresnel colour per bounce (multiscatter_walk.h, kFresnel), each sphere
    within 1% of Cycles or its bound (PRINCIPLED_WALK_KNOWN)."""
    _set_matches_cycles(tmp_path_factory, "closures_principled", PRINCIPLED_WALK_SPP, PRINCIPLED_WALK_KNOWN,
                        "scene.smis.multiscatter_cycles_walk = True\n")


def _sphere_means_match(tmp_path_factory, spp, principled_spp, extra, bound, mode_known=None):
    """All five sets rendered with `extra` settings: every sphere finite and its mean within `bound`
    (plus its known difference, and `mode_known`'s for this mode) of Cycles'. The small sets render at
    `principled_spp` (their glass shows the sun through itself, noisy at few samples: the Principled
    smooth glass +4.5% at 128 spp, +0.7% at 1024, path tracing or spectral alike)."""
    mode_known = mode_known or {}
    worst = []
    for set_name, known, samples in (("closures", KNOWN, spp), ("closures_principled", PRINCIPLED_KNOWN, principled_spp),
                                     ("closures_beckmann", {}, principled_spp),
                                     ("closures_multiglass", MULTIGLASS_KNOWN, principled_spp),
                                     ("closures_aniso", ANISO_KNOWN, principled_spp)):
        blend, tiles = _scene(tmp_path_factory, set_name)
        ours = _render(blend, samples, extra).image
        assert np.isfinite(ours).all()
        ref = _reference(ours.shape, set_name)
        for t in tiles:
            o, r = _tile(ours, t)[..., :3].mean(), _tile(ref, t)[..., :3].mean()
            allowed = bound + known.get(t["name"], 0.0) + mode_known.get(t["name"], 0.0)
            print("%-20s %-28s mean %.4f  Cycles %.4f  relative %+.4f  allowed %.4f"
                  % (set_name, t["name"], o, r, o / r - 1.0, allowed))
            if abs(o - r) > allowed * r:
                worst.append((set_name, t["name"], round(o / r - 1.0, 4)))
    assert not worst, worst


def test_path_space_filtering_renders_the_closures(tmp_path_factory):
    """PSF_SMIS (biased, few samples): every sphere of the five sets finite and within 5% of Cycles on
    average (plus its known difference). Measured (64 spp for closures, 256 for the small sets): beyond
    the known spheres all within 2.0% (glass_ggx_0p3 -2.0%); Beckmann <= 0.4%, aniso <= 0.9%; the
    multiscatter glass set (at 512 spp) is within 1.4% of our own PATH (0.2738/0.2775 ... 0.2138/0.2152)
    while Cycles' inconsistent estimator puts its reference up to 34% away (MULTIGLASS_KNOWN)."""
    _sphere_means_match(tmp_path_factory, 64, 256, "scene.smis.integrator = 'PSF_SMIS'\n", 0.05)


def test_spectral_rendering_renders_the_closures(tmp_path_factory):
    """Hero-wavelength spectral rendering: every sphere of the five sets within 3% of Cycles' RGB on
    average, plus its known difference (RGB upsampling makes coloured multi-bounce products differ
    slightly). Measured (128 spp for closures, 1024 for the small sets): beyond the known spheres all
    within 2.0% (principled_multi_metal +2.0%, anisotropic_beckmann +1.5%); Beckmann <= 0.3%, aniso
    <= 0.6%; the multiscatter glass set within 2.2% of our own RGB PATH (the tinted spheres, -2.2% and
    -1.8%: upsampling), Cycles' reference up to 34% away (MULTIGLASS_KNOWN)."""
    _sphere_means_match(tmp_path_factory, 128, 1024, "scene.smis.spectral = 'HERO'\n", 0.03)


def test_albedo_pass_reads_the_closure_colours(tmp_path_factory):
    """The Albedo pass at the sphere centres: the closure colour for the new lobes (Oren-Nayar,
    Velvet and Translucent reflect or pass their colour; a leaf is the mix of its two)."""
    blend, tiles = _scene(tmp_path_factory)
    run = _render(blend, 4, """
scene.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'
scene.view_layers[0].smis.use_pass_albedo = True
""")
    chans = _smis.read_exr_channels(run.image_path)
    albedo = np.stack([chans["ViewLayer.Albedo." + c] for c in "RGB"], axis=-1)
    expected = {"oren_nayar_0p5": (0.8, 0.5, 0.3), "oren_nayar_1": (0.3, 0.6, 0.8), "velvet_0p5": (0.7, 0.2, 0.3),
                "translucent": (0.5, 0.8, 0.3), "leaf": (0.3, 0.65, 0.15),
                "refraction_ggx_0p3": (1.0, 0.9, 0.8), "glossy_multi_0p8_tinted": (0.9, 0.7, 0.5),
                "anisotropic_ggx": (0.8, 0.8, 0.8), "anisotropic_beckmann": (0.7, 0.8, 0.9)}
    for t in tiles:
        if t["name"] not in expected:
            continue
        c = _tile(albedo, t)[12:20, 12:20].reshape(-1, 3).mean(0)
        np.testing.assert_allclose(c, expected[t["name"]], rtol=1e-3, err_msg=t["name"])

