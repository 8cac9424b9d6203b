"""Animations as a render farm runs them (`-s 1 -e 3 -a`): every frame differs, every run is the same."""
import numpy as np
import pytest

from conftest import render

SMALL = """
scene.render.resolution_x = scene.render.resolution_y = 32
scene.smis.samples = 4
scene.smis.seed = 11
"""

# The cube moves along x, one keyframe per frame; the seed stays fixed.
MOVING_CUBE = SMALL + """
cube = bpy.data.objects['Cube']
for frame, x in ((1, -1.0), (2, 0.0), (3, 1.0)):
    cube.location.x = x
    cube.keyframe_insert('location', frame=frame)
"""

# Nothing moves; only the per-frame seed changes the noise.
ANIMATED_SEED = SMALL + """
scene.smis.use_animated_seed = True
"""


def frames(setup):
    runs = render(setup=setup, frames=(1, 3))
    assert runs[0].returncode == 0, runs[0].output[-3000:]
    return [r.image for r in runs]


@pytest.mark.parametrize("setup", [MOVING_CUBE, ANIMATED_SEED], ids=["moving_cube", "animated_seed"])
def test_three_frames_differ_and_are_deterministic(setup):
    first, second = frames(setup), frames(setup)
    for a, b in zip(first, second):
        assert np.isfinite(a).all()
        assert np.array_equal(a, b)
    for i in range(3):
        for j in range(i + 1, 3):
            assert not np.array_equal(first[i], first[j]), (i, j)
