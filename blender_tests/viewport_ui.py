"""Drives Blender's UI (under Xvfb) for test_viewport.py: switches the 3D view to Rendered shading
with SMIS (after a Solid-shading screenshot), waits for the progressive render, screenshots the 3D view, moves the cube, edits
its mesh, its material's checker colour (a node value of a per-hit program) and the lamp's power, screenshotting after each; finally renders the material's preview icon.

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --addons smis_render \\
        --python blender_tests/viewport_ui.py -- OUT_DIR
"""
import os
import sys

import bpy

OUT = sys.argv[sys.argv.index("--") + 1]
WAIT = 4.0  # seconds for the viewport to converge (16 samples at 1/2 resolution on a small view)


def view3d():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                return window, area
    raise RuntimeError("no 3D view")


def screenshot(name):
    window, area = view3d()
    with bpy.context.temp_override(window=window, area=area):
        bpy.ops.screen.screenshot_area(filepath=os.path.join(OUT, name))
    print("SMIS viewport test: screenshot", name, flush=True)


def start():
    screenshot("solid.png")  # Blender's Solid shading, for comparison
    # The cube's material is a node program (a checker on the base colour), so the material edit
    # below is a node value edit of a per-hit program.
    nt = bpy.data.materials["Material"].node_tree
    checker = nt.nodes.new("ShaderNodeTexChecker")
    checker.name = "Checker"
    checker.inputs["Scale"].default_value = 3.0
    nt.links.new(checker.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
    scene = bpy.context.scene
    scene.render.engine = 'SMIS'
    scene.smis.viewport_samples = 16
    _, area = view3d()
    area.spaces.active.shading.type = 'RENDERED'
    print("SMIS viewport test: rendered shading on", flush=True)


def move_cube():
    screenshot("before.png")
    bpy.data.objects["Cube"].location.x += 1.5
    print("SMIS viewport test: moved the cube", flush=True)


def edit_mesh():
    screenshot("moved.png")
    mesh = bpy.data.objects["Cube"].data
    for v in mesh.vertices:
        v.co.z *= 2.0
    mesh.update()
    print("SMIS viewport test: edited the mesh", flush=True)


def edit_material():
    screenshot("edited.png")
    checker = bpy.data.materials["Material"].node_tree.nodes["Checker"]
    checker.inputs["Color1"].default_value = (0.8, 0.05, 0.02, 1.0)
    print("SMIS viewport test: edited the material", flush=True)


def edit_light():
    screenshot("recolored.png")
    bpy.data.lights["Light"].energy *= 4.0
    print("SMIS viewport test: edited the light", flush=True)


def material_preview():
    screenshot("relit.png")
    # The material's preview icon, which Blender renders with the scene's engine (bl_use_preview)
    # when the Material Properties draw it.
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'PROPERTIES':
                area.spaces.active.context = 'MATERIAL'
    bpy.data.materials["Material"].preview_ensure()
    print("SMIS viewport test: material preview requested", flush=True)


def finish():
    preview = bpy.data.materials["Material"].preview
    pixels = list(preview.icon_pixels_float)
    w, h = preview.icon_size
    mean = sum(pixels) / max(len(pixels), 1)
    spread = max(pixels, default=0.0) - min(pixels, default=0.0)
    print("SMIS viewport test: material preview %dx%d mean %.4f range %.4f" % (w, h, mean, spread), flush=True)
    bpy.ops.wm.quit_blender()


STEPS = [start, move_cube, edit_mesh, edit_material, edit_light, material_preview, finish]


def run_next():
    step = STEPS.pop(0)
    try:
        step()
    except Exception as exc:  # the test reads this; a UI session must not hang
        print("SMIS viewport test: FAILED in %s: %r" % (step.__name__, exc), flush=True)
        bpy.ops.wm.quit_blender()
        return None
    if not STEPS:
        return None
    return 8.0 if step is material_preview else WAIT  # the icon renders in a background job


bpy.context.preferences.view.show_splash = False
bpy.app.timers.register(run_next, first_interval=2.0)
