"""Build the demo / accuracy scenes as .blend files, using bpy only.

Run:
    blender -b --factory-startup --python scenes/build_scenes.py -- [OUTDIR]

OUTDIR defaults to the folder holding this script (scenes/). Writes:

  cornell.blend          Cornell box (Lambertian walls), 1 area light, a GGX gold
                         sphere (Glossy BSDF) and a GGX glass sphere (Glass BSDF,
                         IOR 1.5, roughness 0). 128x128.
  cornell_diffuse.blend  Same box, diffuse walls + two diffuse boxes, 1 area light
                         (the "Lambertian only" accuracy case). 128x128.
  demo.blend             Cornell box + spheres + box, area + point + spot light,
                         blue-grey world. 320x240.

Every file is saved with render engine CYCLES and Cycles' unbiased settings
(see /work/shared/BLENDER_NOTES.md): all per-type bounce limits = max_bounces = 8,
blur_glossy 0, light_sampling_threshold 0, clamps 0, caustics on, no denoising,
no adaptive sampling, BOX pixel filter of width 1 px.

Units/conventions (measured in Cycles 3.4, see /tmp/cycles_facts/FINDINGS.md):
the area light of power P and area A has radiance P/(4A), one-sided (local -Z).
Lights are NOT visible to camera rays unless the object's `visible_camera` is
True (it defaults to False for light objects in 3.4). In the two Cornell scenes
the area light object has visible_camera = True, so the light shows in the image;
in demo.blend all lights keep the default (invisible to the camera).

Geometry: the box interior is x in [-1, 1], y in [-1, 1], z in [0, 2] (metres);
it is open on the camera side (y = -1). Each wall is a closed box 0.1 m thick
outside the interior; walls touch but never overlap with coplanar visible faces.
"""
import math
import os
import sys

import bpy
import bmesh
from mathutils import Matrix

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import make_cycles_unbiased  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))

WHITE = (0.8, 0.8, 0.8)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
GOLD = (1.0, 0.71, 0.29)

# Cornell area light: rectangle 1.0 x 0.8 m, 2 cm below the ceiling, facing down.
# (Bigger than the classic light on purpose: a 0.6 x 0.5 light made the Cycles
# reference ~2.8x noisier for the same samples because of the glass caustics.)
LIGHT_SIZE = (1.0, 0.8)
LIGHT_POWER = 40.0  # W  -> radiance 40 / (4 * 0.8) = 12.5 W/(m^2 sr)


def out_dir():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    return os.path.abspath(args[0]) if args else HERE


# --------------------------------------------------------------------------
# scene setup helpers
# --------------------------------------------------------------------------
def new_scene(res_x, res_y, samples):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = 'CYCLES'
    sc.render.resolution_x = res_x
    sc.render.resolution_y = res_y
    sc.render.resolution_percentage = 100
    sc.render.film_transparent = False
    c = sc.cycles
    c.device = 'CPU'
    c.samples = samples
    c.preview_samples = 32
    c.seed = 0
    make_cycles_unbiased(sc, max_bounces=8)
    return sc


def set_world(sc, color=(0.0, 0.0, 0.0), strength=1.0):
    w = bpy.data.worlds.new("World")
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*color, 1.0)
    bg.inputs["Strength"].default_value = strength
    sc.world = w
    return w


def _material(name, node_type, **inputs):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for node in list(nt.nodes):
        if node.type != 'OUTPUT_MATERIAL':
            nt.nodes.remove(node)
    out = nt.nodes["Material Output"]
    bsdf = nt.nodes.new(node_type)
    bsdf.location = (-250, 0)
    dist = inputs.pop("distribution", None)
    if dist is not None:
        bsdf.distribution = dist
    for key, val in inputs.items():
        sock = bsdf.inputs[key]
        if isinstance(val, tuple) and len(val) == 3:
            val = (*val, 1.0)
        sock.default_value = val
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    # viewport colour, handy in solid mode
    if "Color" in inputs:
        m.diffuse_color = (*inputs["Color"][:3], 1.0)
    return m


def diffuse(name, color):
    return _material(name, 'ShaderNodeBsdfDiffuse', Color=color, Roughness=0.0)


def glossy_ggx(name, color, roughness):
    return _material(name, 'ShaderNodeBsdfGlossy', distribution='GGX',
                     Color=color, Roughness=roughness)


def glass_ggx(name, ior=1.5, roughness=0.0):
    return _material(name, 'ShaderNodeBsdfGlass', distribution='GGX',
                     Color=(1.0, 1.0, 1.0), Roughness=roughness, IOR=ior)


def link(sc, obj):
    sc.collection.objects.link(obj)
    return obj


def box_object(sc, name, lo, hi, mat):
    """Closed axis-aligned box mesh with its vertices in world space (identity transform)."""
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    cx, cy, cz = [(a + b) / 2 for a, b in zip(lo, hi)]
    sx, sy, sz = [b - a for a, b in zip(lo, hi)]
    bmesh.ops.transform(bm, matrix=Matrix.Translation((cx, cy, cz)) @ Matrix.Diagonal((sx, sy, sz, 1.0)),
                        verts=bm.verts)
    bm.to_mesh(me)
    bm.free()
    me.materials.append(mat)
    return link(sc, bpy.data.objects.new(name, me))


def unit_cube_object(sc, name, mat, location, rotation_z_deg, scale):
    """Unit cube mesh placed by a non-trivial object transform (rotation + non-uniform scale)."""
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    bm.to_mesh(me)
    bm.free()
    me.materials.append(mat)
    ob = link(sc, bpy.data.objects.new(name, me))
    ob.location = location
    ob.rotation_euler = (0.0, 0.0, math.radians(rotation_z_deg))
    ob.scale = scale
    return ob


def sphere_object(sc, name, mat, location, radius, segments=64, rings=32):
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius)
    bm.to_mesh(me)
    bm.free()
    me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
    me.update()
    me.materials.append(mat)
    ob = link(sc, bpy.data.objects.new(name, me))
    ob.location = location
    return ob


def add_light(sc, name, ltype, location, rotation=(0.0, 0.0, 0.0), visible_camera=None, **props):
    ld = bpy.data.lights.new(name, ltype)
    for key, val in props.items():
        setattr(ld, key, val)
    ob = link(sc, bpy.data.objects.new(name, ld))
    ob.location = location
    ob.rotation_euler = rotation
    if visible_camera is not None:
        ob.visible_camera = visible_camera
    return ob


def add_camera(sc, location, rotation_deg, lens, sensor=36.0):
    cd = bpy.data.cameras.new("Camera")
    cd.lens = lens
    cd.sensor_width = sensor
    cd.sensor_fit = 'AUTO'
    cd.clip_start = 0.1
    cd.clip_end = 100.0
    ob = link(sc, bpy.data.objects.new("Camera", cd))
    ob.location = location
    ob.rotation_euler = [math.radians(a) for a in rotation_deg]
    sc.camera = ob
    return ob


# --------------------------------------------------------------------------
# the box
# --------------------------------------------------------------------------
def cornell_box(sc, light_visible_camera=True):
    t = 0.1  # wall thickness
    white = diffuse("White", WHITE)
    red = diffuse("Red", RED)
    green = diffuse("Green", GREEN)
    box_object(sc, "Floor", (-1 - t, -1, -t), (1 + t, 1 + t, 0), white)
    box_object(sc, "Ceiling", (-1 - t, -1, 2), (1 + t, 1 + t, 2 + t), white)
    box_object(sc, "BackWall", (-1, 1, 0), (1, 1 + t, 2), white)
    box_object(sc, "LeftWall", (-1 - t, -1, 0), (-1, 1 + t, 2), red)
    box_object(sc, "RightWall", (1, -1, 0), (1 + t, 1 + t, 2), green)
    add_light(sc, "AreaLight", 'AREA', (0.0, 0.0, 1.98),
              visible_camera=light_visible_camera,
              shape='RECTANGLE', size=LIGHT_SIZE[0], size_y=LIGHT_SIZE[1],
              energy=LIGHT_POWER, color=(1.0, 1.0, 1.0))
    return white


def cornell_camera(sc):
    # looks along +Y into the box through the open side, centred on the box
    return add_camera(sc, (0.0, -3.6, 1.0), (90.0, 0.0, 0.0), lens=42.0)


def build_cornell(path):
    sc = new_scene(128, 128, samples=1024)
    set_world(sc)
    cornell_box(sc)
    sphere_object(sc, "GoldSphere", glossy_ggx("GoldGGX", GOLD, 0.3), (-0.45, 0.35, 0.4), 0.4)
    sphere_object(sc, "GlassSphere", glass_ggx("GlassGGX", 1.5, 0.0), (0.42, -0.3, 0.35), 0.35)
    cornell_camera(sc)
    save(path)


def build_cornell_diffuse(path):
    sc = new_scene(128, 128, samples=1024)
    set_world(sc)
    white = cornell_box(sc)
    # classic tall and short boxes, placed by object transforms
    unit_cube_object(sc, "TallBox", white, (-0.35, 0.3, 0.6), 17.0, (0.55, 0.55, 1.2))
    unit_cube_object(sc, "ShortBox", white, (0.38, -0.32, 0.3), -17.0, (0.55, 0.55, 0.6))
    cornell_camera(sc)
    save(path)


def build_demo(path):
    sc = new_scene(320, 240, samples=128)
    set_world(sc, (0.05, 0.07, 0.1), 1.0)
    white = cornell_box(sc, light_visible_camera=None)  # lights keep Blender's default visibility
    sphere_object(sc, "GoldSphere", glossy_ggx("GoldGGX", GOLD, 0.3), (-0.5, 0.4, 0.4), 0.4)
    sphere_object(sc, "GlassSphere", glass_ggx("GlassGGX", 1.5, 0.0), (0.45, -0.35, 0.35), 0.35)
    unit_cube_object(sc, "Box", white, (0.45, 0.5, 0.45), -20.0, (0.5, 0.5, 0.9))
    add_light(sc, "PointLight", 'POINT', (-0.6, -0.6, 1.6), energy=15.0,
              shadow_soft_size=0.05, color=(1.0, 0.85, 0.7))
    # spot at the upper right front corner, aimed at the gold sphere
    spot = add_light(sc, "SpotLight", 'SPOT', (0.8, -0.8, 1.8), energy=40.0,
                     shadow_soft_size=0.02, spot_size=math.radians(35.0), spot_blend=0.2,
                     color=(0.7, 0.8, 1.0))
    target = (-0.5, 0.4, 0.4)
    d = [a - b for a, b in zip(target, spot.location)]
    from mathutils import Vector
    spot.rotation_euler = Vector(d).to_track_quat('-Z', 'Y').to_euler()
    add_camera(sc, (0.0, -3.4, 1.0), (90.0, 0.0, 0.0), lens=30.0)
    save(path)


def save(path):
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
    print("build_scenes: wrote", path)


def main():
    out = out_dir()
    os.makedirs(out, exist_ok=True)
    build_cornell(os.path.join(out, "cornell.blend"))
    build_cornell_diffuse(os.path.join(out, "cornell_diffuse.blend"))
    build_demo(os.path.join(out, "demo.blend"))


main()
