"""Loading the compiled engine module `smis_render._smis`.

The module is built separately (CMake target `_smis`, pybind11) into this
folder. It is imported lazily, at the first render, so that:
- the add-on still registers without it: the panels say what is wrong and a
  render fails with a clear ERROR report (Blender exits 1 in background mode)
  instead of "engine not found";
- enabling the add-on does not load it: a pybind11 module must be imported
  under one name only per process, and tools may import it as plain `_smis`.
"""

import importlib
import importlib.util
import os
import sys

_NAME = __package__ + "._smis"
_module = None
_error = None


def _message(reason):
    here = os.path.dirname(os.path.abspath(__file__))
    return (
        "SMIS native module 'smis_render._smis' could not be loaded ({}). "
        "Build the engine (CMake target '_smis') so that "
        "_smis.cpython-311-x86_64-linux-gnu.so is placed in {}".format(reason, here)
    )


def load():
    """Return the native module, or raise RuntimeError with a readable message."""
    global _module, _error
    if _module is None:
        try:
            _module = _already_loaded() or importlib.import_module(_NAME)
            _error = None
        except ImportError as exc:  # also covers undefined symbols / wrong Python ABI
            _error = _message(exc)
            raise RuntimeError(_error) from exc
    return _module


def _already_loaded():
    """The same .so imported under its bare name `_smis` (test tools put this folder on
    sys.path). pybind11 refuses to load one module twice in a process ("type already
    registered"), so reuse that one."""
    mod = sys.modules.get("_smis")
    path = getattr(mod, "__file__", None)
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        same = bool(path) and os.path.samefile(os.path.dirname(path), here)
    except OSError:
        same = False
    if same:
        sys.modules[_NAME] = mod
        return mod
    return None


def problem():
    """A message if the native module is known to be unusable, else None.

    Does not import it: only reports a failed load, or a missing file.
    """
    if _module is not None:
        return None
    if _error is not None:
        return _error
    if importlib.util.find_spec(_NAME) is None:
        return _message("no such module")
    return None
