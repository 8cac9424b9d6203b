"""Render passes: which ones a view layer asks for, declaring them to Blender, and
copying the engine's auxiliary buffers into the render result.

Depth and Normal use Blender's own view layer toggles (`use_pass_z`,
`use_pass_normal`, the ones Cycles uses); Albedo and the integrator's diagnostic
pass have toggles of ours under `view_layer.smis`. Names and channel ids follow
Cycles, so compositor set-ups made for Cycles find them.
"""

from dataclasses import dataclass

import bpy
import numpy as np
from bpy.props import BoolProperty, PointerProperty


@dataclass(frozen=True)
class Pass:
    name: str        # Blender pass name (what the compositor and multilayer EXR show)
    engine: str      # the engine's buffer (`RenderSession.pass_pixels`)
    chanid: str
    kind: str        # Blender pass type: COLOR, VECTOR or VALUE

    @property
    def channels(self):
        return len(self.chanid)


DEPTH = Pass("Depth", "Depth", "Z", 'VALUE')
NORMAL = Pass("Normal", "Normal", "XYZ", 'VECTOR')
ALBEDO = Pass("Albedo", "Albedo", "RGB", 'COLOR')

# The integrators' diagnostic passes (one value per sample, averaged), chosen by the settings the
# engine's registry uses to pick the integrator (engine/integrators/registry.cpp).
PSF_REUSED = Pass("PSF Reused", "Diagnostic", "X", 'VALUE')        # other paths' suffixes combined at x1
PLANE_HITS = Pass("Plane Hits", "Diagnostic", "X", 'VALUE')        # photon planes the camera ray gathered
RESTIR_M = Pass("ReSTIR M", "Diagnostic", "X", 'VALUE')            # candidates the final reservoir stands for
WAVELENGTHS = Pass("Wavelengths", "Diagnostic", "X", 'VALUE')      # wavelengths alive at the path's end


def diagnostic_pass(settings):
    """The diagnostic pass of the integrator these scene.smis settings select, or None."""
    if settings.integrator in {"PSF_SMIS", "PSF_KELLER", "PSF_SMIS_UNBIASED"}:
        return PSF_REUSED
    if settings.volume_estimator != 'PATH':
        return PLANE_HITS
    if settings.integrator == 'PATH' and settings.direct_light == 'RESTIR':
        return RESTIR_M
    if settings.integrator == 'PATH' and settings.spectral != 'RGB':
        return WAVELENGTHS  # 0 where AUTO renders the scene in RGB


class SMISViewLayerSettings(bpy.types.PropertyGroup):
    use_pass_albedo: BoolProperty(
        name="Albedo",
        description="Albedo of the first surface a camera ray sees, through perfect mirrors and "
                    "smooth glass (Cycles' denoising albedo), recorded where the render's own camera "
                    "paths meet their first hit",
        default=False,
    )
    use_pass_diagnostic: BoolProperty(
        name="Integrator Diagnostic",
        description="The integrator's own diagnostic pass, averaged over samples: path-space "
                    "filtering's reused suffixes (PSF Reused), photon planes gathered by the camera "
                    "ray (Plane Hits), ReSTIR's reservoir M (ReSTIR M), spectral rendering's "
                    "wavelengths alive at the path's end (Wavelengths). Integrators without one "
                    "write nothing",
        default=False,
    )


def enabled_passes(scene, view_layer):
    """The auxiliary passes (beyond Combined) this view layer asks for."""
    out = []
    if view_layer.use_pass_z:
        out.append(DEPTH)
    if view_layer.use_pass_normal:
        out.append(NORMAL)
    own = getattr(view_layer, "smis", None)
    if own is not None and own.use_pass_albedo:
        out.append(ALBEDO)
    diagnostic = diagnostic_pass(scene.smis)
    if own is not None and own.use_pass_diagnostic and diagnostic is not None:
        out.append(diagnostic)
    return out


def register_passes(engine, scene, view_layer):
    """Body of RenderEngine.update_render_passes: Blender knows only the passes declared here."""
    engine.register_pass(scene, view_layer, "Combined", 4, "RGBA", 'COLOR')
    for p in enabled_passes(scene, view_layer):
        engine.register_pass(scene, view_layer, p.name, p.channels, p.chanid, p.kind)


def write_passes(session, layer, passes):
    """Copy the engine's averaged auxiliary buffers into the render layer's passes."""
    for p in passes:
        target = layer.passes.get(p.name)
        pixels = session.pass_pixels(p.engine)
        if target is None or pixels is None:
            continue
        pixels = np.ascontiguousarray(pixels, dtype=np.float32).reshape(-1, p.channels)
        if len(pixels) != len(target.rect):
            raise RuntimeError("pass %s: %d pixels for a %d-pixel result"
                               % (p.name, len(pixels), len(target.rect)))
        target.rect.foreach_set(pixels)


def register():
    bpy.utils.register_class(SMISViewLayerSettings)
    bpy.types.ViewLayer.smis = PointerProperty(type=SMISViewLayerSettings,
                                               name="SMIS View Layer Settings")


def unregister():
    del bpy.types.ViewLayer.smis
    bpy.utils.unregister_class(SMISViewLayerSettings)
