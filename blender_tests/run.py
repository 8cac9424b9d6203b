"""Runs the Blender test suite inside Blender:

    blender -b --factory-startup --addons smis_render --python blender_tests/run.py -- [pytest args]

Blender swallows a script's exceptions, so the pytest exit code is passed on explicitly.
"""
import os
import sys

import pytest

here = os.path.dirname(os.path.abspath(__file__))
args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
# --durations: the slowest tests are listed in every log, so the CI budget can be watched.
code = pytest.main([here, "-p", "no:cacheprovider", "-ra", "--durations=25"] + args)
sys.stdout.flush()
os._exit(int(code))
