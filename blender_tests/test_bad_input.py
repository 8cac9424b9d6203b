"""Bad input gives a clear message and a valid image (or a clean failure), never a crash or NaN."""
import numpy as np

from conftest import render

SMALL = """
scene.render.resolution_x = 32
scene.render.resolution_y = 24
scene.render.resolution_percentage = 100
scene.smis.samples = 4
"""


def assert_clean_image(run, shape=(24, 32, 4)):
    assert run.returncode == 0, run.output[-3000:]
    img = run.image
    assert img.shape == shape
    assert np.isfinite(img).all()
    return img


def test_scene_without_camera_fails_cleanly():
    run = render(setup=SMALL + "bpy.data.objects.remove(bpy.data.objects['Camera'])\n")
    assert run.returncode == 1, run.output[-3000:]   # an error, reported: a farm sees the failure
    assert "no camera" in run.output.lower()
    assert "Segmentation fault" not in run.output


def test_empty_scene_renders_black_with_a_warning():
    setup = SMALL + """
for ob in list(bpy.data.objects):
    if ob.type != 'CAMERA':
        bpy.data.objects.remove(ob)
scene.world.node_tree.nodes['Background'].inputs['Color'].default_value = (0, 0, 0, 1)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    assert np.all(img[..., :3] == 0.0)
    assert "empty" in run.output.lower()


def test_nan_vertices_are_dropped_and_counted():
    setup = SMALL + """
cube = bpy.data.objects['Cube']
cube.data.vertices[0].co = (float('nan'), 0.0, 0.0)
"""
    run = render(setup=setup)
    assert_clean_image(run)
    assert "dropped" in run.output.lower()


def test_zero_size_and_negative_power_lights_are_skipped_with_a_warning():
    setup = SMALL + """
light = bpy.data.objects['Light']
light.data.energy = -100.0
area = bpy.data.lights.new('Flat', 'AREA')
area.size = 0.0
area.energy = 50.0
ob = bpy.data.objects.new('Flat', area)
scene.collection.objects.link(ob)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    out = run.output
    assert "Light" in out and "negative" in out.lower()
    assert "Flat" in out and "size" in out.lower()
    # Only the world lights the scene now; the image is still valid.
    assert img[..., :3].max() >= 0.0


def test_unsupported_node_falls_back_with_one_warning_naming_it():
    setup = SMALL + """
mat = bpy.data.materials.new('Noisy')
mat.use_nodes = True
nt = mat.node_tree
bsdf = nt.nodes['Principled BSDF']
# Eevee's Specular BSDF: not a Cycles closure (the Toon BSDF and then the Hair BSDF, used here before, now are)
spec = nt.nodes.new('ShaderNodeEeveeSpecular')
nt.links.new(spec.outputs[0], nt.nodes['Material Output'].inputs['Surface'])
bpy.data.objects['Cube'].data.materials.clear()
bpy.data.objects['Cube'].data.materials.append(mat)
"""
    run = render(setup=setup)
    img = assert_clean_image(run)
    lines = [l for l in run.output.splitlines() if "Noisy" in l and "Specular" in l]
    assert len(lines) == 1, run.output[-3000:]
    assert img[..., :3].max() > 0.0  # the fallback diffuse is lit


# Shader nodes fed with bad input: the default cube's material (an emission so the value shows in the
# image without lighting noise) gets the node set-up of each case.
NODE_CASE = SMALL + """
cube = bpy.data.objects['Cube']
mat = bpy.data.materials.new('Bad')
mat.use_nodes = True
nt = mat.node_tree
nt.nodes.clear()
out = nt.nodes.new('ShaderNodeOutputMaterial')
emit = nt.nodes.new('ShaderNodeEmission')
nt.links.new(emit.outputs[0], out.inputs['Surface'])
cube.data.materials.clear()
cube.data.materials.append(mat)
"""


def test_missing_image_renders_magenta_with_a_warning_naming_the_file():
    run = render(setup=NODE_CASE + """
img = bpy.data.images.new('brick_wall', 4, 4)  # then pointed at a file that is not there
img.source = 'FILE'
img.filepath = '/nonexistent/folder/brick_wall.png'
img.reload()
tex = nt.nodes.new('ShaderNodeTexImage')
tex.image = img
nt.links.new(tex.outputs['Color'], emit.inputs['Color'])
""")
    img = assert_clean_image(run)
    centre = img[10:14, 14:18, :3].reshape(-1, 3)
    np.testing.assert_allclose(centre, np.broadcast_to([1.0, 0.0, 1.0], centre.shape), atol=1e-6)
    warnings = [l for l in run.output.splitlines() if "brick_wall" in l]
    assert warnings and "magenta" in warnings[0], run.output[-3000:]


def test_normal_map_on_ngons_falls_back_with_a_warning_naming_the_object():
    # MikkTSpace (Blender's calc_tangents) refuses faces of more than four corners: the mesh still
    # renders, its normal map on per-triangle tangents, and the warning says so and names it.
    run = render(setup=NODE_CASE + """
bpy.ops.mesh.primitive_cylinder_add(vertices=8)   # its caps are octagons
cyl = bpy.context.active_object
cube.data = cyl.data
bpy.data.objects.remove(cyl)
me = cube.data
me.materials.append(mat)
assert max(len(p.vertices) for p in me.polygons) > 4
nmap = nt.nodes.new('ShaderNodeNormalMap')
nmap.inputs['Color'].default_value = (0.7, 0.5, 0.9, 1.0)
vm = nt.nodes.new('ShaderNodeVectorMath')
vm.operation = 'ABSOLUTE'
nt.links.new(nmap.outputs['Normal'], vm.inputs[0])
nt.links.new(vm.outputs['Vector'], emit.inputs['Color'])
""")
    img = assert_clean_image(run)
    assert img[..., :3].max() > 0.1, "the cube should show its normals"
    warnings = [l for l in run.output.splitlines() if "more than four corners" in l]
    assert warnings and "'Cube'" in warnings[0], run.output[-3000:]


def test_bad_node_values_never_reach_the_film():
    # Division by zero, the logarithm of a negative, a power of a negative, absurd scales and a NaN
    # socket value, all into the emission: finite pixels, the safe maths' values as in Cycles.
    run = render(setup=NODE_CASE + """
def math(op, a, b):
    n = nt.nodes.new('ShaderNodeMath')
    n.operation = op
    n.inputs[0].default_value = a
    n.inputs[1].default_value = b
    return n
div = math('DIVIDE', 1.0, 0.0)
log = math('LOGARITHM', -2.0, 10.0)
pw = math('POWER', -2.0, 0.5)
coord = nt.nodes.new('ShaderNodeTexCoord')
noise = nt.nodes.new('ShaderNodeTexNoise')
noise.inputs['Scale'].default_value = 1e30
noise.inputs['Detail'].default_value = float('nan')
nt.links.new(coord.outputs['Object'], noise.inputs['Vector'])
add1 = nt.nodes.new('ShaderNodeMath'); add1.operation = 'ADD'
add2 = nt.nodes.new('ShaderNodeMath'); add2.operation = 'ADD'
add3 = nt.nodes.new('ShaderNodeMath'); add3.operation = 'ADD'
nt.links.new(div.outputs[0], add1.inputs[0]); nt.links.new(log.outputs[0], add1.inputs[1])
nt.links.new(add1.outputs[0], add2.inputs[0]); nt.links.new(pw.outputs[0], add2.inputs[1])
nt.links.new(add2.outputs[0], add3.inputs[0]); nt.links.new(noise.outputs['Fac'], add3.inputs[1])
nt.links.new(add3.outputs[0], emit.inputs['Strength'])
emit.inputs['Color'].default_value = (1e30, float('nan'), 1.0, 1.0)
""")
    assert_clean_image(run)


def test_node_group_without_output_renders_black_with_a_warning():
    run = render(setup=NODE_CASE + """
group = bpy.data.node_groups.new('NoOutput', 'ShaderNodeTree')
group.outputs.new('NodeSocketColor', 'Color')
g = nt.nodes.new('ShaderNodeGroup')
g.node_tree = group
nt.links.new(g.outputs[0], emit.inputs['Color'])
""")
    img = assert_clean_image(run)
    assert np.all(img[10:14, 14:18, :3] == 0.0)
    assert any("Group Output" in l for l in run.output.splitlines()), run.output[-3000:]


def test_zero_scale_and_nan_objects_are_skipped_by_name():
    # One object scaled to zero (hidden in an animation) and one with a NaN location: both are
    # named in one warning and the rest of the scene (the default cube) still renders.
    run = render(setup=SMALL + """
bpy.ops.mesh.primitive_uv_sphere_add(location=(0, 0, 3))
bpy.context.active_object.name = 'Flattened'
bpy.context.active_object.scale = (0.0, 0.0, 0.0)
bpy.ops.mesh.primitive_cone_add(location=(0, 3, 0))
bpy.context.active_object.name = 'Broken'
bpy.context.active_object.location = (float('nan'), 0.0, 0.0)
""")
    img = assert_clean_image(run)
    assert img[10:14, 14:18, :3].max() > 0.0  # the cube is there
    skipped = [l for l in run.output.splitlines() if "Skipped" in l]
    assert len(skipped) == 1 and "'Flattened'" in skipped[0] and "'Broken'" in skipped[0], run.output[-3000:]
