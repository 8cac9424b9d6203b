"""Spectral rendering through the add-on: light.smis / material.smis reach the engine, AUTO switches
to spectral sampling only when the scene has spectral content, and spectra keep Blender's units."""
import bpy
import numpy as np

from conftest import render

# Blender's factory scene (grey cube, point light, world) at 32x32.
SMALL = """
scene.render.resolution_x = 32
scene.render.resolution_y = 32
scene.smis.samples = 64
scene.smis.seed = 1
light = bpy.data.lights["Light"]
"""


def _luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def test_f10_light_keeps_luminance_and_changes_colour():
    rgb = render(setup=SMALL + "light.smis.spectrum = 'RGB'\n")
    f10 = render(setup=SMALL + "light.smis.spectrum = 'F10'\n")
    assert rgb.returncode == 0 and f10.returncode == 0, rgb.output[-2000:] + f10.output[-2000:]
    # AUTO: RGB rendering without spectral content, SMIS (4 wavelengths per path) with it.
    assert "wavelengths per path" not in rgb.output
    assert "wavelengths per path 4" in f10.output, f10.output[-2000:]
    a = rgb.image[..., :3].reshape(-1, 3).mean(axis=0)
    b = f10.image[..., :3].reshape(-1, 3).mean(axis=0)
    assert np.isfinite(b).all() and _luminance(a) > 0.01
    # Same strength, same luminance (the spectrum is normalised to it): within noise.
    assert abs(_luminance(b) / _luminance(a) - 1.0) < 0.05, (a, b)
    # FL10 (about 5000 K) is warmer than the RGB white (D65): more red relative to blue.
    assert b[0] / b[2] > 1.05 * a[0] / a[2], (a, b)


def test_material_spectral_settings_are_exported():
    from smis_render.sync import materials
    mat = bpy.data.materials.new("SpectralGold")
    mat.use_nodes = True
    mat.smis.metal = 'Au'
    mat.smis.dispersion = 'N-BK7'
    mat.smis.emission_spectrum = 'BLACKBODY'
    mat.smis.emission_temperature = 3000.0
    d = materials.translate(mat, print)
    assert d["metal"] == "Au" and d["dispersion"] == "N-BK7"
    assert d["emission_spectrum"] == "BLACKBODY" and d["emission_temperature"] == 3000.0


def test_measured_gold_renders_gold():
    setup = SMALL + """
mat = bpy.data.materials.new("Gold")
mat.use_nodes = True
nt = mat.node_tree
glossy = nt.nodes.new("ShaderNodeBsdfGlossy")
glossy.inputs["Color"].default_value = (1, 1, 1, 1)
glossy.inputs["Roughness"].default_value = 0.3
nt.links.new(glossy.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
mat.smis.metal = 'Au'
cube = bpy.data.objects["Cube"].data
cube.materials.clear()
cube.materials.append(mat)
world = bpy.context.scene.world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
"""
    run = render(setup=setup)
    assert run.returncode == 0, run.output[-2000:]
    # A white Glossy cube mirrors the white world: white. Measured gold mirrors it gold.
    px = run.image[..., :3].reshape(-1, 3)
    assert np.isfinite(px).all()
    gold = (px[:, 0] > 1.3 * px[:, 2]) & (px[:, 0] > 0.2)
    assert gold.mean() > 0.05, px.mean(axis=0)


def test_spectral_content_with_path_space_filtering_renders_spectrally():
    # Path-space filtering renders spectral content at one wavelength set per iteration (no warning,
    # no RGB fallback): the F10 light keeps the luminance of the RGB light and changes its colour.
    setup = SMALL + "light.smis.spectrum = '%s'\nscene.smis.integrator = 'PSF_SMIS'\nscene.smis.samples = 16\n"
    spectral, rgb = render(setup=setup % 'F10'), render(setup=setup % 'RGB')
    for run in (spectral, rgb):
        assert run.returncode == 0, run.output[-2000:]
        assert np.isfinite(run.image).all()
    assert "Path Tracing" not in spectral.output, spectral.output[-2000:]
    a, b = spectral.image[..., :3].mean(axis=(0, 1)), rgb.image[..., :3].mean(axis=(0, 1))
    assert abs(a.mean() / b.mean() - 1.0) < 0.15, (a, b)
    assert np.abs(a / a.mean() - b / b.mean()).max() > 0.03, (a, b)
