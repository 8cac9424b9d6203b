"""The render camera -> the engine camera dict.

Only raw Blender values go to the engine (sensor, lens, shift, ...); the
projection itself (Cycles' `blender/camera.cpp` rules for sensor fit and
shift) and removing scale from the matrix are the engine's job, so that there
is one implementation of it.
"""

import numpy as np


class CameraError(Exception):
    """The scene cannot be rendered from its camera (message for the user)."""


def resolution(render):
    """Full output resolution in pixels, after the percentage scale (as Blender computes it)."""
    w = render.resolution_x * render.resolution_percentage // 100
    h = render.resolution_y * render.resolution_percentage // 100
    return max(w, 1), max(h, 1)


def border_window(render, width, height):
    """The render border as a pixel window (x0, y0, x1, y1), [x0, x1) x [y0, y1),
    y from the bottom row; the full frame when the border is off."""
    if not render.use_border:
        return 0, 0, width, height
    # Blender computes `(int)(border.xmin * winx)` in single precision; doing it in
    # double can land one pixel lower (0.9f * 540 is 486 in float, 485.99999 in double)
    # and then disagree with the size of the result Blender allocates.
    f32 = np.float32
    x0 = int(f32(render.border_min_x) * f32(width))
    x1 = int(f32(render.border_max_x) * f32(width))
    y0 = int(f32(render.border_min_y) * f32(height))
    y1 = int(f32(render.border_max_y) * f32(height))
    # Keep at least one pixel, inside the frame, so a degenerate border can't crash.
    x0, y0 = min(max(x0, 0), width - 1), min(max(y0, 0), height - 1)
    x1, y1 = min(max(x1, x0 + 1), width), min(max(y1, y0 + 1), height)
    return x0, y0, x1, y1


def camera_object(engine, scene):
    """The object the render looks through: the engine's override (e.g. a marker-bound
    or command-line camera) when there is one, else the scene camera."""
    obj = engine.camera_override if engine is not None else None
    return obj if obj is not None else scene.camera


def focus_distance(obj, dof, depsgraph):
    """Cycles' blender_camera_focal_distance: the focus object's (or bone's) distance along the
    camera's view axis, else the Distance setting."""
    target = dof.focus_object
    if target is None:
        return float(dof.focus_distance)
    target = target.evaluated_get(depsgraph)
    matrix = target.matrix_world
    bone = getattr(dof, "focus_subtarget", "")
    if bone and target.pose is not None and bone in target.pose.bones:
        matrix = matrix @ target.pose.bones[bone].matrix
    view_axis = obj.matrix_world.col[2].xyz.normalized()
    return abs(view_axis.dot(obj.matrix_world.col[3].xyz - matrix.col[3].xyz))


def depth_of_field(obj, depsgraph):
    """The camera's thin-lens settings for the engine; none when depth of field is off."""
    dof = obj.data.dof
    if not dof.use_dof:
        return {}
    return {
        "fstop": max(float(dof.aperture_fstop), 1e-5),  # Cycles clamps the same way
        "focus_distance": max(focus_distance(obj, dof, depsgraph), 1e-5),
        "aperture_blades": int(dof.aperture_blades),
        "aperture_rotation": float(dof.aperture_rotation),
        "aperture_ratio": float(dof.aperture_ratio),
    }


def export_camera(engine, depsgraph, warn):
    """Camera dict for `_smis.Scene.set_camera`. Raises CameraError."""
    scene = depsgraph.scene
    obj = camera_object(engine, scene)
    if obj is None:
        raise CameraError("Scene has no camera")
    if not obj.is_evaluated:
        obj = obj.evaluated_get(depsgraph)  # animated/constrained transform of this frame
    if obj.type != 'CAMERA':
        raise CameraError("Active camera '%s' is not a camera object" % obj.name)
    cam = obj.data
    if cam.type not in {'PERSP', 'ORTHO'}:
        raise CameraError("Camera '%s': %s cameras are not supported" % (obj.name, cam.type))
    render = scene.render
    width, height = resolution(render)
    return {
        **depth_of_field(obj, depsgraph),
        "type": cam.type,
        "matrix": [list(row) for row in obj.matrix_world],
        "sensor_fit": cam.sensor_fit,
        "sensor_width": float(cam.sensor_width),
        "sensor_height": float(cam.sensor_height),
        "lens": float(cam.lens),
        "ortho_scale": float(cam.ortho_scale),
        "shift_x": float(cam.shift_x),
        "shift_y": float(cam.shift_y),
        "clip_start": float(cam.clip_start),
        "clip_end": float(cam.clip_end),
        "width": width,
        "height": height,
        "pixel_aspect_x": float(render.pixel_aspect_x),
        "pixel_aspect_y": float(render.pixel_aspect_y),
        "border": border_window(render, width, height),
    }
