"""A scene lit only by an HDRI World (issue 18): a diffuse sphere, a glossy (GGX 0.25) sphere and a
diffuse floor under Blender's bundled CC0 studio light `sunset.exr` (1024 x 512, a low sun), turned by
a Mapping node (Texture Coordinate Generated -> Mapping rotation -> Environment Texture -> Background).
The camera sees the environment above the horizon. 96 x 72 pixels, Cycles' unbiased settings
(scenes/cycles_settings.py, max bounces 8), BOX filter 1 px, World importance sampling AUTOMATIC.

In a Blender session (the Blender test builds the scene this way before rendering with SMIS):
    exec(open("scenes/world_hdri.py").read()); build(bpy.context.scene)

As a script, the Cycles reference render (see scenes/make_world_reference.sh):
    blender -b --factory-startup --python scenes/world_hdri.py -- OUT.exr SAMPLES SEED
"""
import json
import math
import os
import sys
import time

import bpy

HDRI = "/usr/share/blender/datafiles/studiolights/world/sunset.exr"
MAPPING_ROTATION = (0.15, 0.0, 2.2)  # radians, XYZ Euler
WIDTH, HEIGHT = 96, 72


def _material(name, node_type, **inputs):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    for n in list(nt.nodes):
        if n.bl_idname != "ShaderNodeOutputMaterial":
            nt.nodes.remove(n)
    bsdf = nt.nodes.new(node_type)
    for key, value in inputs.items():
        bsdf.inputs[key].default_value = value
    if node_type == "ShaderNodeBsdfGlossy":
        bsdf.distribution = "GGX"
    nt.links.new(bsdf.outputs[0], nt.nodes["Material Output"].inputs["Surface"])
    return mat


def _sphere(name, location, radius, mat):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=radius, location=location)
    obj = bpy.context.active_object
    obj.name = name
    bpy.ops.object.shade_smooth()
    obj.data.materials.append(mat)
    return obj


def build(sc):
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    sc.render.resolution_x, sc.render.resolution_y = WIDTH, HEIGHT
    sc.render.resolution_percentage = 100
    sc.view_settings.view_transform = "Standard"
    sc.view_settings.look = "None"

    floor = _material("Floor", "ShaderNodeBsdfDiffuse", Color=(0.5, 0.5, 0.5, 1.0))
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0.0, 0.0, 0.0))
    bpy.context.active_object.data.materials.append(floor)
    _sphere("Diffuse", (-0.7, 0.0, 0.6), 0.6, _material("Clay", "ShaderNodeBsdfDiffuse", Color=(0.8, 0.45, 0.25, 1.0)))
    _sphere("Glossy", (0.75, 0.35, 0.6), 0.6,
            _material("Metal", "ShaderNodeBsdfGlossy", Color=(0.9, 0.9, 0.9, 1.0), Roughness=0.25))

    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 30.0
    cam = bpy.data.objects.new("Camera", cam_data)
    sc.collection.objects.link(cam)
    cam.location = (0.0, -4.2, 1.5)
    cam.rotation_euler = (math.radians(78.0), 0.0, 0.0)
    sc.camera = cam

    world = bpy.data.worlds.new("HDRI")
    sc.world = world
    world.use_nodes = True
    nt = world.node_tree
    background = nt.nodes["Background"]
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(HDRI, check_existing=True)
    coords = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = MAPPING_ROTATION
    nt.links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    nt.links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    nt.links.new(env.outputs["Color"], background.inputs["Color"])
    background.inputs["Strength"].default_value = 1.0
    world.cycles.sampling_method = "AUTOMATIC"


def _render_cycles():
    args = sys.argv[sys.argv.index("--") + 1:]
    out, samples = os.path.abspath(args[0]), int(args[1])
    seed = int(args[2]) if len(args) > 2 else 0
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from cycles_settings import make_cycles_unbiased

    sc = bpy.context.scene
    build(sc)
    sc.render.engine = "CYCLES"
    c = sc.cycles
    c.max_bounces = 8
    make_cycles_unbiased(sc)
    c.samples = samples
    c.seed = seed
    c.use_animated_seed = False
    sc.render.film_transparent = False
    im = sc.render.image_settings
    im.file_format = "OPEN_EXR"
    im.color_mode = "RGBA"
    im.color_depth = "32"
    sc.render.use_file_extension = False
    sc.render.filepath = out
    t0 = time.time()
    bpy.ops.render.render(write_still=True)
    meta = {"scene": "scenes/world_hdri.py", "hdri": HDRI, "mapping_rotation": MAPPING_ROTATION,
            "output": out, "engine": "CYCLES 3.4 CPU", "samples": samples, "seed": seed,
            "max_bounces": c.max_bounces, "world_sampling": sc.world.cycles.sampling_method,
            "resolution": [sc.render.resolution_x, sc.render.resolution_y], "pixel_filter": "BOX 1.0 px",
            "render_seconds": round(time.time() - t0, 2), "blender": bpy.app.version_string}
    with open(out + ".json", "w") as f:
        json.dump(meta, f, indent=2)


# Only when Blender runs this file itself (not when another script exec()s it).
if os.path.basename(globals().get("__file__", "")) == "world_hdri.py":
    _render_cycles()
