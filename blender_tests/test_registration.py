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
