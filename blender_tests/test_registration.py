"""The add-on registers an engine and its settings inside the running Blender."""
import bpy


def test_engine_is_registered():
    engines = {cls.bl_idname for cls in bpy.types.RenderEngine.__subclasses__()}
    assert "SMIS" in engines


def test_settings_exist_with_documented_defaults():
    scene = bpy.context.scene
    s = scene.smis
    assert s.samples >= 1
    assert s.max_bounces >= 0
    assert s.time_limit == 0.0
    assert s.threads == 0
    props = s.bl_rna.properties
    assert {i.identifier for i in props["mis_heuristic"].enum_items} == {"BALANCE", "POWER"}
    assert "PATH" in {i.identifier for i in props["integrator"].enum_items}
    for name in ("samples", "max_bounces", "seed", "mis_heuristic", "time_limit", "threads"):
        assert props[name].description, f"{name} has no tooltip"


def test_engine_can_be_selected():
    scene = bpy.context.scene
    scene.render.engine = "SMIS"
    assert scene.render.engine == "SMIS"


def test_presets_set_what_they_name():
    """Every preset of the Sampling header's menu applies through its operator and leaves the
    settings it names at its values (so a renamed property or enum item fails here)."""
    from smis_render.presets import PRESETS
    assert hasattr(bpy.types, "SMIS_MT_presets")
    scene = bpy.context.scene
    for name, (label, description, values) in PRESETS.items():
        assert label and description
        assert bpy.ops.smis.apply_preset(preset=name) == {'FINISHED'}
        for key, value in values.items():
            got = getattr(scene.smis, key)
            assert (abs(got - value) < 1e-6 if isinstance(value, float) else got == value), (name, key, got)
    bpy.ops.smis.apply_preset(preset="QUICK")
    assert scene.smis.samples == 16 and scene.smis.integrator == 'PATH'


def test_last_render_warnings_stay_listed_in_the_render_properties():
    """A render's warnings are kept for the SMIS Warnings panel (the status bar shows only the last
    report), and the final statistics no longer go to the status bar."""
    from smis_render.sync import reports
    scene = bpy.context.scene
    scene.render.engine = "SMIS"
    scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 16, 16, 100
    scene.smis.samples = 1
    mat = bpy.data.materials.new("Warned")
    mat.use_nodes = True
    nt = mat.node_tree
    s2r = nt.nodes.new("ShaderNodeShaderToRGB")
    nt.links.new(s2r.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    cube = bpy.data.objects.get("Cube")
    cube.data.materials.clear()
    cube.data.materials.append(mat)
    try:
        bpy.ops.render.render()
        listed = reports.recent_warnings["render"]
        assert any("ShaderNodeShaderToRGB" in m and "'Warned'" in m for m in listed), listed
        assert not any("counters" in m for m in listed), listed
        assert hasattr(bpy.types, "SMIS_RENDER_PT_warnings")
    finally:
        cube.data.materials.clear()
        bpy.data.materials.remove(mat)


def test_an_unknown_render_setting_is_an_error():
    """Every key the add-on sends is one the engine reads; a misspelt or retired key is a ValueError
    naming it, not a setting silently left at its default."""
    import numpy as np
    import pytest
    from smis_render import _smis, properties
    s = _smis.Scene()
    s.set_camera({"matrix": np.eye(4), "width": 4, "height": 4, "lens": 20.0})
    s.commit()
    _smis.RenderSession(s, properties.session_settings(bpy.context.scene))  # all known
    with pytest.raises(ValueError, match="'sampels'"):
        _smis.RenderSession(s, {"sampels": 4, "seed": 1})
