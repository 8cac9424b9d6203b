"""Volumes: Blender's volume shaders become media with Cycles' conventions, a world volume is exported,
every photon-plane estimator renders through the add-on with its counters reported, and so do
path-space filtering and RIS/ReSTIR (their convergence is engine/tests/media_integrators_test.cpp's)."""
import functools

import bpy
import numpy as np
import pytest

from conftest import render, scene_path
from smis_render.sync import materials, world


def _volume_material(builder):
    m = bpy.data.materials.new("VolumeTest")
    m.use_nodes = True
    nt = m.node_tree
    out = nt.nodes["Material Output"]
    for link in list(out.inputs["Surface"].links):
        nt.links.remove(link)
    nt.links.new(builder(nt).outputs[0], out.inputs["Volume"])
    return m


def test_scatter_plus_absorption_follow_cycles_conventions():
    def build(nt):
        scatter = nt.nodes.new('ShaderNodeVolumeScatter')
        scatter.inputs["Color"].default_value = (0.9, 0.5, 0.2, 1.0)
        scatter.inputs["Density"].default_value = 2.0
        scatter.inputs["Anisotropy"].default_value = 0.3
        absorb = nt.nodes.new('ShaderNodeVolumeAbsorption')
        absorb.inputs["Color"].default_value = (0.25, 0.5, 1.0, 1.0)
        absorb.inputs["Density"].default_value = 4.0
        add = nt.nodes.new('ShaderNodeAddShader')
        nt.links.new(scatter.outputs[0], add.inputs[0])
        nt.links.new(absorb.outputs[0], add.inputs[1])
        return add
    warnings = []
    desc = materials.translate(_volume_material(build), warnings.append)
    assert desc["pass_through"] and desc["closures"] == []
    v = desc["volume"]
    assert v["sigma_s"] == pytest.approx((1.8, 1.0, 0.4))
    assert v["sigma_a"] == pytest.approx((3.0, 2.0, 0.0))
    assert v["anisotropy"] == pytest.approx(0.3)
    assert not warnings


def test_principled_volume_and_mix():
    def build(nt):
        pv = nt.nodes.new('ShaderNodeVolumePrincipled')
        pv.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
        pv.inputs["Density"].default_value = 1.0
        pv.inputs["Absorption Color"].default_value = (0.25, 0.0, 1.0, 1.0)
        mix = nt.nodes.new('ShaderNodeMixShader')
        mix.inputs["Fac"].default_value = 0.5
        nt.links.new(pv.outputs[0], mix.inputs[2])  # the other input stays unlinked (nothing)
        return mix
    desc = materials.translate(_volume_material(build), lambda msg: None)
    v = desc["volume"]
    # sigma_s = 0.5 * 1 * colour; sigma_a = 0.5 * (1 - colour) * (1 - sqrt(absorption colour))
    assert v["sigma_s"] == pytest.approx((0.25, 0.25, 0.25))
    assert v["sigma_a"] == pytest.approx((0.125, 0.25, 0.0))


def test_world_volume_is_exported():
    w = bpy.data.worlds.new("FogWorld")
    w.use_nodes = True
    nt = w.node_tree
    scatter = nt.nodes.new('ShaderNodeVolumeScatter')
    scatter.inputs["Density"].default_value = 0.1
    nt.links.new(scatter.outputs[0], nt.nodes["World Output"].inputs["Volume"])
    desc = world.export_world(w, lambda msg: None)
    assert desc["volume"]["sigma_s"] == pytest.approx((0.08, 0.08, 0.08))


@pytest.mark.parametrize("estimator", ["PATH", "PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_COS",
                                       "PLANES_SMIS_EXACT"])
def test_every_volume_estimator_renders(estimator):
    setup = f"""
scene.render.resolution_percentage = 50
scene.smis.samples = 2
scene.smis.volume_estimator = '{estimator}'
scene.smis.photon_planes = 4096
"""
    run = render(scene_path("volume_planes.blend"), setup)
    assert run.returncode == 0, run.output[-3000:]
    img = run.image[..., :3]
    assert np.isfinite(img).all()
    assert img.mean() > 0.05  # the fog is lit
    if estimator != "PATH":
        assert "parallel rejected" in run.output  # the counters reach the user


@functools.lru_cache(maxsize=None)
def _volume_path_mean():
    run = render(scene_path("volume_planes.blend"), """
scene.render.resolution_percentage = 50
scene.smis.samples = 16
""")
    assert run.returncode == 0, run.output[-3000:]
    return float(run.image[..., :3].mean())


@pytest.mark.parametrize("integrator, direct_light", [("PSF_SMIS_UNBIASED", "NEE"), ("PSF_KELLER", "NEE"),
                                                      ("PATH", "RIS"), ("PATH", "RESTIR")])
def test_path_space_filtering_and_resampled_lights_render_media(integrator, direct_light):
    # Refused before; now rendered with the media (measured at 4 spp: within 4% of PATH's mean).
    run = render(scene_path("volume_planes.blend"), f"""
scene.render.resolution_percentage = 50
scene.smis.samples = 4
scene.smis.integrator = '{integrator}'
scene.smis.direct_light = '{direct_light}'
""")
    assert run.returncode == 0, run.output[-3000:]
    img = run.image[..., :3]
    assert np.isfinite(img).all()
    assert img.mean() == pytest.approx(_volume_path_mean(), rel=0.1)


def test_photon_planes_same_seed_same_image_with_one_and_two_threads():
    setup = """
scene.render.resolution_percentage = 50
scene.smis.samples = 1
scene.smis.seed = 5
scene.smis.threads = {threads}
scene.smis.volume_estimator = 'PLANES_SMIS_EXACT'
scene.smis.photon_planes = 4096
"""
    one = render(scene_path("volume_planes.blend"), setup.format(threads=1))
    two = render(scene_path("volume_planes.blend"), setup.format(threads=2))
    assert one.returncode == 0 and two.returncode == 0, one.output[-2000:] + two.output[-2000:]
    assert np.array_equal(one.image, two.image)


def test_volume_settings_and_panels_are_registered():
    s = bpy.context.scene.smis
    props = s.bl_rna.properties
    assert {i.identifier for i in props["volume_estimator"].enum_items} == {
        "PATH", "PLANES_UNWEIGHTED", "PLANES_CMIS", "PLANES_SMIS_COS", "PLANES_SMIS_EXACT"}
    assert s.volume_estimator == "PATH" and s.photon_planes == 40960 and s.smis_planes == 2
    for name in ("volume_estimator", "photon_planes", "smis_planes"):
        assert props[name].description, f"{name} has no tooltip"
    for panel in ("SMIS_RENDER_PT_volumes", "SMIS_MATERIAL_PT_volume", "SMIS_WORLD_PT_volume"):
        assert hasattr(bpy.types, panel), panel
