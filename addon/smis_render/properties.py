"""Render settings stored on the scene as `scene.smis`."""

import math

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

from . import settings_schema


def _blender_property(setting):
    """The Blender property of one row of the settings table."""
    common = {"name": setting.name, "description": setting.description}
    if setting.is_enum:
        items = [(i.id, i.name, i.description) for i in setting.kind.items]
        return EnumProperty(items=items, default=setting.default, **common)
    if setting.kind == "bool":
        return BoolProperty(default=setting.default, **common)
    for key in ("min", "max", "soft_min", "soft_max", "subtype", "unit"):
        value = getattr(setting, key)
        if value is not None:
            common[key] = value
    if setting.kind in ("float", "double"):
        return FloatProperty(default=float(setting.default), **common)
    return IntProperty(default=int(setting.default), **common)


# scene.smis: one property per row of the settings table that has one (settings_schema.py).
SMISRenderSettings = type("SMISRenderSettings", (bpy.types.PropertyGroup,), {
    "__annotations__": {s.prop: _blender_property(s) for s in settings_schema.SETTINGS if s.prop},
    "__doc__": "The SMIS render settings (scene.smis), made from the settings table",
})


def film_exposure(scene):
    """The scene's Film > Exposure, a linear factor on the image's light (Cycles' `film_exposure`:
    it scales the Combined colour, not alpha nor data passes such as Depth, Normal or Albedo).

    It is a Cycles setting (Cycles' Film panel), but the scene carries it: a scene set up for Cycles
    with Exposure 10 must come out 10 times as bright from SMIS too. Without the Cycles add-on its
    value is still stored in the scene's "cycles" ID properties (absent there means the default 1)."""
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, "film_exposure"):
        value = cycles.film_exposure
    else:
        stored = scene.get("cycles")
        value = stored.get("film_exposure", 1.0) if hasattr(stored, "get") else 1.0
    try:
        value = float(value)
    except (TypeError, ValueError):
        return 1.0
    return value if math.isfinite(value) and value >= 0.0 else 1.0


def _cycles_scene_setting(scene, name, default):
    """A setting of Cycles' own panels that the scene carries (without the Cycles add-on: in the
    scene's "cycles" ID properties, absent meaning Cycles' default)."""
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, name):
        return getattr(cycles, name)
    stored = scene.get("cycles")
    return stored.get(name, default) if hasattr(stored, "get") else default


# Light Paths settings: ours (scene.smis) -> Cycles' name in scene.cycles.
LIGHT_PATH_SETTINGS = tuple((s.prop, s.cycles) for s in settings_schema.SETTINGS if s.cycles)


def light_path_source(scene, ours, cycles_name):
    """Where a Light Paths setting comes from: (owner, property name). Ours once set; else the
    scene's Cycles setting when the scene sets it (a scene made for Cycles renders with its limits,
    clamps and caustics); else ours, whose defaults leave the image unbiased."""
    settings = scene.smis
    if settings.is_property_set(ours):
        return settings, ours
    cycles = getattr(scene, "cycles", None)
    if cycles is not None and hasattr(cycles, cycles_name):
        if cycles.is_property_set(cycles_name):
            return cycles, cycles_name
    else:  # without the Cycles add-on its settings are the scene's "cycles" ID properties
        stored = scene.get("cycles")
        if hasattr(stored, "get") and stored.get(cycles_name) is not None:
            return stored, cycles_name
    return settings, ours


def light_path_settings(scene):
    """The engine's per-type bounce limits, clamps and caustics toggles for the scene."""
    out = {}
    for ours, cycles_name in LIGHT_PATH_SETTINGS:
        owner, name = light_path_source(scene, ours, cycles_name)
        value = getattr(owner, name) if isinstance(owner, bpy.types.bpy_struct) else owner[name]
        out[ours] = type(getattr(scene.smis, ours))(value)
    return out


def film_transparent_glass(scene):
    """Cycles' Film > Transparent Glass as the engine takes it: the roughness threshold under which
    glass lets the World through as alpha, or -1 when off (it needs Film > Transparent)."""
    if not scene.render.film_transparent or not _cycles_scene_setting(scene, "film_transparent_glass", False):
        return -1.0
    try:
        value = float(_cycles_scene_setting(scene, "film_transparent_roughness", 0.1))
    except (TypeError, ValueError):
        return -1.0
    return value if math.isfinite(value) and value >= 0.0 else -1.0


def _engine_value(setting, value):
    """A property's value as the engine's settings dict takes it."""
    if setting.is_enum:
        return str(value)
    return {"bool": bool, "float": float, "double": float}.get(setting.kind, int)(value)


def session_settings(scene):
    """The settings dict for `_smis.RenderSession`, resolved for the scene's current frame: every
    engine setting of the table that has a property (a Light Paths setting from where the render takes
    it, light_path_source; a derived one by its row's `session`), and Blender's Film > Transparent."""
    s = scene.smis
    light_paths = light_path_settings(scene)
    out = {}
    for setting in settings_schema.SETTINGS:
        if not (setting.engine and setting.prop):
            continue
        if setting.session:
            value = setting.session(scene, s)
        elif setting.cycles:
            value = light_paths[setting.prop]
        else:
            value = getattr(s, setting.prop)
        out[setting.key] = _engine_value(setting, value)
    # Blender's Film > Transparent (a scene.render setting: Cycles' own Film panel shows it)
    out["film_transparent"] = bool(scene.render.film_transparent)
    out["film_transparent_glass"] = film_transparent_glass(scene)
    return out


def register():
    bpy.utils.register_class(SMISRenderSettings)
    bpy.types.Scene.smis = PointerProperty(type=SMISRenderSettings, name="SMIS Render Settings")


def unregister():
    del bpy.types.Scene.smis
    bpy.utils.unregister_class(SMISRenderSettings)
