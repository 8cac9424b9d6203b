"""The SMIS RenderEngine: export in update(), render in render().

The native session renders in its own threads with the GIL released; this
thread only polls it (cancel, progress, stats, intermediate results) and
copies pixels into Blender's render result.
"""

import time
import traceback

import bpy
import numpy as np

from . import native, passes, properties, sync
from .sync.reports import Reporter

POLL_SECONDS = 0.2            # test_break / progress / stats cadence
PREVIEW_SAMPLES = 16          # material preview renders
RESULT_UPDATE_SECONDS = 1.5   # how often the intermediate image is shown


def intermediate_results_shown():
    """Whether anyone can see an intermediate image. Not in background mode (`blender -b`): Cycles
    then has no display driver (BlenderSession::ensure_display_driver_if_needed returns for
    headless), so it only writes the final result. Each update here costs a film resolve, a
    foreach_set and Blender's update_result on the main thread while the render threads run."""
    return not bpy.app.background


class SMISRenderEngine(bpy.types.RenderEngine):
    bl_idname = "SMIS"
    bl_label = "SMIS"
    bl_use_postprocess = True           # compositor and sequencer run on our result
    bl_use_shading_nodes_custom = False  # use Blender's shader node editor (Cycles' nodes)
    bl_use_preview = True                # material/light/world preview thumbnails and panels
    # Rendered shading is ours (view_update/view_draw); Material Preview uses EEVEE on
    # the same nodes, as with Cycles.
    bl_use_eevee_viewport = True

    def __init__(self):
        # One instance per frame; it renders every view layer of that frame.
        self._export = None
        self._export_error = None
        self._reporter = Reporter(self)
        # Interactive viewport state. When Blender frees the engine, the native session
        # in it is destroyed too, and its destructor stops and joins the render threads.
        self._viewport = None

    def break_requested(self):
        """Blender's test_break() (Esc in the UI, closing the render window).

        A plain Python method so tests can patch it: RNA functions such as test_break
        take precedence over attributes set on the Python class, so patching
        SMISRenderEngine.test_break has no effect.
        """
        return self.test_break()

    # -- export ----------------------------------------------------------------------

    def update(self, data, depsgraph):
        """Translate the view layer's depsgraph into a committed engine scene."""
        self._export, self._export_error = None, None
        self._reporter.quiet = self.is_preview
        try:
            smis = native.load()
            self.update_stats("", "Exporting scene")
            self._export = sync.export_depsgraph(smis, depsgraph, self._reporter,
                                                  engine=self)
        except sync.Cancelled:
            self._export_error = None  # render() sees no export and returns quietly
        except (RuntimeError, sync.ExportError) as exc:
            self._export_error = str(exc)
        except Exception as exc:  # a bug of ours: report it, never take Blender down
            traceback.print_exc()
            self._export_error = "Scene export failed: %s: %s" % (type(exc).__name__, exc)

    # -- interactive viewport ----------------------------------------------------------

    def view_update(self, context, depsgraph):
        from .viewport import ViewportRenderer  # needs the gpu module: UI sessions only
        if self._viewport is None:
            self._viewport = ViewportRenderer()
        try:
            self._viewport.update(context, depsgraph)
        except Exception:  # a bug of ours must not take the UI down
            traceback.print_exc()

    def view_draw(self, context, depsgraph):
        if self._viewport is None:
            return
        try:
            self._viewport.draw(self, context, depsgraph)
        except Exception:
            traceback.print_exc()

    def update_render_passes(self, scene=None, renderlayer=None):
        passes.register_passes(self, scene, renderlayer)

    # -- render ----------------------------------------------------------------------

    def render(self, depsgraph):
        export, self._export = self._export, None
        if self._export_error:
            # In background mode an ERROR report makes Blender exit 1 and write nothing:
            # the clean failure a render farm can see.
            self.report({'ERROR'}, self._export_error)
            return
        if export is None:
            return  # export cancelled by the user
        try:
            self._render(depsgraph, export)
        except Exception as exc:
            traceback.print_exc()
            self.report({'ERROR'}, "SMIS render failed: %s: %s" % (type(exc).__name__, exc))

    def _render(self, depsgraph, export):
        smis = native.load()
        scene = depsgraph.scene
        x0, y0, x1, y1 = export.camera["border"]
        w, h = x1 - x0, y1 - y0

        aux = passes.enabled_passes(scene, depsgraph.view_layer)
        settings = properties.session_settings(scene)
        settings["aux_passes"] = bool(aux)  # off: the engine traces no extra rays for them
        settings["aux_shading"] = any(p is not passes.DEPTH for p in aux)  # Z alone needs no shading
        if self.is_preview:
            # Blender's preview scene (material ball, light, world) is rendered small and often.
            settings.update(samples=min(settings["samples"], PREVIEW_SAMPLES), time_limit=0.0)
        try:
            session = smis.RenderSession(export.scene, settings)
            spectral = smis.resolve_spectral_mode(export.scene, settings)
        except ValueError as exc:
            self.report({'ERROR'}, "SMIS: invalid render settings: %s" % exc)
            return
        if export.scene.stats()["has_subsurface"] and settings["integrator"].startswith("PSF"):
            self._reporter.warning("%s: subsurface scattering is path traced per pixel, not filtered, where "
                                   "it is a surface's only closure; seen after a glossy bounce it renders as "
                                   "diffuse (Path Tracing walks there)" % settings["integrator"])

        # begin_result's rectangle is relative to the border window: Blender's result
        # is already border-sized, so (0, 0, w, h) is the whole of it.
        result = self.begin_result(0, 0, w, h, layer=depsgraph.view_layer.name)
        if result is None:
            self.report({'ERROR'}, "SMIS: Blender gave no render result for %dx%d" % (w, h))
            return
        try:
            combined = result.layers[0].passes["Combined"]
            if len(combined.rect) != w * h:
                raise RuntimeError("render result is %d pixels, the camera border window "
                                   "%dx%d" % (len(combined.rect), w, h))
            self._run_session(session, result, combined, aux, properties.film_exposure(scene))
        finally:
            # Ending the result is mandatory: an exception between begin_result and
            # end_result crashes Blender.
            self.end_result(result)
        self._final_reports(export, session)

    def _run_session(self, session, result, combined, aux=(), exposure=1.0):
        skipped = list(session.skipped())
        show = intermediate_results_shown()
        session.start()
        try:
            last_update = time.monotonic()
            cancelled = False
            while not session.wait(POLL_SECONDS):
                if not cancelled and self.break_requested():
                    session.cancel()
                    cancelled = True
                self._show_progress(session.progress(), skipped)
                if show and time.monotonic() - last_update >= RESULT_UPDATE_SECONDS:
                    self._write_pixels(session, combined, exposure)
                    passes.write_passes(session, result.layers[0], aux)
                    self.update_result(result)
                    last_update = time.monotonic()
            self._show_progress(session.progress(), skipped)
            self._write_pixels(session, combined, exposure)
            passes.write_passes(session, result.layers[0], aux)
            error = session.error() if hasattr(session, "error") else ""
            if error:
                self.report({'ERROR'}, "SMIS render failed: %s" % error)
        except BaseException:
            # Never leave native threads rendering into a session we are abandoning.
            session.cancel()
            session.wait(30.0)
            raise

    def _show_progress(self, p, skipped=()):
        self.update_progress(float(p["fraction"]))
        self.update_stats("", stats_line(p, skipped))

    @staticmethod
    def _write_pixels(session, combined, exposure=1.0):
        # (h, w, 4) float32, row 0 = bottom, exactly Blender's layout; foreach_set
        # wants (N, 4), a flat array is refused.
        pixels = np.ascontiguousarray(session.pixels(), dtype=np.float32)
        if exposure != 1.0:  # Film > Exposure scales the colour, not alpha (as Cycles does)
            pixels = pixels * np.array([exposure, exposure, exposure, 1.0], dtype=np.float32)
        n = len(combined.rect)
        if pixels.ndim != 3 or pixels.shape[2] != 4 or pixels.shape[0] * pixels.shape[1] != n:
            raise RuntimeError("engine returned pixels of shape %s for a %d-pixel result"
                               % (pixels.shape, n))
        combined.rect.foreach_set(pixels.reshape(-1, 4))

    def _final_reports(self, export, session):
        p = session.progress()
        counters = dict(session.counters())
        dropped_tris = int(export.stats.get("dropped_triangles", export.counts.dropped_triangles))
        nan = int(counters.get("nan_caught", 0))

        # Through the reporter: with several view layers the same message comes once.
        if dropped_tris:
            self._reporter.warning("%d degenerate or non-finite triangles were dropped"
                                   % dropped_tris)
        if nan:
            self._reporter.warning("%d non-finite samples (NaN/Inf) were caught and discarded"
                                   % nan)
        # Statistics go to the console, not to the status bar, where they would replace the warnings
        # that explain an image; named as a user reads them.
        names = {"samples_rejected": "paths ended by a scattered direction below the surface"}
        others = ", ".join("%s %d" % (names.get(k, k.replace("_", " ")), v) for k, v in sorted(counters.items())
                           if k != "nan_caught" and isinstance(v, int) and v)
        if others:
            print("SMIS counters: " + others, flush=True)
        integrator = session.integrator_stats()
        if integrator:
            print("SMIS integrator: " + ", ".join(
                "%s %.4g" % (k.replace("_", " "), v) for k, v in sorted(integrator.items())), flush=True)

        skipped = list(session.skipped())
        parts = ["Cancelled" if p.get("cancelled") or self.break_requested() else "Done",
                 "%d/%d samples" % (p["samples_done"], p["samples_total"]),
                 "%.2f s" % p["elapsed"],
                 "export %.2f s" % export.seconds,
                 "%d tris, %d meshes, %d instances, %d lights"
                 % (export.stats.get("triangles", 0), export.counts.meshes,
                    export.counts.instances, export.counts.lights)]
        if nan:
            parts.append("NaN caught %d" % nan)
        if dropped_tris:
            parts.append("dropped tris %d" % dropped_tris)
        if export.counts.dropped_lights:
            parts.append("dropped lights %d" % export.counts.dropped_lights)
        if skipped:
            parts.append("skipped: " + ", ".join(skipped))
        self.update_stats("", " \u00b7 ".join(parts))


def stats_line(progress, skipped=()):
    """`Sample 12/64 · 1.7 M paths/s · skipped: filtering`: the skipped list is what the
    engine's scene analysis and integrator switched off (RenderSession.skipped())."""
    parts = ["Sample %d/%d" % (progress["samples_done"], progress["samples_total"]),
             "%.1f M paths/s" % (progress["paths_per_second"] / 1e6)]
    if skipped:
        parts.append("skipped: " + ", ".join(skipped))
    return " \u00b7 ".join(parts)


def register():
    bpy.utils.register_class(SMISRenderEngine)


def unregister():
    bpy.utils.unregister_class(SMISRenderEngine)
