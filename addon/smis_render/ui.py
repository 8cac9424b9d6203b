"""Properties-editor panels, and SMIS added to the standard panels that apply to it."""

import bpy

from . import native, passes, properties, settings_schema
from .sync.reports import recent_warnings

ENGINE = 'SMIS'


class SMISButtonsPanel:
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}
    settings_panel = None  # a render panel showing just the settings table's rows for it

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        self.layout.use_property_split = True
        self.layout.use_property_decorate = False
        draw_settings(self.layout, context.scene, self.settings_panel)


def draw_settings(layout, scene, panel, heading=None):
    """The settings the table (settings_schema.py) puts on `panel`, in its order: hidden where their
    row's `show` says so, greyed out where `active` does, an icon toggle beside the setting its row
    names (`beside`), and a Light Paths setting from where the render takes it (a Cycles setting the
    scene sets is shown, and edited, as Cycles' own: properties.light_path_source)."""
    settings = scene.smis
    col = layout.column(align=True, heading=heading) if heading else layout.column()
    rows = [s for s in settings_schema.SETTINGS if s.panel == panel and s.prop]
    for setting in rows:
        if setting.beside or (setting.show and not setting.show(settings)):
            continue
        sub = col
        if setting.active:
            sub = col.column()
            sub.active = bool(setting.active(settings))
        toggles = [t for t in rows if t.beside == setting.prop]
        if toggles:
            sub = sub.row(align=True)
        if setting.cycles:
            owner, name = properties.light_path_source(scene, setting.prop, setting.cycles)
            if isinstance(owner, bpy.types.bpy_struct):
                sub.prop(owner, name, text=setting.name)
            else:
                sub.label(text="%s: %s (Cycles)" % (setting.name, owner[name]))
        else:
            sub.prop(settings, setting.prop)
        for toggle in toggles:
            sub.prop(settings, toggle.prop, text="", icon='TIME')
    return col


class SMIS_RENDER_PT_sampling(SMISButtonsPanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw_header_preset(self, context):
        # Where Cycles puts its sampling presets: quick preview, final, the paper's set-ups.
        self.layout.menu("SMIS_MT_presets", text="Presets", icon='PRESET')

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False

        err = native.problem()
        if err:
            box = layout.box()
            box.alert = True
            box.label(text="Native engine module missing", icon='ERROR')
            # The full message names the expected file; wrap it over a few labels.
            for chunk in _wrap(err, 60):
                box.label(text=chunk)

        draw_settings(layout, context.scene, "sampling")
        # Cycles' Film > Exposure, which SMIS applies too (properties.film_exposure); Cycles' own
        # Film panel is not shown for SMIS.
        cycles = getattr(context.scene, "cycles", None)
        if cycles is not None and hasattr(cycles, "film_exposure"):
            layout.column().prop(cycles, "film_exposure", text="Film Exposure")


class SMIS_RENDER_PT_light_paths(SMISButtonsPanel, bpy.types.Panel):
    bl_label = "Light Paths"

    settings_panel = "light_paths"


class SMIS_RENDER_PT_max_bounces(SMISButtonsPanel, bpy.types.Panel):
    """Cycles' per-type bounce limits (Max Bounces is in the parent panel)."""
    bl_label = "Max Bounces per Type"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"
    bl_options = {'DEFAULT_CLOSED'}

    settings_panel = "max_bounces"


class SMIS_RENDER_PT_clamping(SMISButtonsPanel, bpy.types.Panel):
    """Cycles' Clamping and Caustics: off by default, since both bias the image."""
    bl_label = "Clamping and Caustics"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        draw_settings(layout, context.scene, "clamp", heading="Clamp")
        draw_settings(layout, context.scene, "caustics", heading="Caustics")


class SMIS_RENDER_PT_path_space_filtering(SMISButtonsPanel, bpy.types.Panel):
    """Shown only for the path-space filtering integrators, with only the settings that apply."""
    bl_label = "Path-Space Filtering"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.scene.smis.integrator.startswith("PSF_")

    settings_panel = "psf"


class SMIS_RENDER_PT_volumes(SMISButtonsPanel, bpy.types.Panel):
    """Single scattering in participating media: the estimator and the photon-plane settings."""
    bl_label = "Volumes"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"

    settings_panel = "volumes"


class SMIS_RENDER_PT_direct_light(SMISButtonsPanel, bpy.types.Panel):
    """Many-light direct illumination of the path tracer, with only the settings that apply."""
    bl_label = "Direct Light"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.scene.smis.integrator == 'PATH'

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis
        col = draw_settings(layout, context.scene, "direct_light")
        if settings.direct_light == 'RESTIR' and (
                settings.restir_mis == 'NONE' or (settings.restir_visibility_reuse and not settings.restir_unbiased)):
            col.label(text="Biased: darker near shadows", icon='ERROR')


class SMIS_RENDER_PT_performance(SMISButtonsPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis
        rd = context.scene.render

        col = draw_settings(layout, context.scene, "performance")
        if settings.threads == 0:
            # Say what 0 resolves to, since Blender's own thread setting can override it.
            if rd.threads_mode == 'FIXED':
                col.label(text="Using Blender's fixed thread count: %d" % rd.threads)
            else:
                col.label(text="Using all cores")


class SMIS_RENDER_PT_warnings(SMISButtonsPanel, bpy.types.Panel):
    """What the last render and the viewport warned about (a missing image, an unsupported node, a
    skipped object), readable after the status bar has moved on."""
    bl_label = "SMIS Warnings"
    bl_options = {'DEFAULT_CLOSED'}
    MAX_LINES = 30

    def draw_header(self, context):
        n = sum(len(v) for v in recent_warnings.values())
        self.layout.label(text="(%d)" % n if n else "")

    def draw(self, context):
        layout = self.layout
        shown = 0
        for source, title in (("render", "Last render"), ("viewport", "Viewport")):
            messages = recent_warnings[source]
            if not messages:
                continue
            layout.label(text="%s: %d" % (title, len(messages)))
            col = layout.column(align=True)
            for message in messages[:max(0, self.MAX_LINES - shown)]:
                col.label(text=message, icon='ERROR')
                shown += 1
        if shown == 0:
            layout.label(text="No warnings")


class SMIS_LIGHT_PT_light(SMISButtonsPanel, bpy.types.Panel):
    """Only the light settings the engine reads.

    Cycles' light panel also shows Cycles-only switches (max bounces, cast shadow,
    multiple importance, portal) that SMIS ignores, and Blender's generic
    DATA_PT_light shows only the type, so SMIS has its own.
    """
    bl_label = "Light"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.light is not None and super().poll(context)

    def draw(self, context):
        layout = self.layout
        light = context.light

        layout.row().prop(light, "type", expand=True)
        layout.use_property_split = True
        layout.use_property_decorate = False

        col = layout.column()
        col.prop(light, "color")
        col.prop(light, "energy", text="Strength" if light.type == 'SUN' else "Power")
        col.separator()
        if light.type in {'POINT', 'SPOT'}:
            col.prop(light, "shadow_soft_size", text="Radius")
            if light.type == 'SPOT':
                col.separator()
                col.prop(light, "spot_size", text="Spot Size")
                col.prop(light, "spot_blend", text="Blend", slider=True)
                col.prop(light, "show_cone")
        elif light.type == 'SUN':
            col.prop(light, "angle")
        elif light.type == 'AREA':
            col.prop(light, "shape")
            sub = col.column(align=True)
            if light.shape in {'SQUARE', 'DISK'}:
                sub.prop(light, "size")
            else:
                sub.prop(light, "size", text="Size X")
                sub.prop(light, "size_y", text="Y")
        col.separator()
        col.prop(light.smis, "spectrum")
        if light.smis.spectrum == 'BLACKBODY':
            col.prop(light.smis, "temperature")


class SMIS_VIEWLAYER_PT_passes(SMISButtonsPanel, bpy.types.Panel):
    """The passes SMIS writes, as Cycles' Passes > Data panel: Depth and Normal are
    Blender's own toggles, Albedo and the integrator's diagnostic pass are ours."""
    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        view_layer = context.view_layer

        col = layout.column(heading="Include", align=True)
        col.prop(view_layer, "use_pass_combined")
        col.prop(view_layer, "use_pass_z")
        col.prop(view_layer, "use_pass_normal")
        col.prop(view_layer.smis, "use_pass_albedo")
        sub = col.column(align=True)
        sub.active = passes.diagnostic_pass(context.scene.smis) is not None
        sub.prop(view_layer.smis, "use_pass_diagnostic")


def _draw_surface(layout, id_data, fallback_prop):
    """The node tree feeding the Surface input of the Cycles/All output, as Cycles'
    Surface panels show it: the same output node the exporter reads."""
    layout.prop(id_data, "use_nodes", icon='NODETREE')
    layout.separator()
    layout.use_property_split = True
    if not id_data.use_nodes:
        layout.prop(id_data, fallback_prop)
        return
    _draw_output_input(layout, id_data, "Surface")


def _draw_output_input(layout, id_data, socket_name):
    """The node tree feeding one input (Surface, Volume) of the Cycles/All output node."""
    layout.use_property_split = True
    ntree = id_data.node_tree if id_data.use_nodes else None
    node = ntree.get_output_node('CYCLES') if ntree else None
    if node is None:
        layout.label(text="No output node" if id_data.use_nodes else "Use nodes (Surface panel)")
        return
    socket = node.inputs.get(socket_name)
    if socket is None:
        layout.label(text="Incompatible output node")
        return
    layout.template_node_view(ntree, node, socket)


class _MaterialPanel(SMISButtonsPanel):
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        mat = context.material
        return mat is not None and not mat.grease_pencil and super().poll(context)


class _WorldPanel(SMISButtonsPanel):
    bl_context = "world"

    @classmethod
    def poll(cls, context):
        return context.world is not None and super().poll(context)


class SMIS_MATERIAL_PT_surface(_MaterialPanel, bpy.types.Panel):
    bl_label = "Surface"

    def draw(self, context):
        _draw_surface(self.layout, context.material, "diffuse_color")


class SMIS_MATERIAL_PT_volume(_MaterialPanel, bpy.types.Panel):
    """Volume Scatter / Absorption / Principled Volume: the homogeneous medium inside the mesh."""
    bl_label = "Volume"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        _draw_output_input(self.layout, context.material, "Volume")


class SMIS_MATERIAL_PT_spectral(_MaterialPanel, bpy.types.Panel):
    """material.smis: what spectral rendering adds to the node material."""
    bl_label = "Spectral"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        s = context.material.smis
        col = layout.column()
        col.prop(s, "emission_spectrum")
        if s.emission_spectrum == 'BLACKBODY':
            col.prop(s, "emission_temperature")
        col.prop(s, "metal")
        col.prop(s, "dispersion")
        if s.dispersion == 'ABBE':
            col.prop(s, "abbe")


class SMIS_WORLD_PT_surface(_WorldPanel, bpy.types.Panel):
    bl_label = "Surface"

    def draw(self, context):
        _draw_surface(self.layout, context.world, "color")


class SMIS_WORLD_PT_volume(_WorldPanel, bpy.types.Panel):
    """The world's homogeneous medium, filling the scene."""
    bl_label = "Volume"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        _draw_output_input(self.layout, context.world, "Volume")


def _wrap(text, width):
    words, line, lines = text.split(), "", []
    for w in words:
        if line and len(line) + 1 + len(w) > width:
            lines.append(line)
            line = w
        else:
            line = (line + " " + w).strip()
    if line:
        lines.append(line)
    return lines


classes = (
    SMIS_RENDER_PT_sampling,
    SMIS_RENDER_PT_light_paths,
    SMIS_RENDER_PT_max_bounces,
    SMIS_RENDER_PT_clamping,
    SMIS_RENDER_PT_path_space_filtering,
    SMIS_RENDER_PT_volumes,
    SMIS_RENDER_PT_direct_light,
    SMIS_RENDER_PT_performance,
    SMIS_RENDER_PT_warnings,
    SMIS_VIEWLAYER_PT_passes,
    SMIS_LIGHT_PT_light,
    SMIS_MATERIAL_PT_surface,
    SMIS_MATERIAL_PT_spectral,
    SMIS_MATERIAL_PT_volume,
    SMIS_WORLD_PT_surface,
    SMIS_WORLD_PT_volume,
)


# --- Blender's own panels -------------------------------------------------------

# Generic panels of Blender ('BLENDER_RENDER' is the marker for "works with any
# engine") that do NOT apply to SMIS.
_EXCLUDED_GENERIC = {
    'DATA_PT_light',            # replaced by SMIS_LIGHT_PT_light
    'DATA_PT_area',             # idem
    'DATA_PT_spot',             # idem (and it is a child of EEVEE's light panel)
    'DATA_PT_falloff_curve',    # custom light falloff is not supported
    'VIEWLAYER_PT_filter',
    'VIEWLAYER_PT_layer_passes',  # passes are declared by the engine itself
    'RENDER_PT_freestyle',
}

# Blender's material slot list; its poll reads the panel's own COMPAT_ENGINES.
# Cycles' panels cannot be reused the same way: their polls call
# `CyclesButtonsPanel.poll(context)`, which reads the set of the shared base class, so
# adding SMIS to one panel's set shows nothing, and adding it to the base set would
# show every Cycles panel. Hence SMIS' own Surface panels for materials and worlds.
_EXTRA_PANELS = (
    'EEVEE_MATERIAL_PT_context_material',
    'MATERIAL_PT_preview',      # rendered by SMIS (bl_use_preview)
)

# panel class -> the COMPAT_ENGINES it had in its own __dict__ (None if inherited)
_patched = {}


def _is_excluded(name):
    return name in _EXCLUDED_GENERIC or 'freestyle' in name.lower()


def _panels_to_patch():
    panels = []
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, 'COMPAT_ENGINES', None)
        if engines and 'BLENDER_RENDER' in engines and not _is_excluded(panel.__name__):
            panels.append(panel)
    for name in _EXTRA_PANELS:
        panel = getattr(bpy.types, name, None)
        if panel is not None:
            panels.append(panel)
    return panels


def _add_engine_to_panels():
    for panel in _panels_to_patch():
        if panel in _patched:
            continue
        # Assign a NEW set on the class itself: many panels inherit COMPAT_ENGINES
        # from a shared base (all Cycles panels share CyclesButtonsPanel's set), and
        # mutating that set in place would switch on every sibling panel too.
        _patched[panel] = panel.__dict__.get('COMPAT_ENGINES')
        panel.COMPAT_ENGINES = set(panel.COMPAT_ENGINES) | {ENGINE}


def _remove_engine_from_panels():
    for panel, own in _patched.items():
        if own is None:
            try:
                del panel.COMPAT_ENGINES  # back to the inherited set
            except AttributeError:
                pass
        else:
            panel.COMPAT_ENGINES = own
    _patched.clear()


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    _add_engine_to_panels()


def unregister():
    _remove_engine_from_panels()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
