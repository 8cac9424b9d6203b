"""Properties-editor panels, and SMIS added to the standard panels that apply to it."""

import bpy

from . import native, passes, properties
from .sync.reports import recent_warnings

ENGINE = 'SMIS'


class SMISButtonsPanel:
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "render"
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class SMIS_RENDER_PT_sampling(SMISButtonsPanel, bpy.types.Panel):
    bl_label = "Sampling"

    def draw_header_preset(self, context):
        # Where Cycles puts its sampling presets: quick preview, final, the paper's set-ups.
        self.layout.menu("SMIS_MT_presets", text="Presets", icon='PRESET')

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis

        err = native.problem()
        if err:
            box = layout.box()
            box.alert = True
            box.label(text="Native engine module missing", icon='ERROR')
            # The full message names the expected file; wrap it over a few labels.
            for chunk in _wrap(err, 60):
                box.label(text=chunk)

        col = layout.column()
        col.prop(settings, "samples")
        col.prop(settings, "time_limit")
        sub = col.column(align=True)
        sub.prop(settings, "viewport_samples")
        sub.prop(settings, "viewport_resolution_divider")
        # As Cycles lays it out: the seed with the animated-seed toggle beside it.
        row = col.row(align=True)
        row.prop(settings, "seed")
        row.prop(settings, "use_animated_seed", text="", icon='TIME')
        col.prop(settings, "sampling_pattern")
        col = layout.column(align=True)
        col.prop(settings, "filter_type")
        col.prop(settings, "filter_width")
        # Cycles' Film > Exposure, which SMIS applies too (properties.film_exposure); Cycles' own
        # Film panel is not shown for SMIS.
        cycles = getattr(context.scene, "cycles", None)
        if cycles is not None and hasattr(cycles, "film_exposure"):
            layout.column().prop(cycles, "film_exposure", text="Film Exposure")
        col = layout.column(align=True)
        col.prop(settings, "spectral")
        sub = col.column()
        sub.active = settings.spectral in {'AUTO', 'HERO', 'SMIS', 'SMIS_INDEPENDENT'}
        sub.prop(settings, "wavelengths")


class SMIS_RENDER_PT_light_paths(SMISButtonsPanel, bpy.types.Panel):
    bl_label = "Light Paths"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis

        col = layout.column()
        col.prop(settings, "integrator")
        col.prop(settings, "max_bounces")
        col.prop(settings, "mis_heuristic")


def _light_path_props(layout, scene, names, heading=None):
    """Each setting from where the render takes it (properties.light_path_source): a Cycles
    setting the scene sets is shown, and edited, as Cycles' own."""
    col = layout.column(align=True, heading=heading) if heading else layout.column(align=True)
    for ours, cycles_name in properties.LIGHT_PATH_SETTINGS:
        if ours not in names:
            continue
        owner, name = properties.light_path_source(scene, ours, cycles_name)
        if isinstance(owner, bpy.types.bpy_struct):
            col.prop(owner, name, text=scene.smis.bl_rna.properties[ours].name)
        else:
            col.label(text="%s: %s (Cycles)" % (scene.smis.bl_rna.properties[ours].name, owner[name]))


class SMIS_RENDER_PT_max_bounces(SMISButtonsPanel, bpy.types.Panel):
    """Cycles' per-type bounce limits (Max Bounces is in the parent panel)."""
    bl_label = "Max Bounces per Type"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        _light_path_props(layout, context.scene,
                          {"diffuse_bounces", "glossy_bounces", "transmission_bounces", "transparent_bounces"})


class SMIS_RENDER_PT_clamping(SMISButtonsPanel, bpy.types.Panel):
    """Cycles' Clamping and Caustics: off by default, since both bias the image."""
    bl_label = "Clamping and Caustics"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        _light_path_props(layout, context.scene, {"clamp_direct", "clamp_indirect"}, heading="Clamp")
        _light_path_props(layout, context.scene, {"filter_glossy", "caustics_reflective", "caustics_refractive"},
                          heading="Caustics")


class SMIS_RENDER_PT_path_space_filtering(SMISButtonsPanel, bpy.types.Panel):
    """Shown only for the path-space filtering integrators, with only the settings that apply."""
    bl_label = "Path-Space Filtering"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.scene.smis.integrator.startswith("PSF_")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis
        col = layout.column()
        col.prop(settings, "psf_radius_px")
        col.prop(settings, "psf_radius_alpha")
        col.prop(settings, "psf_max_neighbors")
        col.prop(settings, "psf_light_samples")
        col.prop(settings, "psf_extra_paths")
        col.prop(settings, "psf_block_size")
        if settings.integrator == 'PSF_KELLER':
            col.prop(settings, "psf_keller_normal_cos")
            col.prop(settings, "psf_keller_plane")


class SMIS_RENDER_PT_volumes(SMISButtonsPanel, bpy.types.Panel):
    """Single scattering in participating media: the estimator and the photon-plane settings."""
    bl_label = "Volumes"
    bl_parent_id = "SMIS_RENDER_PT_light_paths"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.scene.smis
        col = layout.column()
        col.prop(settings, "volume_estimator")
        if settings.volume_estimator.startswith("PLANES_"):
            col.prop(settings, "photon_planes")
            col.prop(settings, "plane_shadow_rays")
            col.prop(settings, "plane_surface_samples")
        if settings.volume_estimator.startswith("PLANES_SMIS"):
            col.prop(settings, "smis_planes")


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
        col = layout.column()
        col.prop(settings, "direct_light")
        if settings.direct_light == 'NEE':
            return
        col.prop(settings, "ris_candidates")
        if settings.direct_light != 'RESTIR':
            return
        col = layout.column()
        col.prop(settings, "restir_mis")
        col.prop(settings, "restir_neighbors")
        col.prop(settings, "restir_radius_px")
        col.prop(settings, "restir_history_cap")
        col.prop(settings, "restir_visibility_reuse")
        sub = col.column()
        sub.active = settings.restir_visibility_reuse and settings.restir_mis != 'NONE'
        sub.prop(settings, "restir_unbiased")
        if settings.restir_mis == 'NONE' or (settings.restir_visibility_reuse and not settings.restir_unbiased):
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

        col = layout.column()
        col.prop(settings, "threads")
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
