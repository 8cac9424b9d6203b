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
  psf_glossy.blend       Path-space filtering comparison, glossy-heavy (after West et
                         al. 2020, Fig. 4): GGX objects of roughness 0.05-0.6 (spheres,
                         a torus, tall thin cylinders, small beveled cubes and rods,
                         a Principled plastic and a Mix Shader sphere) on a diffuse
                         floor before a diffuse back wall; 3 area lights (invisible to
                         the camera), dim world. 256x256.
  many_lights.blend      Many-light direct illumination (ReSTIR, issue 8): a courtyard
                         floor with pillars under a slatted pergola, 144 small area
                         lights above the slats and 160 small emissive quads (320
                         emitting triangles) among the pillars and on the walls, in
                         varied colours and powers, dim world. 128x128.
  psf_room.blend         Path-space filtering comparison, mostly diffuse (after Fig. 5):
                         a closed room seen from inside, a box table with a glossy
                         (Principled) top, diffuse cabinet/stool/vase/ball, a picture,
                         small glossy wall-socket and switch plates, a metal ball;
                         2 ceiling area lights (invisible to the camera). 256x256.

  spectral_gold.blend    Spectral rendering (after West et al. 2020, Fig. 8): a glossy
                         (GGX 0.25) torus knot-like torus, a sphere and a cube of measured
                         gold (material.smis.metal = Au, Glossy colour white) on a grey
                         floor before a grey wall, lit only by two F10 area lights
                         (light.smis.spectrum = F10, spiky SPD). 128x128.
  spectral_glass.blend   Spectral rendering (after Fig. 9): sharp glass objects of
                         slightly dispersive glasses (N-BK7 and F2 Sellmeier spheres, an
                         Abbe-number cube) and a dense-flint N-SF11 prism on a grey floor
                         before a dark wall of thin vertical D65 emissive slits (the
                         high-contrast backdrop that shows dispersion as spectra and
                         coloured fringes), lit by two D65 area lights. 128x128.
                         The smis properties are written by registering the add-on's
                         spectral_properties module (no native module needed).

  volume_planes, volume_spot, volume_slit, volume_thin_hg, volume_beams,
  volume_searchlights, volume_stage
                         Single scattering (max_bounces 1, Cycles' volume bounces 0) for
                         photon planes against the path tracer and Cycles at 512x384
                         (bench/single_scattering_equal_time.py); each builder says what
                         its scene tests.

Only some scenes:  blender -b --factory-startup --python scenes/build_scenes.py -- [OUTDIR] psf_glossy psf_room
(arguments that name a scene select it; any other argument is OUTDIR).

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

# Path-space filtering scenes, powers chosen by rendering (PATH, Filmic view): median pixel
# luminance about 0.35 (psf_glossy) and 0.32 (psf_room), nothing clipped but the highlights.
PSF_GLOSSY_LIGHTS = (85.0, 45.0, 20.0)  # W: key 1.2x0.6 m, fill 0.8x0.8 m, rim disk 0.5 m
PSF_ROOM_LIGHT_POWER = 45.0  # W for each 0.5x0.5 m ceiling light


def _script_args():
    argv = sys.argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


def out_dir():
    args = [a for a in _script_args() if a not in SCENE_NAMES]
    return os.path.abspath(args[0]) if args else HERE


def selected_scenes():
    """Scene names given on the command line, or every scene."""
    names = [a for a in _script_args() if a in SCENE_NAMES]
    return names or list(SCENE_NAMES)


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


def _node_material(name):
    """A new material whose node tree holds only its Material Output: (material, tree, output)."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nt = m.node_tree
    for node in list(nt.nodes):
        if node.type != 'OUTPUT_MATERIAL':
            nt.nodes.remove(node)
    return m, nt, nt.nodes["Material Output"]


def _bsdf_node(nt, node_type, inputs, location):
    """A BSDF node with its distribution and input values set (RGB tuples get alpha 1)."""
    bsdf = nt.nodes.new(node_type)
    bsdf.location = location
    inputs = dict(inputs)
    dist = inputs.pop("distribution", None)
    if dist is not None:
        bsdf.distribution = dist
    for key, val in inputs.items():
        bsdf.inputs[key].default_value = (*val, 1.0) if isinstance(val, tuple) and len(val) == 3 else val
    return bsdf


def _material(name, node_type, **inputs):
    m, nt, out = _node_material(name)
    bsdf = _bsdf_node(nt, node_type, inputs, (-250, 0))
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


def bmesh_object(sc, name, mat, bm, location, rotation_z_deg, scale=(1.0, 1.0, 1.0)):
    """Object of the mesh in `bm` (freed here) placed by an object transform (turn about z, scale)."""
    me = bpy.data.meshes.new(name)
    bm.to_mesh(me)
    bm.free()
    me.materials.append(mat)
    ob = link(sc, bpy.data.objects.new(name, me))
    ob.location = location
    ob.rotation_euler = (0.0, 0.0, math.radians(rotation_z_deg))
    ob.scale = scale
    return ob


def unit_cube_object(sc, name, mat, location, rotation_z_deg, scale):
    """Unit cube mesh placed by a non-trivial object transform (rotation + non-uniform scale)."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    return bmesh_object(sc, name, mat, bm, location, rotation_z_deg, scale)


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


# --------------------------------------------------------------------------
# path-space filtering scenes (West et al. 2020, Sec. 4.4, Figs. 4-6)
# --------------------------------------------------------------------------
def mix_material(name, fac, first, second):
    """Mix Shader of two BSDF nodes; `first`/`second` are (node_type, {input: value})."""
    m, nt, out = _node_material(name)
    mix = nt.nodes.new('ShaderNodeMixShader')
    mix.inputs["Fac"].default_value = fac
    for slot, (node_type, inputs) in ((1, first), (2, second)):
        bsdf = _bsdf_node(nt, node_type, inputs, (-300, 150 - 300 * (slot - 1)))
        nt.links.new(bsdf.outputs[0], mix.inputs[slot])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    return m


def principled(name, base, metallic, roughness, specular=0.5):
    m = _material(name, 'ShaderNodeBsdfPrincipled', distribution='GGX',
                  **{"Base Color": base, "Metallic": metallic, "Roughness": roughness,
                     "Specular": specular})
    m.diffuse_color = (*base, 1.0)
    return m


def _finish_mesh(sc, name, bm, mat, location=(0.0, 0.0, 0.0), rotation_deg=(0.0, 0.0, 0.0),
                 smooth=False, auto_smooth_deg=35.0):
    """Mesh object from a bmesh; smooth shading with auto smooth keeps hard edges hard."""
    me = bpy.data.meshes.new(name)
    bm.to_mesh(me)
    bm.free()
    if smooth:
        me.polygons.foreach_set("use_smooth", [True] * len(me.polygons))
        me.use_auto_smooth = True
        me.auto_smooth_angle = math.radians(auto_smooth_deg)
    me.update()
    me.materials.append(mat)
    ob = link(sc, bpy.data.objects.new(name, me))
    ob.location = location
    ob.rotation_euler = [math.radians(a) for a in rotation_deg]
    return ob


def cylinder_object(sc, name, mat, location, radius, depth, rotation_deg=(0.0, 0.0, 0.0), segments=32):
    """Closed cylinder along local Z, centred on `location`."""
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, cap_tris=False, segments=segments,
                          radius1=radius, radius2=radius, depth=depth)
    return _finish_mesh(sc, name, bm, mat, location, rotation_deg, smooth=True)


def torus_object(sc, name, mat, location, major, minor, rotation_deg=(0.0, 0.0, 0.0),
                 major_segments=64, minor_segments=24):
    """Torus around local Z (ring radius `major`, tube radius `minor`), smooth shaded."""
    bm = bmesh.new()
    rings = []
    for i in range(major_segments):
        u = 2.0 * math.pi * i / major_segments
        ring = []
        for j in range(minor_segments):
            v = 2.0 * math.pi * j / minor_segments
            r = major + minor * math.cos(v)
            ring.append(bm.verts.new((r * math.cos(u), r * math.sin(u), minor * math.sin(v))))
        rings.append(ring)
    for i in range(major_segments):
        a, b = rings[i], rings[(i + 1) % major_segments]
        for j in range(minor_segments):
            k = (j + 1) % minor_segments
            bm.faces.new((a[j], b[j], b[k], a[k]))
    bm.normal_update()
    return _finish_mesh(sc, name, bm, mat, location, rotation_deg, smooth=True, auto_smooth_deg=180.0)


def beveled_cube_object(sc, name, mat, location, size, rotation_deg=(0.0, 0.0, 0.0), bevel=0.2,
                        segments=3):
    """Cube of edge `size` with rounded edges (bevel as a fraction of the edge)."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=size)
    bmesh.ops.bevel(bm, geom=list(bm.verts) + list(bm.edges), offset=bevel * size, offset_type='OFFSET',
                    segments=segments, profile=0.5, affect='EDGES', clamp_overlap=True)
    return _finish_mesh(sc, name, bm, mat, location, rotation_deg, smooth=True, auto_smooth_deg=50.0)


def aim(ob, target):
    """Point the object's local -Z (a light's or camera's forward axis) at `target`, Y up."""
    from mathutils import Vector
    d = Vector(target) - Vector(ob.location)
    ob.rotation_euler = d.to_track_quat('-Z', 'Y').to_euler()
    return ob


def build_psf_glossy(path):
    """Glossy-heavy scene: GGX roughness 0.05 ... 0.6, small glossy details, 3 area lights."""
    sc = new_scene(256, 256, samples=1024)
    set_world(sc, (0.02, 0.022, 0.026), 1.0)  # dim, so open directions are not pitch black
    t = 0.1
    floor = diffuse("FloorGrey", (0.45, 0.45, 0.45))
    wall = diffuse("WallWarm", (0.7, 0.62, 0.52))
    box_object(sc, "Floor", (-4.0, -4.0, -t), (4.0, 2.0 + t, 0.0), floor)
    box_object(sc, "BackWall", (-4.0, 2.0, 0.0), (4.0, 2.0 + t, 3.5), wall)

    # large glossy objects, roughness from 0.05 to 0.6
    sphere_object(sc, "GoldSphere", glossy_ggx("GoldGGX005", GOLD, 0.05), (-0.95, 0.55, 0.42), 0.42)
    sphere_object(sc, "CopperSphere", glossy_ggx("CopperGGX035", (0.95, 0.64, 0.54), 0.35),
                  (0.98, 0.7, 0.38), 0.38)
    torus_object(sc, "SilverTorus", glossy_ggx("SilverGGX015", (0.92, 0.92, 0.95), 0.15),
                 (0.08, 0.7, 0.42), 0.32, 0.09, rotation_deg=(90.0, 0.0, 20.0))
    cylinder_object(sc, "TallRodRough", glossy_ggx("BlueGGX060", (0.55, 0.68, 0.9), 0.6),
                    (-0.38, 1.35, 0.8), 0.06, 1.6)
    cylinder_object(sc, "TallRodSmooth", glossy_ggx("SteelGGX025", (0.8, 0.8, 0.82), 0.25),
                    (0.55, 1.45, 0.65), 0.045, 1.3)
    sphere_object(sc, "PlasticSphere", principled("BluePlastic", (0.08, 0.2, 0.55), 0.0, 0.2),
                  (0.42, -0.05, 0.24), 0.24)
    sphere_object(sc, "RedVarnish", mix_material(
        "RedVarnish", 0.35,
        ('ShaderNodeBsdfDiffuse', {"Color": (0.6, 0.08, 0.05)}),
        ('ShaderNodeBsdfGlossy', {"distribution": 'GGX', "Color": (0.9, 0.9, 0.9), "Roughness": 0.1})),
        (-0.45, -0.25, 0.2), 0.2)

    # small glossy details: beveled cubes and thin rods on the floor, in front
    cubes = [((-1.0, -0.5, 0.08), 20.0, glossy_ggx("CubeGGX010", (0.95, 0.8, 0.5), 0.1)),
             ((-0.75, -0.72, 0.08), -35.0, principled("CubeMetal020", (0.9, 0.6, 0.45), 1.0, 0.2)),
             ((0.05, -0.55, 0.08), 10.0, glossy_ggx("CubeGGX040", (0.85, 0.85, 0.88), 0.4)),
             ((0.85, -0.42, 0.08), 45.0, glossy_ggx("CubeGGX005", (0.7, 0.85, 0.7), 0.05))]
    for i, (loc, rz, mat) in enumerate(cubes):
        beveled_cube_object(sc, "SmallCube%d" % i, mat, loc, 0.16, rotation_deg=(0.0, 0.0, rz))
    rod = glossy_ggx("RodGGX008", (0.9, 0.88, 0.85), 0.08)
    for i, (x, y, rz) in enumerate([(0.45, -0.85, 70.0), (0.6, -0.8, 80.0), (0.75, -0.78, 95.0)]):
        cylinder_object(sc, "FloorRod%d" % i, rod, (x, y, 0.022), 0.022, 0.6,
                        rotation_deg=(90.0, 0.0, rz), segments=16)
    cylinder_object(sc, "LeaningRod", glossy_ggx("RodGGX030", (0.95, 0.7, 0.4), 0.3),
                    (-1.35, 0.35, 0.45), 0.025, 1.0, rotation_deg=(0.0, 25.0, 10.0), segments=16)

    # two area lights from the top (warm and cool) and a small one at the back
    aim(add_light(sc, "AreaKey", 'AREA', (-1.7, -0.8, 2.6), shape='RECTANGLE', size=1.2, size_y=0.6,
                  energy=PSF_GLOSSY_LIGHTS[0], color=(1.0, 0.9, 0.78)), (-0.2, 0.5, 0.3))
    aim(add_light(sc, "AreaFill", 'AREA', (1.9, 0.0, 2.2), shape='SQUARE', size=0.8,
                  energy=PSF_GLOSSY_LIGHTS[1], color=(0.78, 0.86, 1.0)), (0.3, 0.6, 0.3))
    aim(add_light(sc, "AreaRim", 'AREA', (0.2, 1.7, 2.4), shape='DISK', size=0.5,
                  energy=PSF_GLOSSY_LIGHTS[2], color=(1.0, 1.0, 1.0)), (0.0, 0.4, 0.3))

    cam = add_camera(sc, (0.0, -3.0, 1.3), (0.0, 0.0, 0.0), lens=38.0)
    aim(cam, (0.0, 0.25, 0.45))
    save(path)


def build_psf_room(path):
    """Mostly diffuse closed room, a few glossy objects, lit by 2 ceiling area lights."""
    sc = new_scene(256, 256, samples=1024)
    set_world(sc)  # black: the room is closed anyway
    t = 0.1
    x0, x1, y0, y1, h = -2.0, 2.0, -2.2, 2.2, 2.6
    ceiling = diffuse("Ceiling", (0.8, 0.8, 0.8))
    plaster = diffuse("Plaster", (0.72, 0.68, 0.6))
    accent = diffuse("AccentBlue", (0.35, 0.5, 0.62))
    floor = diffuse("FloorWood", (0.42, 0.3, 0.2))
    box_object(sc, "Floor", (x0 - t, y0 - t, -t), (x1 + t, y1 + t, 0.0), floor)
    box_object(sc, "Ceiling", (x0 - t, y0 - t, h), (x1 + t, y1 + t, h + t), ceiling)
    box_object(sc, "BackWall", (x0, y1, 0.0), (x1, y1 + t, h), plaster)
    box_object(sc, "FrontWall", (x0, y0 - t, 0.0), (x1, y0, h), plaster)
    box_object(sc, "LeftWall", (x0 - t, y0 - t, 0.0), (x0, y1 + t, h), accent)
    box_object(sc, "RightWall", (x1, y0 - t, 0.0), (x1 + t, y1 + t, h), plaster)

    # table from boxes, glossy varnished top
    top = principled("TableTopVarnish", (0.3, 0.14, 0.06), 0.0, 0.12)
    legs = diffuse("TableLegs", (0.18, 0.12, 0.08))
    tx0, tx1, ty0, ty1, tz = -1.0, 0.6, 0.3, 1.3, 0.74
    box_object(sc, "TableTop", (tx0, ty0, tz), (tx1, ty1, tz + 0.04), top)
    for i, (lx, ly) in enumerate([(tx0 + 0.05, ty0 + 0.05), (tx1 - 0.1, ty0 + 0.05),
                                  (tx0 + 0.05, ty1 - 0.1), (tx1 - 0.1, ty1 - 0.1)]):
        box_object(sc, "TableLeg%d" % i, (lx, ly, 0.0), (lx + 0.05, ly + 0.05, tz), legs)

    # diffuse objects
    box_object(sc, "Cabinet", (1.35, 0.6, 0.0), (x1, 2.0, 0.9), diffuse("CabinetWhite", (0.75, 0.75, 0.72)))
    unit_cube_object(sc, "Stool", diffuse("StoolGreen", (0.2, 0.42, 0.22)), (0.85, -0.3, 0.22), 25.0,
                     (0.4, 0.4, 0.44))
    sphere_object(sc, "Ball", diffuse("BallOrange", (0.8, 0.35, 0.08)), (-0.55, 0.75, tz + 0.04 + 0.14), 0.14)
    cylinder_object(sc, "Vase", diffuse("VaseWhite", (0.8, 0.8, 0.78)), (1.65, 1.6, 0.9 + 0.18), 0.1, 0.36)
    box_object(sc, "Picture", (-0.7, y1 - 0.02, 1.25), (0.5, y1, 1.95), diffuse("PictureRed", (0.55, 0.18, 0.12)))
    box_object(sc, "Rug", (-1.6, -0.6, 0.0), (0.9, 1.8, 0.01), diffuse("RugBeige", (0.55, 0.5, 0.4)))

    # a few glossy objects: wall socket plates, a metal ball on the table
    socket = glossy_ggx("SocketGloss", (0.9, 0.9, 0.88), 0.1)
    box_object(sc, "WallSocket", (-1.5, y1 - 0.012, 0.3), (-1.34, y1, 0.4), socket)
    box_object(sc, "WallSocket2", (x1 - 0.012, -0.2, 0.3), (x1, -0.04, 0.4), socket)
    box_object(sc, "LightSwitch", (x1 - 0.012, -0.55, 1.05), (x1, -0.45, 1.17), socket)
    sphere_object(sc, "MetalBall", principled("BrushedSteel", (0.8, 0.8, 0.8), 1.0, 0.25),
                  (0.2, 0.95, tz + 0.04 + 0.1), 0.1)

    for i, (x, y) in enumerate([(-0.6, 0.3), (0.9, 1.3)]):
        add_light(sc, "CeilingLight%d" % i, 'AREA', (x, y, h - 0.02), shape='SQUARE', size=0.5,
                  energy=PSF_ROOM_LIGHT_POWER, color=(1.0, 0.95, 0.88))

    cam = add_camera(sc, (-1.2, -2.0, 1.55), (0.0, 0.0, 0.0), lens=22.0)
    aim(cam, (0.2, 1.0, 0.7))
    save(path)


def emission(name, color, strength):
    m, nt, out = _node_material(name)
    em = _bsdf_node(nt, 'ShaderNodeEmission', {"Color": color, "Strength": strength}, (-250, 0))
    nt.links.new(em.outputs[0], out.inputs["Surface"])
    return m


def quads_object(sc, name, mat, quads):
    """One mesh of many flat quads, each given by its 4 corners (counter-clockwise seen from the front)."""
    me = bpy.data.meshes.new(name)
    verts = [v for q in quads for v in q]
    faces = [(4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3) for i in range(len(quads))]
    me.from_pydata(verts, [], faces)
    me.update()
    me.materials.append(mat)
    return link(sc, bpy.data.objects.new(name, me))


MANY_LIGHTS_GRID = 12        # 12 x 12 area lights above the pergola
MANY_LIGHTS_QUADS = 160      # emissive quads below it and on the walls


def build_many_lights(path):
    """Hundreds of small emitters with occluders: the many-light case of RIS/ReSTIR."""
    import random
    rng = random.Random(8)
    sc = new_scene(128, 128, samples=1024)
    set_world(sc, (0.02, 0.025, 0.035), 1.0)
    floor = diffuse("Floor", (0.6, 0.58, 0.55))
    stone = diffuse("Stone", (0.7, 0.7, 0.68))
    tiles = glossy_ggx("GlossyTiles", (0.8, 0.8, 0.8), 0.2)
    t = 0.1
    box_object(sc, "Floor", (-4.0, -4.0, -t), (4.0, 4.0, 0.0), floor)
    box_object(sc, "GlossyPath", (-0.5, -4.0, 0.0), (0.5, 4.0, 0.005), tiles)
    box_object(sc, "BackWall", (-4.0, 3.0, 0.0), (4.0, 3.0 + t, 2.6), stone)
    box_object(sc, "LeftWall", (-3.0 - t, -4.0, 0.0), (-3.0, 3.0, 2.6), stone)
    box_object(sc, "RightWall", (3.0, -4.0, 0.0), (3.0 + t, 3.0, 2.6), stone)
    for i, x in enumerate((-2.0, -1.0, 1.0, 2.0)):          # pillars
        for j, y in enumerate((-1.5, 0.5, 2.2)):
            box_object(sc, "Pillar%d%d" % (i, j), (x - 0.12, y - 0.12, 0.0), (x + 0.12, y + 0.12, 2.4), stone)
    for k in range(14):                                     # pergola slats
        y = -3.0 + 0.45 * k
        box_object(sc, "Slat%d" % k, (-3.0, y, 2.4), (3.0, y + 0.2, 2.5), stone)

    def colour():
        h = rng.random()
        r, g, b = (0.5 + 0.5 * math.cos(2 * math.pi * (h + o)) for o in (0.0, 1 / 3, 2 / 3))
        return (0.35 + 0.65 * r, 0.35 + 0.65 * g, 0.35 + 0.65 * b)

    n = MANY_LIGHTS_GRID
    for i in range(n * n):
        x = -2.8 + 5.6 * (i % n + rng.random()) / n
        y = -3.0 + 6.0 * (i // n + rng.random()) / n
        add_light(sc, "Lamp%03d" % i, 'AREA', (x, y, 2.7 + 0.5 * rng.random()), shape='SQUARE', size=0.12,
                  energy=0.4 + 2.0 * rng.random() ** 2, color=colour())

    # Emissive quads: lanterns floating among the pillars (horizontal, both sides emit) and tiles on
    # the walls, in 8 materials of different colours and strengths.
    materials = [emission("Glow%d" % m, colour(), 1.0 + 3.0 * rng.random()) for m in range(8)]
    buckets = [[] for _ in materials]
    for q in range(MANY_LIGHTS_QUADS):
        r = 0.05 + 0.05 * rng.random()
        if q % 2 == 0:
            x, y, z = rng.uniform(-2.8, 2.8), rng.uniform(-3.5, 2.9), rng.uniform(0.4, 2.2)
            quad = [(x - r, y - r, z), (x + r, y - r, z), (x + r, y + r, z), (x - r, y + r, z)]
        else:
            wall = rng.choice(("back", "left", "right"))
            a, z = rng.uniform(-2.8, 2.8), rng.uniform(0.3, 2.3)
            if wall == "back":
                yy = 3.0 - 0.002
                quad = [(a - r, yy, z - r), (a - r, yy, z + r), (a + r, yy, z + r), (a + r, yy, z - r)]
            else:
                xx = -3.0 + 0.002 if wall == "left" else 3.0 - 0.002
                a = rng.uniform(-3.5, 2.9)
                quad = [(xx, a - r, z - r), (xx, a + r, z - r), (xx, a + r, z + r), (xx, a - r, z + r)]
        buckets[q % len(materials)].append(quad)
    for m, (mat, quads) in enumerate(zip(materials, buckets)):
        quads_object(sc, "Glow%d" % m, mat, quads)

    cam = add_camera(sc, (0.3, -3.9, 1.7), (0.0, 0.0, 0.0), lens=20.0)  # under the pergola
    aim(cam, (0.0, 1.0, 0.5))
    save(path)


def _spectral_properties():
    """Register light.smis / material.smis from the add-on source (it needs only bpy), so the
    spectral scenes can set them without enabling the add-on."""
    if hasattr(bpy.types.Material, "smis"):
        return
    import importlib.util
    path = os.path.join(os.path.dirname(HERE), "addon", "smis_render", "spectral_properties.py")
    spec = importlib.util.spec_from_file_location("smis_spectral_properties", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.register()


def spectral_room(sc, wall_color=(0.5, 0.5, 0.5)):
    """Floor and back wall, camera looking slightly down at the origin."""
    grey = diffuse("Grey", wall_color)
    box_object(sc, "Floor", (-3, -3, -0.1), (3, 3, 0), grey)
    box_object(sc, "Wall", (-3, 1.2, 0), (3, 1.3, 3), grey)
    cam = add_camera(sc, (0.0, -3.2, 1.3), (0.0, 0.0, 0.0), lens=40.0)
    aim(cam, (0.0, 0.0, 0.45))
    return grey


def spectral_lights(sc, spectrum, lights, size, target):
    """Square area lights (name, location, power W) aimed at `target`, emitting `spectrum`."""
    for name, loc, power in lights:
        light = add_light(sc, name, 'AREA', loc, shape='SQUARE', size=size, energy=power)
        aim(light, target)
        light.data.smis.spectrum = spectrum


def build_spectral_gold(path):
    _spectral_properties()
    sc = new_scene(128, 128, samples=64)
    set_world(sc)
    spectral_room(sc)
    gold = glossy_ggx("MeasuredGold", (1.0, 1.0, 1.0), 0.25)
    gold.smis.metal = 'Au'
    torus_object(sc, "GoldTorus", gold, (-0.55, 0.1, 0.45), 0.35, 0.13, rotation_deg=(70.0, 0.0, 20.0))
    sphere_object(sc, "GoldSphere", gold, (0.55, 0.2, 0.4), 0.4)
    unit_cube_object(sc, "GoldCube", gold, (0.05, -0.55, 0.18), 30.0, (0.36, 0.36, 0.36))
    spectral_lights(sc, 'F10', (("F10Key", (-1.2, -1.2, 2.2), 120.0), ("F10Fill", (1.5, -0.5, 1.6), 60.0)),
                    size=0.8, target=(0.0, 0.0, 0.4))
    save(path)


def prism_object(sc, name, mat, location, apex_deg, side, height, rotation_z_deg):
    """Upright triangular prism: apex angle `apex_deg` between two faces of width `side`, base
    along the local x axis, extruded `height` up from `location`, turned by `rotation_z_deg`."""
    half = side * math.sin(math.radians(apex_deg) / 2.0)
    apex = side * math.cos(math.radians(apex_deg) / 2.0)
    tri = [(-half, 0.0), (half, 0.0), (0.0, apex)]
    bm = bmesh.new()
    bottom = [bm.verts.new((x, y - apex / 3.0, 0.0)) for x, y in tri]
    top = [bm.verts.new((x, y - apex / 3.0, height)) for x, y in tri]
    bm.faces.new(bottom)
    bm.faces.new(top)
    for i in range(3):
        j = (i + 1) % 3
        bm.faces.new((bottom[i], bottom[j], top[j], top[i]))
    bmesh.ops.recalc_face_normals(bm, faces=bm.faces)  # outward: the glass needs its inside
    return bmesh_object(sc, name, mat, bm, location, rotation_z_deg)


def build_spectral_glass(path):
    """Fig. 9-like: slightly dispersive glasses (N-BK7 and F2 spheres, an Abbe-number cube) and a
    dense-flint N-SF11 prism on a grey floor before a dark wall of thin vertical D65 slits. The slits
    are the high-contrast backdrop that makes dispersion visible: through the prism (deviation ~41
    degrees, spread ~2.4 degrees over 430-680 nm at its 45-degree apex) each slit becomes a small
    spectrum, and the spheres' refracted images of the slits get coloured fringes."""
    _spectral_properties()
    sc = new_scene(128, 128, samples=64)
    set_world(sc)
    box_object(sc, "Floor", (-4, -4, -0.1), (4, 4, 0), diffuse("Floor", (0.4, 0.4, 0.4)))
    box_object(sc, "Wall", (-5, 2.5, 0), (5, 2.6, 4), diffuse("Wall", (0.02, 0.02, 0.02)))
    slit = emission("Slit", (1.0, 1.0, 1.0), 6.0)
    slit.smis.emission_spectrum = 'D65'
    quads = []
    for i in range(21):
        x = -5.0 + 0.5 * i
        quads.append([(x, 2.49, 0.0), (x + 0.04, 2.49, 0.0), (x + 0.04, 2.49, 3.0), (x, 2.49, 3.0)])
    quads_object(sc, "Slits", slit, quads)
    for glass, loc, radius in (("N-BK7", (-0.95, -0.1, 0.32), 0.32), ("F2", (0.95, 0.2, 0.3), 0.3)):
        mat = glass_ggx("Glass_" + glass, 1.5, 0.0)
        mat.smis.dispersion = glass
        sphere_object(sc, "Sphere_" + glass, mat, loc, radius)
    cube = glass_ggx("Glass_Abbe", 1.6, 0.0)
    cube.smis.dispersion = 'ABBE'
    cube.smis.abbe = 40.0
    unit_cube_object(sc, "AbbeCube", cube, (-0.35, -0.75, 0.12), 35.0, (0.24, 0.24, 0.24))
    flint = glass_ggx("Glass_N-SF11", 1.78, 0.0)
    flint.smis.dispersion = 'N-SF11'
    # Base turned to the ray inside at minimum deviation: 90 - delta_min / 2 with delta_min ~41 degrees.
    prism_object(sc, "Prism_N-SF11", flint, (0.05, -0.35, 0.0), 45.0, 0.8, 1.3, 69.5)
    cam = add_camera(sc, (0.0, -3.2, 0.75), (0.0, 0.0, 0.0), lens=42.0)
    aim(cam, (0.0, 0.0, 0.4))
    spectral_lights(sc, 'D65', (("D65Key", (-1.0, -1.5, 2.4), 100.0), ("D65Fill", (1.6, -1.0, 1.5), 40.0)),
                    size=0.6, target=(0.0, 0.0, 0.3))
    save(path)


# --------------------------------------------------------------------------
# single scattering with photon planes (West et al. 2020, Sec. 6, Fig. 11)
# --------------------------------------------------------------------------
def volume_material(name, scatter_color, scatter_density, absorption_color, absorption_density,
                    anisotropy=0.0):
    """Volume-only material (no Surface: its mesh is an index-matched boundary): Volume Scatter
    plus Volume Absorption through an Add Shader, so both of Cycles' conventions are exercised
    (scatter: sigma_s = density * colour; absorption: sigma_a = density * (1 - colour))."""
    m, nt, out = _node_material(name)
    scatter = nt.nodes.new('ShaderNodeVolumeScatter')
    scatter.inputs["Color"].default_value = (*scatter_color, 1.0)
    scatter.inputs["Density"].default_value = scatter_density
    scatter.inputs["Anisotropy"].default_value = anisotropy
    absorb = nt.nodes.new('ShaderNodeVolumeAbsorption')
    absorb.inputs["Color"].default_value = (*absorption_color, 1.0)
    absorb.inputs["Density"].default_value = absorption_density
    add = nt.nodes.new('ShaderNodeAddShader')
    nt.links.new(scatter.outputs[0], add.inputs[0])
    nt.links.new(absorb.outputs[0], add.inputs[1])
    nt.links.new(add.outputs[0], out.inputs["Volume"])
    return m


# Six rectangular lights (name, centre, aim point, size x, size y, power W, colour), several of
# them narrow so that photon planes through their short side are thin (the case SMIS_exact fixes).
VOLUME_LIGHTS = (
    ("KeyLight", (-1.2, -0.6, 2.6), (-0.6, 0.3, 0.0), 0.8, 0.5, 60.0, (1.0, 0.9, 0.75)),
    ("StripLight", (1.3, 0.4, 2.7), (0.9, 0.6, 0.0), 1.6, 0.08, 50.0, (0.75, 0.85, 1.0)),
    ("SideLight", (-2.0, 1.3, 1.2), (0.0, 0.9, 0.5), 0.12, 0.9, 40.0, (1.0, 0.7, 0.6)),
    ("BackLight", (0.3, 1.8, 2.2), (0.2, 0.0, 0.0), 0.6, 0.6, 35.0, (0.8, 1.0, 0.8)),
    ("LowLight", (1.8, -1.0, 0.6), (0.0, 0.5, 0.3), 0.5, 0.05, 25.0, (1.0, 0.95, 0.9)),
    ("TopLight", (0.0, 0.2, 3.0), (0.1, 0.1, 0.0), 1.0, 0.3, 45.0, (0.9, 0.9, 1.0)),
)


def fog_scene(res_x, res_y, fog, box_lo, box_hi):
    """A single-scattering scene: max_bounces 1 and volume bounces 0 (the scene's custom property
    smis_volume_bounces tells make_cycles_unbiased), a black world, and a box from box_lo to box_hi
    of the volume-only material volume_material(*fog)."""
    sc = new_scene(res_x, res_y, samples=1024)
    sc["smis_volume_bounces"] = 0
    make_cycles_unbiased(sc, max_bounces=1)
    set_world(sc)
    box_object(sc, "FogBox", box_lo, box_hi, volume_material(*fog))
    return sc


def build_volume_planes(path):
    """Homogeneous isotropic medium (a closed box with a volume-only material) holding a floor,
    a back wall, two pillars and a cube, lit by six rectangular area lights inside the medium;
    the camera looks in from outside. Rendered with max_bounces 1 and volume bounces 0 (single
    scattering; the scene's custom property smis_volume_bounces tells make_cycles_unbiased)."""
    sc = fog_scene(96, 96, ("Fog", (0.9, 0.85, 0.8), 0.35, (0.8, 0.9, 1.0), 0.15), (-2.6, -2.6, -0.3), (2.6, 2.6, 3.4))
    white = diffuse("White", WHITE)
    red = diffuse("Red", RED)
    box_object(sc, "Floor", (-2.4, -2.4, -0.1), (2.4, 2.4, 0.0), white)
    box_object(sc, "BackWall", (-2.4, 2.3, 0.0), (2.4, 2.4, 3.0), white)
    box_object(sc, "PillarL", (-1.0, 0.6, 0.0), (-0.7, 0.9, 2.2), white)
    box_object(sc, "PillarR", (0.8, 1.0, 0.0), (1.1, 1.3, 1.8), red)
    unit_cube_object(sc, "Cube", white, (0.1, -0.3, 0.35), 25.0, (0.7, 0.7, 0.7))
    for name, loc, target, sx, sy, power, color in VOLUME_LIGHTS:
        aim(add_light(sc, name, 'AREA', loc, shape='RECTANGLE', size=sx, size_y=sy, energy=power,
                      color=color), target)
    add_camera(sc, (0.0, -5.4, 1.45), (85.0, 0.0, 0.0), lens=32.0)
    save(path)


def _single_scattering_scene(*fog, camera=((0.0, -5.6, 1.5), (84.0, 0.0, 0.0))):
    """A 512x384 single-scattering scene (max_bounces 1, Cycles' volume bounces 0) whose fog box
    (volume_material(*fog)) holds a floor and a back wall; the camera (location, rotation) looks
    in from outside."""
    sc = fog_scene(512, 384, fog, (-3.0, -3.0, -0.3), (3.0, 3.0, 3.6))
    white = diffuse("White", WHITE)
    box_object(sc, "Floor", (-2.8, -2.8, -0.1), (2.8, 2.8, 0.0), white)
    box_object(sc, "BackWall", (-2.8, 2.7, 0.0), (2.8, 2.8, 3.4), white)
    add_camera(sc, *camera, lens=30.0)
    return sc, white


def build_volume_spot(path):
    """Single scattering from focused light: a spot light (35 degrees, blend 0.3, radius 0: a
    point, so photon planes cover it) shining down through isotropic fog past a small cube, so the
    beam has a shadow shaft, and a dim rectangular fill light. The beam is a small part of the
    image's volume."""
    sc, white = _single_scattering_scene("Fog", (0.9, 0.9, 0.9), 0.25, (0.9, 0.9, 1.0), 0.05)
    unit_cube_object(sc, "Blocker", white, (-0.2, 0.2, 1.9), 20.0, (0.35, 0.35, 0.35))
    unit_cube_object(sc, "Cube", diffuse("Red", RED), (0.9, 0.6, 0.4), -15.0, (0.8, 0.8, 0.8))
    aim(add_light(sc, "Spot", 'SPOT', (-0.4, 0.0, 3.4), spot_size=math.radians(35.0), spot_blend=0.3,
                  shadow_soft_size=0.0, energy=600.0, color=(1.0, 0.9, 0.75)), (0.1, 0.6, 0.0))
    aim(add_light(sc, "Fill", 'AREA', (2.2, -1.5, 2.5), shape='RECTANGLE', size=0.6, size_y=0.4,
                  energy=15.0, color=(0.7, 0.8, 1.0)), (0.0, 0.5, 0.0))
    save(path)


def build_volume_slit(path):
    """Light through a gap: a rectangular area light behind a wall with a narrow vertical slit
    (8 cm) throws a fan of light into isotropic fog, seen obliquely; a narrow strip light (2 m x 4 cm)
    above the floor is the second light. Most of the first light's planes (and light samples) are
    blocked."""
    sc, white = _single_scattering_scene("Fog", (0.85, 0.85, 0.9), 0.3, (0.9, 0.9, 0.9), 0.05,
                                         camera=((2.0, -5.4, 1.6), (84.0, 0.0, 20.0)))
    box_object(sc, "WallL", (-2.8, 1.0, 0.0), (-0.04, 1.1, 3.0), white)
    box_object(sc, "WallR", (0.04, 1.0, 0.0), (2.8, 1.1, 3.0), white)
    aim(add_light(sc, "Behind", 'AREA', (0.0, 2.2, 1.6), shape='RECTANGLE', size=1.2, size_y=1.2,
                  energy=300.0, color=(1.0, 0.85, 0.6)), (0.0, -1.0, 1.0))
    aim(add_light(sc, "Strip", 'AREA', (0.0, -0.8, 0.6), shape='RECTANGLE', size=2.0, size_y=0.04,
                  energy=20.0, color=(0.6, 0.8, 1.0)), (0.0, -0.8, 0.0))
    save(path)


def build_volume_thin_hg(path):
    """Thin, forward-scattering medium: density 0.04, Henyey-Greenstein g = 0.7, lit by two
    narrow rectangular lights that face the camera from behind the scene, so the glow around them
    comes from the phase function's forward peak; a pillar between them casts a shadow."""
    sc, white = _single_scattering_scene("Haze", (1.0, 1.0, 1.0), 0.04, (1.0, 1.0, 1.0), 0.0, 0.7)
    box_object(sc, "Pillar", (-0.15, 0.9, 0.0), (0.15, 1.2, 2.4), white)
    aim(add_light(sc, "BackLeft", 'AREA', (-0.9, 2.2, 1.6), shape='RECTANGLE', size=0.08, size_y=1.0,
                  energy=80.0, color=(1.0, 0.85, 0.7)), (0.0, -5.6, 1.5))
    aim(add_light(sc, "BackRight", 'AREA', (1.1, 2.0, 1.0), shape='RECTANGLE', size=0.8, size_y=0.06,
                  energy=60.0, color=(0.7, 0.85, 1.0)), (0.0, -5.6, 1.5))
    aim(add_light(sc, "Top", 'AREA', (0.0, 0.0, 3.2), shape='RECTANGLE', size=1.0, size_y=0.3,
                  energy=40.0, color=(1.0, 1.0, 1.0)), (0.0, 0.5, 0.0))
    save(path)


STAGE_BEAMS = (  # name, position, aim point, cone degrees, power W, colour
    ("RigLeft", (-2.0, 1.6, 3.4), (-0.7, -0.5, 0.0), 14.0, 900.0, (1.0, 0.75, 0.5)),
    ("RigCentre", (0.2, 2.3, 3.4), (0.3, -0.4, 0.0), 10.0, 900.0, (0.6, 0.8, 1.0)),
    ("RigRight", (2.2, 1.2, 3.3), (0.6, -1.2, 0.0), 16.0, 900.0, (1.0, 0.55, 0.8)),
    ("Side", (-2.8, 0.2, 1.1), (2.8, 0.9, 1.9), 12.0, 600.0, (0.9, 0.95, 1.0)),
)


def stage_scene():
    """The haze, floor and back wall of _single_scattering_scene with the four spot lights of
    STAGE_BEAMS and the riser they light (volume_beams and volume_stage)."""
    sc, white = _single_scattering_scene("Haze", (0.9, 0.9, 0.9), 0.15, (0.9, 0.9, 0.9), 0.02)
    for name, loc, target, cone, power, color in STAGE_BEAMS:
        aim(add_light(sc, name, 'SPOT', loc, spot_size=math.radians(cone), spot_blend=0.15,
                      shadow_soft_size=0.0, energy=power, color=color), target)
    unit_cube_object(sc, "Riser", white, (0.3, 0.6, 0.25), 10.0, (1.6, 0.9, 0.5))
    return sc


def build_volume_beams(path):
    """Stage beams: four narrow spot lights (10-16 degrees, radius 0: points, so photon planes
    cover them) in thin haze, three from the rig above and one from the side across the stage, as
    stage lighting does; no other light, so the fog outside the cones is dark. Each camera ray that
    crosses a beam is lit over a short stretch of its length: the path tracer's equiangular
    distance sampling towards a light point spreads its samples by 1/r^2 along the whole ray and
    does not know the cone (nor does Cycles 3.4's), while a spot's photon planes lie inside its cone."""
    stage_scene()
    save(path)


def build_volume_stage(path):
    """A lit stage in haze: volume_beams' four narrow spot lights (10-16 degrees, radius 0) and a
    large, dim rectangular wash light overhead, as a stage is lit: the wash lights the floor, the
    back wall and the riser directly and fills the haze with a soft, even glow, and the beams cut
    through it. The surfaces are lit mostly by the wash (which the path tracer's light sampling
    renders smoothly), not only by the beams' glow as on volume_beams, so the image's noise is the
    beams' single scattering along the camera rays."""
    sc = stage_scene()
    aim(add_light(sc, "Wash", 'AREA', (0.0, -1.0, 3.5), shape='RECTANGLE', size=4.0, size_y=2.5,
                  energy=40.0, color=(1.0, 0.95, 0.9)), (0.0, 0.3, 0.0))
    save(path)


def build_volume_searchlights(path):
    """Searchlights in night haze: five narrow spot lights (5-8 degrees, radius 0) on the ground
    shine up into a large, thin isotropic fog; the camera, on the ground outside the fog, looks up
    at the beams (the lamps just below the frame, so no radius-0 point is in view) against a black
    sky: no surface is in view and every pixel is the camera ray's single scattering. A beam lights
    a few metres of a camera ray that runs 40 m or more through the fog, while equiangular sampling
    towards the lamp puts its samples near the ray's closest point to the lamp, outside the cone."""
    sc = fog_scene(512, 384, ("NightHaze", (0.95, 0.95, 1.0), 0.04, (0.9, 0.9, 1.0), 0.01), (-24.0, -2.0, -0.5),
                   (24.0, 40.0, 70.0))
    beams = (  # name, position, aim point, cone degrees, power W, colour
        ("SearchA", (-7.0, 8.0, 0.2), (-11.0, 14.0, 14.0), 6.0, 240000.0, (1.0, 0.95, 0.85)),
        ("SearchB", (-2.5, 12.0, 0.2), (1.5, 16.0, 15.0), 5.0, 240000.0, (0.85, 0.9, 1.0)),
        ("SearchC", (2.0, 6.0, 0.2), (-3.0, 13.0, 13.0), 7.0, 200000.0, (1.0, 0.9, 0.8)),
        ("SearchD", (6.5, 10.0, 0.2), (10.0, 18.0, 15.0), 6.0, 240000.0, (0.9, 0.95, 1.0)),
        ("SearchE", (0.5, 16.0, 0.2), (6.0, 20.0, 15.0), 8.0, 280000.0, (1.0, 0.85, 0.7)),
    )
    for name, loc, target, cone, power, color in beams:
        aim(add_light(sc, name, 'SPOT', loc, spot_size=math.radians(cone), spot_blend=0.1,
                      shadow_soft_size=0.0, energy=power, color=color), target)
    add_camera(sc, (0.0, -6.0, 1.0), (124.0, 0.0, 0.0), lens=20.0)
    save(path)


def principled_extras(name, base, roughness, **inputs):
    """Principled BSDF with sheen / clearcoat inputs (e.g. Clearcoat=1.0, Sheen=1.0)."""
    m = _material(name, 'ShaderNodeBsdfPrincipled', distribution='GGX',
                  **{"Base Color": base, "Roughness": roughness, **inputs})
    m.diffuse_color = (*base, 1.0)
    return m


def build_principled_coat(path):
    """Two spheres on a grey floor: left a dark red base under a clearcoat (Clearcoat 1,
    roughness 0.1), right a blue rough base with full sheen (tint 0.5), both seen against a grey
    world and lit by one area light from the upper left, so the coat's highlight and the sheen's
    grazing rim are both in view. Small (96x64): the Cycles reference is committed."""
    sc = new_scene(96, 64, samples=1024)
    set_world(sc, (0.5, 0.5, 0.5), 0.6)
    grey = diffuse("Grey", (0.5, 0.5, 0.5))
    box_object(sc, "Floor", (-3.0, -3.0, -0.1), (3.0, 3.0, 0.0), grey)
    coat = principled_extras("Clearcoat", (0.35, 0.04, 0.03), 0.5, Clearcoat=1.0,
                             **{"Clearcoat Roughness": 0.1})
    sheen = principled_extras("Sheen", (0.05, 0.1, 0.4), 0.8, Sheen=1.0, **{"Sheen Tint": 0.5})
    sphere_object(sc, "CoatSphere", coat, (-0.55, 0.0, 0.5), 0.5)
    sphere_object(sc, "SheenSphere", sheen, (0.55, 0.0, 0.5), 0.5)
    aim(add_light(sc, "Key", 'AREA', (-2.0, -2.0, 2.5), shape='SQUARE', size=1.0, energy=150.0),
        (0.0, 0.0, 0.5))
    add_camera(sc, (0.0, -3.2, 0.9), (83.0, 0.0, 0.0), lens=40.0)
    save(path)


def _procedural_material(name, variant):
    """A material of about ten procedural nodes (textures, ramps, maths, mix, bump) into a
    Principled BSDF, as real scenes' materials look; `variant` changes the recipe."""
    m, nt, out = _node_material(name)
    bsdf = nt.nodes.new("ShaderNodeBsdfPrincipled")
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    coord = nt.nodes.new("ShaderNodeTexCoord")
    mapping = nt.nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (2.0 + variant, 2.0, 2.0)
    nt.links.new(coord.outputs["Object"], mapping.inputs["Vector"])
    noise = nt.nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 4.0
    noise.inputs["Detail"].default_value = 4.0
    nt.links.new(mapping.outputs["Vector"], noise.inputs["Vector"])
    voronoi = nt.nodes.new("ShaderNodeTexVoronoi")
    voronoi.inputs["Scale"].default_value = 6.0
    nt.links.new(mapping.outputs["Vector"], voronoi.inputs["Vector"])
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.05, 0.1 * variant, 0.3, 1.0)
    ramp.color_ramp.elements[1].color = (0.9, 0.6, 0.2, 1.0)
    nt.links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    mix = nt.nodes.new("ShaderNodeMix")
    mix.data_type = 'RGBA'
    mix.blend_type = 'MULTIPLY'
    mix.inputs["Factor"].default_value = 0.6
    nt.links.new(ramp.outputs["Color"], mix.inputs[6])
    nt.links.new(voronoi.outputs["Color"], mix.inputs[7])
    nt.links.new(mix.outputs[2], bsdf.inputs["Base Color"])
    math = nt.nodes.new("ShaderNodeMath")
    math.operation = 'MULTIPLY_ADD'
    math.inputs[1].default_value = 0.5
    math.inputs[2].default_value = 0.2
    nt.links.new(voronoi.outputs["Distance"], math.inputs[0])
    nt.links.new(math.outputs[0], bsdf.inputs["Roughness"])
    bump = nt.nodes.new("ShaderNodeBump")
    bump.inputs["Strength"].default_value = 0.4
    nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    layer = nt.nodes.new("ShaderNodeLayerWeight")
    nt.links.new(layer.outputs["Facing"], bsdf.inputs["Specular"])
    return m


def build_procedural(path):
    """Three objects and a floor whose materials have about ten procedural nodes each (noise,
    voronoi, mapping, colour ramp, mix, math, bump, layer weight): the node evaluator's speed
    against Cycles (bench/path_speed.py) and its agreement on a lit scene."""
    sc = new_scene(160, 120, samples=256)
    set_world(sc, (0.3, 0.35, 0.4), 1.0)
    box_object(sc, "Floor", (-3.0, -3.0, -0.1), (3.0, 3.0, 0.0), _procedural_material("FloorNodes", 0))
    sphere_object(sc, "Sphere", _procedural_material("SphereNodes", 1), (-0.7, 0.0, 0.5), 0.5)
    unit_cube_object(sc, "Cube", _procedural_material("CubeNodes", 2), (0.7, 0.2, 0.4), 30.0, (0.7, 0.7, 0.8))
    aim(add_light(sc, "Key", 'AREA', (-2.0, -2.0, 3.0), shape='SQUARE', size=1.5, energy=300.0),
        (0.0, 0.0, 0.3))
    add_camera(sc, (0.0, -3.4, 1.4), (72.0, 0.0, 0.0), lens=35.0)
    save(path)


def build_textured_plane(path):
    """One image-textured plane under a point light, camera looking straight down: the simple
    public-scene case of issue 21's speed bar (bench/path_speed.py). The 512x512 texture is made
    here (a checker with a smooth colour gradient) and packed into the .blend."""
    import numpy as np
    sc = new_scene(480, 270, samples=64)
    set_world(sc, (0.05, 0.05, 0.05), 1.0)
    n = 512
    y, x = np.mgrid[0:n, 0:n] / n
    checker = ((np.floor(x * 16) + np.floor(y * 16)) % 2) * 0.6 + 0.2
    rgba = np.stack([checker * (0.5 + 0.5 * x), checker * (0.5 + 0.5 * y), checker * 0.7,
                     np.ones_like(x)], axis=-1).astype(np.float32)
    img = bpy.data.images.new("Checker", n, n)
    img.pixels.foreach_set(rgba.ravel())
    img.pack()
    m, nt, out = _node_material("Textured")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Color"])
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")  # create_grid's calc_uvs fills the mesh's UV layer
    bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=4.0, calc_uvs=True)
    _finish_mesh(sc, "Plane", bm, m)
    add_light(sc, "Point", 'POINT', (0.5, -0.5, 2.0), energy=200.0, shadow_soft_size=0.1)
    add_camera(sc, (0.0, 0.0, 3.0), (0.0, 0.0, 0.0), lens=35.0)
    save(path)


def save(path):
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
    print("build_scenes: wrote", path)


SCENE_NAMES = {
    "cornell": build_cornell,
    "cornell_diffuse": build_cornell_diffuse,
    "demo": build_demo,
    "psf_glossy": build_psf_glossy,
    "psf_room": build_psf_room,
    "spectral_gold": build_spectral_gold,
    "spectral_glass": build_spectral_glass,
    "volume_planes": build_volume_planes,
    "volume_spot": build_volume_spot,
    "volume_slit": build_volume_slit,
    "volume_thin_hg": build_volume_thin_hg,
    "volume_beams": build_volume_beams,
    "volume_searchlights": build_volume_searchlights,
    "volume_stage": build_volume_stage,
    "many_lights": build_many_lights,
    "principled_coat": build_principled_coat,
    "procedural": build_procedural,
    "textured_plane": build_textured_plane,
}


def main():
    out = out_dir()
    os.makedirs(out, exist_ok=True)
    for name in selected_scenes():
        SCENE_NAMES[name](os.path.join(out, name + ".blend"))


main()
