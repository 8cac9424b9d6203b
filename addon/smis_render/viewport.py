"""Interactive viewport rendering (Rendered shading in the 3D view).

view_update (after edits): re-export what changed (sync/viewport.py) and restart a
progressive session. view_draw (redraws, navigation): when the view moved, restart
with the new camera on the same engine scene; draw the session's current image
through Blender's display transform with the `gpu` module, and ask for another
redraw until the session has all its samples.
"""

import time

import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from . import native, properties
from .sync import ExportError, viewport as sync_viewport
from .sync.reports import Reporter, recent_warnings


class ViewportRenderer:
    def __init__(self):
        self.sync = sync_viewport.ViewportSync()
        # Console and the header's warning count: viewport warnings must not pop up on every edit.
        self.reporter = Reporter(None, source="viewport")
        self.export = None
        self.session = None
        self.camera = None
        self.error = None
        self._texture = None
        self._uploaded = None  # (samples done, size, exposure) of the image in _texture

    # -- view_update ---------------------------------------------------------------

    def update(self, context, depsgraph):
        edited = self.export is not None
        if edited:
            self.sync.invalidate(depsgraph)
        self.stop()
        self.camera = self._camera(context, depsgraph.scene)
        try:
            self.export = self.sync.build(native.load(), depsgraph, self.reporter, self.camera, edited)
            self.export.scene.set_camera(self.camera)
            self.error = None
        except (RuntimeError, ExportError, ValueError) as exc:
            self.export, self.error = None, str(exc)
            return
        print("SMIS viewport: scene sync %.1f ms, %d meshes exported, %d cached, %s"
              % (1000 * self.sync.last_seconds, self.sync.last_exported, len(self.sync.cache),
                 "updated in place" if self.sync.last_in_place else "new engine scene"))
        self._start(depsgraph.scene)

    # -- view_draw -----------------------------------------------------------------

    def draw(self, engine, context, depsgraph):
        scene = depsgraph.scene
        if self.export is None:
            engine.update_stats("", "SMIS: " + (self.error or "waiting for the scene"))
            return
        camera = self._camera(context, scene)
        if camera != self.camera:  # navigation: same scene, new view
            self.stop()
            self.export.scene.set_camera(camera)
            self.camera = camera
            self._start(scene)
        progress = self.session.progress()
        self._upload(properties.film_exposure(scene))
        if self._texture is not None:
            gpu.state.blend_set('ALPHA_PREMULT')
            engine.bind_display_space_shader(scene)
            draw_texture_2d(self._texture, (0, 0), context.region.width, context.region.height)
            engine.unbind_display_space_shader()
            gpu.state.blend_set('NONE')
        from .engine import stats_line  # engine imports this module
        warned = len(recent_warnings["viewport"])
        engine.update_stats("", (stats_line(progress, self.session.skipped())
                                 + ("" if not warned else " · %d warning%s (Render Properties > SMIS Warnings)"
                                    % (warned, "" if warned == 1 else "s")))
                            + " \u00b7 sync %.0f ms (%d meshes exported)"
                            % (1000 * self.sync.last_seconds, self.sync.last_exported))
        if not progress["finished"]:
            time.sleep(0.02)  # let the render threads work between redraws
            engine.tag_redraw()

    def _upload(self, exposure=1.0):
        progress = self.session.progress()
        key = (progress["samples_done"], self.camera["width"], self.camera["height"], exposure)
        if key == self._uploaded or progress["samples_done"] == 0:
            return
        pixels = np.array(self.session.pixels(), dtype=np.float32)  # a copy: scaled below
        pixels[..., :3] *= np.float32(exposure)  # Film > Exposure, as in a final render
        h, w = pixels.shape[:2]
        buffer = gpu.types.Buffer('FLOAT', w * h * 4, pixels.reshape(-1))
        self._texture = gpu.types.GPUTexture((w, h), format='RGBA16F', data=buffer)
        self._uploaded = key

    # -- sessions ------------------------------------------------------------------

    def _camera(self, context, scene):
        divider = max(1, scene.smis.viewport_resolution_divider)
        w = max(1, context.region.width // divider)
        h = max(1, context.region.height // divider)
        return sync_viewport.view_camera(context.region, context.region_data, w, h)

    def _start(self, scene):
        settings = properties.session_settings(scene)
        settings.update(samples=scene.smis.viewport_samples, time_limit=0.0, aux_passes=False)
        self.session = native.load().RenderSession(self.export.scene, settings)
        # The uploaded image's key counts samples: a new session that finishes before the next
        # redraw would match the old one's key and never be drawn.
        self._uploaded = None
        self.session.start()

    def stop(self):
        if self.session is not None:
            self.session.cancel()
            self.session.wait(10.0)
            self.session = None
