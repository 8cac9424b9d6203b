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


def done_line(run):
    assert run.returncode == 0, run.output[-2000:]
    return [l for l in run.output.splitlines() if "Done" in l][-1]


def test_stats_line_lists_skipped_work():
    line = done_line(render(setup=UNLIT.format(integrator="PATH")))
    assert "skipped: NEE (no lights), filtering" in line, line


def test_stats_line_omits_work_that_runs():
    line = done_line(render(setup=UNLIT.format(integrator="PSF_SMIS") + "\nbpy.ops.object.light_add(type='POINT')"))
    assert "skipped" not in line, line
