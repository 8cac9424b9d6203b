"""Camera depth of field from Blender's camera settings (f-stop, focus object or distance)."""
import numpy as np

from conftest import block_mean, render

DOF = """
scene.render.resolution_x = scene.render.resolution_y = 48
scene.smis.samples = 16
scene.smis.seed = 2
cam = scene.camera.data
cam.dof.use_dof = True
cam.dof.aperture_fstop = 0.2
"""


def test_focus_object_is_sharp_and_near_focus_blurs_it():
    focused = render(setup=DOF + "cam.dof.focus_object = bpy.data.objects['Cube']\n")
    blurred = render(setup=DOF + "cam.dof.focus_distance = 2.0\n")
    pinhole = render(setup=DOF + "cam.dof.use_dof = False\n")
    for run in (focused, blurred, pinhole):
        assert run.returncode == 0, run.output[-2000:]
    ref = block_mean(pinhole.image[..., :3], 4)
    sharp = np.abs(block_mean(focused.image[..., :3], 4) - ref).mean()
    soft = np.abs(block_mean(blurred.image[..., :3], 4) - ref).mean()
    # Focused on the cube (f/0.2, a 12.5 cm aperture radius), the image stays close to the pinhole
    # render: only the cube's faces off the focus plane blur a little. Focused 2 m in front of the
    # camera, the cube 11 m away blurs over about 7 pixels (thin-lens circle of confusion).
    print(f"mean |difference| from the pinhole render: focused {sharp:.4f}, defocused {soft:.4f}")
    assert soft > 3.0 * sharp, (sharp, soft)
