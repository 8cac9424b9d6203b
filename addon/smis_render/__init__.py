"""SMIS: a path tracer for Blender, driven through the native module `_smis`."""

bl_info = {
    "name": "SMIS Render",
    "author": "SMIS developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > SMIS",
    "description": "Path tracing render engine (native C++ core)",
    "category": "Render",
}

# Reloading the add-on (F3 "Reload Scripts") must pick up edited submodules too.
if "bpy" in locals():
    import importlib
    for _name in ("native", "properties", "spectral_properties", "passes", "sync", "engine", "presets", "ui"):
        if _name in locals():
            importlib.reload(locals()[_name])

import bpy  # noqa: E402,F401

from . import engine, native, passes, presets, properties, spectral_properties, sync, ui  # noqa: E402,F401


def register():
    properties.register()
    spectral_properties.register()
    passes.register()
    engine.register()
    presets.register()
    ui.register()
    # The engine registers without its native module so that panels and renders can
    # say what is missing; tell the console right away too.
    err = native.problem()
    if err:
        print("SMIS Render: WARNING: " + err)


def unregister():
    ui.unregister()
    presets.unregister()
    engine.unregister()
    passes.unregister()
    spectral_properties.unregister()
    properties.unregister()
