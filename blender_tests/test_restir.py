"""Many-light direct illumination (RIS / ReSTIR): settings with tooltips, and the scene renders with
every strategy to the same image mean as next event estimation (the unbiasedness itself is tested
statistically in engine/tests/restir_test.cpp)."""
import bpy
import numpy as np

from conftest import render, scene_path

RESTIR_SETTINGS = ("direct_light", "ris_candidates", "restir_neighbors", "restir_radius_px",
                   "restir_history_cap", "restir_mis", "restir_unbiased", "restir_visibility_reuse")

SETUP = """
scene.render.engine = 'SMIS'
scene.render.resolution_percentage = 50
scene.smis.samples = 16
scene.smis.seed = 5
scene.smis.max_bounces = 1
scene.smis.direct_light = '{direct}'
scene.smis.restir_mis = '{mis}'
scene.smis.restir_radius_px = 8.0
scene.smis.spectral = '{spectral}'
"""


def test_settings_exist_with_defaults_and_tooltips():
    s = bpy.context.scene.smis
    props = s.bl_rna.properties
    assert s.direct_light == 'NEE'
    assert {i.identifier for i in props["direct_light"].enum_items} == {"NEE", "RIS", "RESTIR"}
    assert {i.identifier for i in props["restir_mis"].enum_items} == {"SEED", "TALBOT", "NONE"}
    assert s.restir_mis == 'SEED' and s.restir_unbiased and s.restir_visibility_reuse
    for name in RESTIR_SETTINGS:
        assert props[name].description, f"{name} has no tooltip"


def _image_mean(direct, mis="SEED", spectral="AUTO"):
    run = render(scene_path("many_lights.blend"), SETUP.format(direct=direct, mis=mis, spectral=spectral))
    assert run.returncode == 0, run.output[-2000:]
    img = run.image[..., :3]
    assert np.isfinite(img).all()
    return float(img.mean())


def test_ris_and_restir_render_the_many_lights_scene_like_nee():
    nee = _image_mean("NEE")
    assert nee > 0.0
    for direct, mis in (("RIS", "SEED"), ("RESTIR", "SEED"), ("RESTIR", "TALBOT")):
        mean = _image_mean(direct, mis)
        # 64x64 pixels, 16 samples: the image means agree within a few percent; 8% is generous.
        assert abs(mean / nee - 1.0) < 0.08, (direct, mis, mean, nee)


def test_ris_and_restir_render_spectrally_like_spectral_nee():
    # Spectral modes take RIS and ReSTIR (refused before): the chosen light sample is shaded at each
    # wavelength (engine/tests/spectral_resampled_test.cpp tests the convergence per pixel).
    nee = _image_mean("NEE", spectral="HERO")
    assert nee > 0.0
    for direct, mis in (("RIS", "SEED"), ("RESTIR", "TALBOT")):
        mean = _image_mean(direct, mis, spectral="HERO")
        assert abs(mean / nee - 1.0) < 0.08, (direct, mis, mean, nee)
