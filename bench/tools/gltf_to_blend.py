"""Import a glTF 2.0 file (.gltf/.glb) into an empty Blender scene and save it as a .blend a user would
render: Blender's own importer (its node groups, normal maps, texture transforms as Cycles sees them),
a camera looking at the meshes from a diagonal, and a world lit by one of Blender's bundled CC0 studio
HDRIs (glTF files carry no environment). Run by bench/real_scenes.py:

    blender -b --factory-startup --python bench/tools/gltf_to_blend.py -- SRC.glb DST.blend HDRI.exr
"""
import sys

import bpy
import mathutils
import numpy

# Blender 3.4's glTF importer uses numpy.bool, which numpy 1.24 removed.
numpy.bool = bool

src, dst, hdri = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
scene = bpy.context.scene
bpy.context.view_layer.update()

pts = [o.matrix_world @ mathutils.Vector(c) for o in scene.objects if o.type == 'MESH' for c in o.bound_box]
lo = mathutils.Vector([min(p[i] for p in pts) for i in range(3)])
hi = mathutils.Vector([max(p[i] for p in pts) for i in range(3)])
centre, radius = (lo + hi) / 2, max((hi - lo).length / 2, 1e-3)
cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(cam)
# glTF is Y-up and the importer turns it Z-up: look from the front-right, slightly above.
cam.location = centre + mathutils.Vector((0.9, -1.5, 0.6)).normalized() * radius * 2.6
cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
scene.camera = cam
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 640, 480, 100

world = bpy.data.worlds.new("studio")
world.use_nodes = True
nodes, links = world.node_tree.nodes, world.node_tree.links
env = nodes.new("ShaderNodeTexEnvironment")
env.image = bpy.data.images.load(hdri)
links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])
scene.world = world
scene.render.engine = 'CYCLES'
bpy.ops.wm.save_as_mainfile(filepath=dst)
print("gltf_to_blend: %s -> %s (%d meshes)" % (src, dst, sum(1 for o in scene.objects if o.type == 'MESH')))
