"""The stats line says what the engine's scene analysis and integrator skipped."""
from conftest import render

UNLIT = """
scene.render.resolution_x = scene.render.resolution_y = 16
scene.smis.samples = 1
bpy.data.objects.remove(bpy.data.objects['Light'])
scene.world.use_nodes = False
scene.world.color = (0.0, 0.0, 0.0)
scene.smis.integrator = '{integrator}'
"""


def skipped(run):
    """The list after 'skipped:' in the final stats line."""
    assert run.returncode == 0, run.output[-2000:]
    line = [l for l in run.output.splitlines() if "Done" in l][-1]
    return line.split("skipped: ")[1].split(", ") if "skipped: " in line else []


# What the default cube scene never uses: no textures, no cut-outs, a pinhole camera, no passes.
UNUSED = {"textures", "cut-outs", "depth of field", "passes"}


def test_stats_line_lists_skipped_work():
    # No lights, no filtering, no spectral content, no media, plain NEE: all are skipped.
    assert set(skipped(render(setup=UNLIT.format(integrator="PATH")))) == UNUSED | {
        "NEE (no lights)", "filtering", "spectral", "volumes", "RIS/ReSTIR"}


def test_stats_line_omits_work_that_runs():
    # A light and a filtering integrator: NEE and filtering run, spectral and volume work still not.
    found = skipped(render(setup=UNLIT.format(integrator="PSF_SMIS") + "\nbpy.ops.object.light_add(type='POINT')"))
    assert set(found) == UNUSED | {"spectral", "volumes"}, found


def test_stats_line_lists_settings_left_off():
    # Depth of field on, random sampling pattern, photon planes without SMIS.
    found = skipped(render(setup=UNLIT.format(integrator="PATH") + """
scene.camera.data.dof.use_dof = True
scene.smis.sampling_pattern = 'RANDOM'
scene.smis.volume_estimator = 'PLANES_CMIS'
"""))
    assert "depth of field" not in found and {"stratified sampling", "second plane"} <= set(found), found
