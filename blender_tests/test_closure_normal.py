"""The closure normal Cycles 3.4 shades with (issue 20, item 2): every BSDF gets the interpolated
normal turned towards the geometric normal just far enough that the viewer's mirror direction stays
above the surface (svm_node_closure_bsdf's ensure_valid_reflection), not only normals from Bump or
Normal Map nodes. A smooth-shaded closed cylinder with flipped normals, lit and seen from inside,
has interpolated normals that lean far from the faces near its rims; shading with them unturned made
the whole image 7% darker than Cycles (the turned normal also brings the bump shadowing term)."""
import bpy  # noqa: F401
import numpy as np

from conftest import EMPTY_SCENE_AND_MATERIALS, block_mean, matched_settings, render_both

SCENE = EMPTY_SCENE_AND_MATERIALS + matched_settings(48, 36, 256, max_bounces=4) + """
import bmesh
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
bpy.ops.mesh.primitive_cylinder_add(vertices=24, radius=1.0, depth=2.0, end_fill_type='NGON')
cyl = bpy.context.active_object
bm = bmesh.new()
bm.from_mesh(cyl.data)
bmesh.ops.reverse_faces(bm, faces=bm.faces[:])
bm.to_mesh(cyl.data)
bm.free()
for p in cyl.data.polygons:
    p.use_smooth = True
bpy.ops.object.light_add(type='POINT', location=(0.0, -0.3, -0.4))
bpy.context.active_object.data.energy = 60.0
bpy.context.active_object.data.shadow_soft_size = 0.1
cam.location = (0.0, -0.6, 0.55)
cam.rotation_euler = (math.radians(95), 0.0, 0.0)
cam.data.angle = math.radians(110)
"""


def _compare(material_line):
    ours, cycles = (img[..., :3] for img in render_both(SCENE + material_line))
    ratio = float(ours.mean() / cycles.mean())
    a, b = (block_mean(img, 4).mean(-1) for img in (ours, cycles))
    blocks = float(np.abs(a - b).mean() / b.mean())
    return ratio, blocks


def test_flipped_cylinder_diffuse_matches_cycles():
    ratio, blocks = _compare("cyl.data.materials.append(material('Wall', 'ShaderNodeBsdfDiffuse'))\n")
    print("diffuse: image mean ours / Cycles %.4f, 4x4-block relative difference %.4f" % (ratio, blocks))
    # Unturned normals: ratio 0.93 (block difference 7.4% at 160 x 120). 256 spp each: the image
    # mean's noise is far below 1%.
    assert abs(ratio - 1.0) < 0.01, ratio
    assert blocks < 0.03, blocks


def test_flipped_cylinder_glossy_matches_cycles():
    ratio, blocks = _compare(
        "cyl.data.materials.append(material('Wall', 'ShaderNodeBsdfGlossy', Roughness=0.4))\n")
    print("glossy: image mean ours / Cycles %.4f, 4x4-block relative difference %.4f" % (ratio, blocks))
    # Unturned normals: 0.9865 here.
    assert abs(ratio - 1.0) < 0.008, ratio
    assert blocks < 0.03, blocks


def test_flipped_cylinder_node_material_matches_cycles():
    """The same through the node evaluator: a checker of two equal greys keeps the material a program."""
    ratio, blocks = _compare("""
m = material('Wall', 'ShaderNodeBsdfDiffuse')
checker = m.node_tree.nodes.new('ShaderNodeTexChecker')
checker.inputs['Color1'].default_value = checker.inputs['Color2'].default_value = (0.8, 0.8, 0.8, 1.0)
m.node_tree.links.new(checker.outputs['Color'], m.node_tree.nodes['Diffuse BSDF'].inputs['Color'])
cyl.data.materials.append(m)
""")
    print("node material: image mean ours / Cycles %.4f, 4x4-block relative difference %.4f" % (ratio, blocks))
    assert abs(ratio - 1.0) < 0.01, ratio
    assert blocks < 0.03, blocks
