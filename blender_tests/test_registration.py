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


class _RecordingLayout:
    """Stands in for a panel's UILayout: records which properties a draw shows."""

    def __init__(self, shown):
        self.shown = shown
        self.active = True

    def column(self, **kwargs):
        return self

    def row(self, **kwargs):
        return self

    def prop(self, owner, name, **kwargs):
        self.shown.append(name)

    def label(self, **kwargs):
        pass


def test_settings_table_makes_the_properties_the_dict_and_the_panels():
    """One table (settings_schema.py) makes scene.smis's properties with its defaults, the engine's
    settings dict, and the render panels' rows, each shown only where its row says."""
    import pytest
    from smis_render import _smis, properties, settings_schema, ui
    scene = bpy.context.scene
    s = scene.smis
    props = s.bl_rna.properties
    for row in settings_schema.SETTINGS:
        if not row.prop:
            continue
        assert row.prop in props, row.prop
        expected = row.default
        if row.kind == "float":
            assert props[row.prop].default == pytest.approx(expected, rel=1e-6), row.prop
        elif row.is_enum:
            assert props[row.prop].default == expected, row.prop
            assert [i.identifier for i in props[row.prop].enum_items] == row.kind.ids(), row.prop
        else:
            assert props[row.prop].default == expected, row.prop
        assert props[row.prop].description, f"{row.prop} has no tooltip"
    sent = properties.session_settings(scene)
    engine_rows = {r.key for r in settings_schema.SETTINGS if r.engine and r.prop}
    assert engine_rows <= set(sent), engine_rows - set(sent)
    assert set(sent) - engine_rows == {"film_transparent", "film_transparent_glass"}
    # The dict's values are the properties' (an enum by its id, the filter by the engine's key).
    assert sent["filter"] == s.filter_type and sent["sampling_pattern"] == s.sampling_pattern

    def shown(panel):
        out = []
        ui.draw_settings(_RecordingLayout(out), scene, panel)
        return out

    old = (s.integrator, s.direct_light)
    try:
        s.integrator = 'PSF_SMIS'
        assert "psf_radius_px" in shown("psf") and "psf_keller_plane" not in shown("psf")
        s.integrator = 'PSF_KELLER'
        assert "psf_keller_plane" in shown("psf")
        s.direct_light = 'NEE'
        assert shown("direct_light") == ["direct_light"]
        s.direct_light = 'RESTIR'
        assert {"ris_candidates", "restir_mis", "restir_unbiased"} <= set(shown("direct_light"))
        # The animated-seed toggle is drawn beside the seed, once.
        assert shown("sampling").count("use_animated_seed") == 1
        # Every row with a panel and a property is shown on it in some state of the settings: each enum
        # setting at each of its items in turn (the others as they are), so a row shown for a new
        # integrator or mode is checked without an edit here.
        all_shown = set()
        panels = {r.panel for r in settings_schema.SETTINGS if r.panel}
        for row in settings_schema.SETTINGS:
            if not (row.is_enum and row.prop):
                continue
            before = getattr(s, row.prop)
            for item in row.kind.ids():
                setattr(s, row.prop, item)
                for panel in panels:
                    all_shown |= set(shown(panel))
            setattr(s, row.prop, before)
        missing = {r.prop for r in settings_schema.SETTINGS if r.panel and r.prop} - all_shown
        # Light Paths rows the scene gives from Cycles are drawn as Cycles' properties.
        missing -= {r.prop for r in settings_schema.SETTINGS if r.cycles}
        assert not missing, missing
    finally:
        s.integrator, s.direct_light = old
    # An out-of-range value is refused by the engine with the table's limits.
    import numpy as np
    sc = _smis.Scene()
    sc.set_camera({"matrix": np.eye(4), "width": 4, "height": 4, "lens": 20.0})
    sc.commit()
    with pytest.raises(ValueError, match="psf_block_size must be between 1 and 4"):
        _smis.RenderSession(sc, {"psf_block_size": 5})
    with pytest.raises(ValueError, match="integrator must be one of PATH"):
        _smis.RenderSession(sc, {"integrator": "PTAH"})
