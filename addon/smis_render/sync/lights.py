"""Blender lights -> engine light dicts.

Units are Blender's, as Cycles reads them: `energy` is the power in W for
point, spot and area lights and the irradiance in W/m^2 for the sun. The
engine converts them with Cycles' formulas.
"""

import math

from ..spectral_properties import light_spectral
from .visibility import ray_visibility


def _matrix(m):
    return [list(row) for row in m]


def _cycles_setting(light, name, default):
    """A Cycles light setting (Light > Cast Shadow, Multiple Importance): Cycles' own panel sets it,
    but the light carries it; without the Cycles add-on it is in the "cycles" ID properties."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and hasattr(cycles, name):
        return bool(getattr(cycles, name))
    stored = light.get("cycles")
    return bool(stored.get(name, default)) if hasattr(stored, "get") else default


def light_dict(light, matrix, visible_camera=True):
    """The engine dict for a Blender Light datablock placed by `matrix` (matrix_world)."""
    d = {"type": light.type, "matrix": _matrix(matrix), "color": tuple(light.color),
         "visible_camera": bool(visible_camera),
         "cast_shadow": _cycles_setting(light, "cast_shadow", True),
         "use_mis": _cycles_setting(light, "use_multiple_importance_sampling", True)}
    d.update(light_spectral(light))
    if light.type == 'SUN':
        d["strength"] = float(light.energy)
        d["angle"] = float(light.angle)
    else:
        d["power"] = float(light.energy)
    if light.type in {'POINT', 'SPOT'}:
        d["radius"] = float(light.shadow_soft_size)
    if light.type == 'SPOT':
        d["spot_size"] = float(light.spot_size)
        d["spot_blend"] = float(light.spot_blend)
    if light.type == 'AREA':
        d["shape"] = light.shape
        d["size"] = float(light.size)
        d["spread"] = float(light.spread)
        # SQUARE and DISK use `size` on both axes; Blender keeps a stale size_y.
        square = light.shape in {'SQUARE', 'DISK'}
        d["size_y"] = float(light.size if square else light.size_y)
    return d


def problem(d):
    """Why a light dict must be skipped, or None. The engine checks too; this gives
    the user a message in Blender's words."""
    energy = d["strength"] if d["type"] == 'SUN' else d["power"]
    word = "strength" if d["type"] == 'SUN' else "power"
    if not math.isfinite(energy):
        return "its %s is not a finite number" % word
    if energy < 0.0:
        return "its %s is negative (%g)" % (word, energy)
    if energy == 0.0:
        return "its %s is zero" % word
    if d["type"] == 'AREA' and not (d["size"] > 0.0 and d["size_y"] > 0.0):
        return "its size is zero"
    return None


def usable_light_dict(obj, matrix, reporter):
    """The engine dict of one light instance, or None (with a warning) if it must be skipped."""
    light = obj.data
    if light.type not in {'POINT', 'SPOT', 'SUN', 'AREA'}:
        reporter.warning("Light '%s': type %s is not supported, skipped" % (obj.name, light.type))
        return None
    # Object > Visibility > Camera: whether the lamp itself shows in camera rays; the other ray
    # types: which bounce rays see it and which lobes its light samples light (Cycles).
    d = light_dict(light, matrix, getattr(obj, "visible_camera", True))
    visibility = ray_visibility(obj)
    if visibility is not None:
        d["visibility"] = visibility
    why = problem(d)
    if why is not None:
        reporter.warning("Light '%s' skipped: %s" % (obj.name, why))
        return None
    return d


def export_light(scene, obj, matrix, reporter):
    """Add one light instance; returns True if added, False if skipped (with a warning)."""
    d = usable_light_dict(obj, matrix, reporter)
    if d is None:
        return False
    try:
        scene.add_light(d)
        return True
    except ValueError as exc:
        reporter.warning("Light '%s' skipped: %s" % (obj.name, exc))
    return False
