"""Scenes for per-node parity with Cycles (issue 17): every shader node set-up on its own tile.

Run:
    blender -b --factory-startup --python scenes/node_parity.py -- OUTDIR

Writes
  OUTDIR/node_parity_emission.blend  320x192: an orthographic camera looking straight down (-Z) at
      10 x 6 emission planes, one per node set-up, each 2 x 2 m and exactly 32 x 32 px, touching, the
      world black. A tile's Emission Color (and sometimes Strength) comes from its node set-up, fed
      by the tile's own Object (-1..1), Generated (0..1) or UV (0..1) coordinates, so the pattern is
      deterministic and seen head-on. Objects and materials are named `tile_NN_<set-up>`.
  OUTDIR/node_parity_emission.json   the tiles: name, pixel rectangle (x0, y0, size; row 0 is the
      image's BOTTOM row, as in Blender's pixel buffers) and the nodes it exercises.
  OUTDIR/node_parity_lit.blend       160x120: a perspective view of a few objects on a floor, lit
      by a sun and a grey world, whose Base Color / Roughness / Metallic / Mix Shader factors
      (Layer Weight, Fresnel) / Bump / Normal Map come from nodes.

Both files are saved for Cycles with the project's unbiased settings (scenes/cycles_settings.py:
per-type bounces = max_bounces, no clamp, no filter glossy, no denoising, no adaptive sampling,
BOX pixel filter 1 px), view transform Standard, and the same settings for SMIS (scene.smis:
max_bounces, BOX filter 1 px, path tracing). Max bounces: 0 for the emission scene (camera rays
only see the tiles), 4 for the lit scene.
"""
import json
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import make_cycles_unbiased  # noqa: E402

TILE_PX = 32          # pixels per tile side: 4 x 4 blocks of 8 x 8 pixels
TILE_M = 2.0          # metres per tile side (the plane's object coordinates span -1..1)
COLS, ROWS = 10, 6    # 320 x 192 pixels


# --------------------------------------------------------------------------------------------------
# node-tree helpers
# --------------------------------------------------------------------------------------------------
def _socket(sockets, key):
    """A socket by index, or the first enabled one with that name (the 3.4 Mix and Map Range nodes
    have several sockets of one name, one per data type)."""
    if isinstance(key, int):
        return sockets[key]
    for s in sockets:
        if s.name == key and s.enabled:
            return s
    return sockets[key]


class Tree:
    """Builds nodes in one node tree (a material's or a group's)."""

    def __init__(self, nt):
        self.nt = nt
        self._coords = None

    def node(self, idname, inputs=None, **props):
        n = self.nt.nodes.new(idname)
        for k, v in props.items():
            setattr(n, k, v)
        for k, v in (inputs or {}).items():
            self.set(n, k, v)
        return n

    def set(self, node, key, value):
        sock = _socket(node.inputs, key)
        if isinstance(value, bpy.types.NodeSocket):
            self.nt.links.new(value, sock)
        elif isinstance(value, bpy.types.Node):
            self.nt.links.new(value.outputs[0], sock)
        else:
            if sock.type == 'RGBA' and len(value) == 3:
                value = (*value, 1.0)
            sock.default_value = value

    def coords(self, which):
        """An output of the tree's Texture Coordinate node ('Generated', 'Object', 'UV')."""
        if self._coords is None:
            self._coords = self.nt.nodes.new("ShaderNodeTexCoord")
        return self._coords.outputs[which]

    def math(self, op, a, b=0.0, c=0.0, **props):
        return out(self.node("ShaderNodeMath", {0: a, 1: b, 2: c}, operation=op, **props))

    def vmath(self, op, a, b=(0.0, 0.0, 0.0), c=None, scale=None, output="Vector"):
        ins = {0: a, 1: b}
        if c is not None:
            ins[2] = c
        if scale is not None:
            ins["Scale"] = scale
        return out(self.node("ShaderNodeVectorMath", ins, operation=op), output)

    def separate_xyz(self, v):
        n = self.node("ShaderNodeSeparateXYZ", {0: v})
        return n.outputs[0], n.outputs[1], n.outputs[2]

    def combine_rgb(self, r, g, b):
        return out(self.node("ShaderNodeCombineRGB", {0: r, 1: g, 2: b}))


def out(node, key=0):
    return _socket(node.outputs, key)


def emission_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    output = nt.nodes.new("ShaderNodeOutputMaterial")
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    nt.links.new(em.outputs[0], output.inputs["Surface"])
    return mat, Tree(nt), em


# --------------------------------------------------------------------------------------------------
# the tiles: each function gets the tile's Tree and Emission node and wires Color (and Strength)
# --------------------------------------------------------------------------------------------------
def t_checker(t, em):
    n = t.node("ShaderNodeTexChecker", {"Vector": t.coords("Object"), "Scale": 2.5,
                                         "Color1": (0.9, 0.25, 0.1), "Color2": (0.1, 0.35, 0.8)})
    t.set(em, "Color", out(n, "Color"))


def t_noise_3d(t, em):
    n = t.node("ShaderNodeTexNoise", {"Vector": t.coords("Object"), "Scale": 2.0, "Detail": 4.0,
                                       "Roughness": 0.55, "Distortion": 0.0}, noise_dimensions='3D')
    t.set(em, "Color", out(n, "Color"))
    t.set(em, "Strength", 1.5)


def t_noise_4d(t, em):
    n = t.node("ShaderNodeTexNoise", {"Vector": t.coords("Object"), "W": 0.7, "Scale": 1.6, "Detail": 2.0,
                                       "Roughness": 0.5, "Distortion": 0.8}, noise_dimensions='4D')
    t.set(em, "Color", out(n, "Color"))


def t_voronoi_f1_euclidean(t, em):
    n = t.node("ShaderNodeTexVoronoi", {"Vector": t.coords("Object"), "Scale": 2.0, "Randomness": 1.0},
               voronoi_dimensions='3D', feature='F1', distance='EUCLIDEAN')
    t.set(em, "Color", out(n, "Color"))
    t.set(em, "Strength", t.math('ADD', out(n, "Distance"), 0.4))


def t_voronoi_f2_manhattan(t, em):
    n = t.node("ShaderNodeTexVoronoi", {"Vector": t.coords("Object"), "Scale": 2.0},
               voronoi_dimensions='3D', feature='F2', distance='MANHATTAN')
    t.set(em, "Color", out(n, "Distance"))


def t_voronoi_smooth_f1(t, em):
    n = t.node("ShaderNodeTexVoronoi", {"Vector": t.coords("Object"), "Scale": 2.0, "Smoothness": 0.6},
               voronoi_dimensions='3D', feature='SMOOTH_F1', distance='EUCLIDEAN')
    t.set(em, "Color", out(n, "Color"))
    t.set(em, "Strength", t.math('ADD', out(n, "Distance"), 0.4))


def t_voronoi_distance_to_edge(t, em):
    n = t.node("ShaderNodeTexVoronoi", {"Vector": t.coords("Object"), "Scale": 2.0},
               voronoi_dimensions='3D', feature='DISTANCE_TO_EDGE')
    t.set(em, "Color", out(n, "Distance"))
    t.set(em, "Strength", 2.0)


def t_musgrave_fbm(t, em):
    n = t.node("ShaderNodeTexMusgrave", {"Vector": t.coords("Object"), "Scale": 2.0, "Detail": 4.0,
                                          "Dimension": 1.5, "Lacunarity": 2.0},
               musgrave_dimensions='3D', musgrave_type='FBM')
    # fBM is signed: shift it into the positive range.
    t.set(em, "Color", t.math('MULTIPLY_ADD', out(n, "Fac"), 0.5, 0.5))


def t_musgrave_ridged(t, em):
    n = t.node("ShaderNodeTexMusgrave", {"Vector": t.coords("Object"), "Scale": 1.5, "Detail": 3.0,
                                          "Dimension": 1.0, "Lacunarity": 2.0, "Offset": 1.0, "Gain": 1.0},
               musgrave_dimensions='3D', musgrave_type='RIDGED_MULTIFRACTAL')
    t.set(em, "Color", out(n, "Fac"))
    t.set(em, "Strength", 0.5)


def t_musgrave_hetero(t, em):
    n = t.node("ShaderNodeTexMusgrave", {"Vector": t.coords("Object"), "Scale": 1.5, "Detail": 3.0,
                                          "Dimension": 1.0, "Lacunarity": 2.0, "Offset": 0.8},
               musgrave_dimensions='3D', musgrave_type='HETERO_TERRAIN')
    t.set(em, "Color", out(n, "Fac"))
    t.set(em, "Strength", 0.5)


def t_wave_bands(t, em):
    n = t.node("ShaderNodeTexWave", {"Vector": t.coords("Object"), "Scale": 1.5, "Distortion": 0.0,
                                      "Phase Offset": 0.5},
               wave_type='BANDS', bands_direction='DIAGONAL', wave_profile='SIN')
    t.set(em, "Color", out(n, "Color"))


def t_wave_rings_distortion(t, em):
    n = t.node("ShaderNodeTexWave", {"Vector": t.coords("Object"), "Scale": 1.0, "Distortion": 3.0,
                                      "Detail": 2.0, "Detail Scale": 1.5, "Detail Roughness": 0.5},
               wave_type='RINGS', rings_direction='SPHERICAL', wave_profile='SAW')
    t.set(em, "Color", out(n, "Fac"))


def t_magic(t, em):
    n = t.node("ShaderNodeTexMagic", {"Vector": t.coords("Object"), "Scale": 1.5, "Distortion": 1.2},
               turbulence_depth=3)
    t.set(em, "Color", out(n, "Color"))


def t_brick(t, em):
    n = t.node("ShaderNodeTexBrick", {"Vector": t.coords("Object"), "Scale": 1.5, "Mortar Size": 0.03,
                                       "Mortar Smooth": 0.2, "Bias": 0.0, "Brick Width": 0.6, "Row Height": 0.3,
                                       "Color1": (0.8, 0.3, 0.1), "Color2": (0.3, 0.6, 0.2),
                                       "Mortar": (0.1, 0.1, 0.1)},
               offset=0.4, offset_frequency=2, squash=0.8, squash_frequency=3)
    t.set(em, "Color", out(n, "Color"))


def t_gradient_linear(t, em):
    n = t.node("ShaderNodeTexGradient", {"Vector": t.coords("Generated")}, gradient_type='LINEAR')
    t.set(em, "Color", out(n, "Color"))


def t_gradient_spherical(t, em):
    n = t.node("ShaderNodeTexGradient", {"Vector": t.coords("Object")}, gradient_type='SPHERICAL')
    t.set(em, "Color", out(n, "Color"))


def t_white_noise_cells(t, em):
    # White noise of the cell index, so each 0.5 m cell has one hash colour (white noise of the raw
    # position would average to 0.5 over any block and test nothing).
    cell = t.vmath('FLOOR', t.vmath('SCALE', t.coords("Object"), scale=2.0))
    n = t.node("ShaderNodeTexWhiteNoise", {"Vector": cell}, noise_dimensions='3D')
    t.set(em, "Color", out(n, "Color"))


def _parity_image():
    """An 8x8 sRGB byte image of distinct colours, packed into the .blend."""
    img = bpy.data.images.get("parity_texels")
    if img is not None:
        return img
    size = 8
    img = bpy.data.images.new("parity_texels", size, size, alpha=True, float_buffer=False)
    img.colorspace_settings.name = 'sRGB'
    px = []
    for j in range(size):
        for i in range(size):
            px += [((i * 5 + j * 3) % 8) / 7.0, ((i * 2 + j * 7) % 8) / 7.0, ((i + j * 5) % 8) / 7.0 * 0.8 + 0.1,
                   1.0]
    img.pixels.foreach_set(px)
    img.file_format = 'PNG'
    img.pack()
    return img


def t_image_closest(t, em):
    n = t.node("ShaderNodeTexImage", {"Vector": t.coords("UV")}, interpolation='Closest', extension='REPEAT')
    n.image = _parity_image()
    t.set(em, "Color", out(n, "Color"))


def t_image_linear(t, em):
    # 1.5 repeats across the tile: texel borders and the wrap-around are inside it.
    uv = t.vmath('SCALE', t.coords("UV"), scale=1.5)
    n = t.node("ShaderNodeTexImage", {"Vector": uv}, interpolation='Linear', extension='REPEAT')
    n.image = _parity_image()
    t.set(em, "Color", out(n, "Color"))


def _ramp(t, fac, interpolation, stops):
    n = t.node("ShaderNodeValToRGB", {"Fac": fac})
    ramp = n.color_ramp
    ramp.interpolation = interpolation
    while len(ramp.elements) < len(stops):
        ramp.elements.new(0.5)
    for el, (pos, col) in zip(ramp.elements, stops):
        el.position = pos
        el.color = (*col, 1.0)
    return n


def t_color_ramp_linear(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    n = _ramp(t, x, 'LINEAR', [(0.1, (0.9, 0.1, 0.1)), (0.45, (0.1, 0.8, 0.2)), (0.85, (0.2, 0.3, 1.0))])
    t.set(em, "Color", out(n, "Color"))


def t_color_ramp_constant(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    fac = t.math('MULTIPLY', t.math('ADD', x, y), 0.5)
    n = _ramp(t, fac, 'CONSTANT', [(0.0, (0.9, 0.6, 0.1)), (0.3, (0.1, 0.8, 0.7)), (0.55, (0.7, 0.2, 0.9)),
                                    (0.8, (0.9, 0.9, 0.9))])
    t.set(em, "Color", out(n, "Color"))


def t_mix_multiply(t, em):
    n = t.node("ShaderNodeMix", data_type='RGBA', blend_type='MULTIPLY')
    t.set(n, "Factor", 0.8)
    t.set(n, "A", t.coords("Generated"))
    t.set(n, "B", (0.9, 0.5, 0.2))
    t.set(em, "Color", out(n, "Result"))


def t_mix_overlay(t, em):
    n = t.node("ShaderNodeMix", data_type='RGBA', blend_type='OVERLAY')
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    t.set(n, "Factor", y)
    t.set(n, "A", t.coords("Generated"))
    t.set(n, "B", (0.2, 0.7, 0.5))
    t.set(em, "Color", out(n, "Result"))


def t_mix_float(t, em):
    n = t.node("ShaderNodeMix", data_type='FLOAT')
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    t.set(n, "Factor", x)
    t.set(n, "A", 0.15)
    t.set(n, "B", t.math('MULTIPLY', y, 1.5))
    t.set(em, "Color", out(n, "Result"))


def t_mixrgb_legacy(t, em):
    n = t.node("ShaderNodeMixRGB", {"Fac": 0.7, "Color1": t.coords("Generated"), "Color2": (0.8, 0.3, 0.6)},
               blend_type='LINEAR_LIGHT', use_clamp=True)
    t.set(em, "Color", out(n, "Color"))


def t_math_basic(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    ox, oy, _ = t.separate_xyz(t.coords("Object"))
    r = t.math('POWER', x, 2.2)
    g = t.math('MULTIPLY_ADD', t.math('SINE', t.math('MULTIPLY', oy, 4.0)), 0.5, 0.5)
    b = t.math('SQRT', t.math('SMOOTH_MIN', x, y, 0.3))
    t.set(em, "Color", t.combine_rgb(r, g, b))


def t_math_wrap(t, em):
    ox, oy, _ = t.separate_xyz(t.coords("Object"))
    r = t.math('FRACT', t.math('MULTIPLY', ox, 1.7))
    g = t.math('PINGPONG', t.math('MULTIPLY', oy, 2.0), 0.7)
    b = t.math('WRAP', t.math('ADD', ox, oy), 0.9, 0.1)
    t.set(em, "Color", t.combine_rgb(r, g, b))


def t_math_safe(t, em):
    # Division by zero (bottom half of the tile), logarithm and square root of negative numbers:
    # Cycles' safe operations give 0 there.
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    ox, oy, _ = t.separate_xyz(t.coords("Object"))
    r = t.math('DIVIDE', x, t.math('FLOOR', t.math('MULTIPLY', y, 2.0)))
    # log2 of a negative number on the left half, of 1.2 .. 4.2 on the right (the argument jumps
    # over 0..1, so no output is negative).
    step = t.math('MULTIPLY', t.math('GREATER_THAN', ox, 0.0), 1.2)
    g = t.math('ADD', t.math('LOGARITHM', t.math('MULTIPLY_ADD', ox, 3.0, step), 2.0), 0.3)
    b = t.math('ADD', t.math('SQRT', oy), t.math('MULTIPLY_ADD', t.math('ARCTAN2', oy, ox), 0.05, 0.2))
    t.set(em, "Color", t.combine_rgb(r, g, b))


def t_vector_math_cross(t, em):
    v = t.vmath('CROSS_PRODUCT', t.coords("Object"), (0.3, 0.6, 0.9))
    t.set(em, "Color", t.vmath('ABSOLUTE', v))
    t.set(em, "Strength", t.vmath('LENGTH', t.coords("Object"), output="Value"))


def t_vector_math_misc(t, em):
    obj = t.coords("Object")
    frac = t.vmath('FRACTION', t.vmath('SCALE', obj, scale=1.3))
    refl = t.vmath('REFLECT', t.vmath('NORMALIZE', t.vmath('ADD', obj, (0.0, 0.0, 1.0))), (0.0, 0.6, 0.8))
    col = t.vmath('MULTIPLY_ADD', t.vmath('SNAP', frac, (0.25, 0.2, 0.5)), (0.6, 0.6, 0.6),
                  t.vmath('ABSOLUTE', refl))
    t.set(em, "Color", t.vmath('SCALE', col, scale=0.6))


def t_map_range(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    r = out(t.node("ShaderNodeMapRange", {"Value": x, "From Min": 0.2, "From Max": 0.7, "To Min": 0.1,
                                           "To Max": 0.9}, interpolation_type='LINEAR', clamp=True))
    g = out(t.node("ShaderNodeMapRange", {"Value": y, "From Min": 0.0, "From Max": 1.0, "To Min": 0.1,
                                           "To Max": 1.0, "Steps": 4.0}, interpolation_type='STEPPED'))
    b = out(t.node("ShaderNodeMapRange", {"Value": x, "From Min": 0.9, "From Max": 0.1, "To Min": 0.0,
                                           "To Max": 1.2}, interpolation_type='SMOOTHERSTEP'))
    t.set(em, "Color", t.combine_rgb(r, g, b))


def t_clamp(t, em):
    ox, oy, _ = t.separate_xyz(t.coords("Object"))
    r = out(t.node("ShaderNodeClamp", {"Value": t.math('MULTIPLY', ox, 1.5), "Min": 0.1, "Max": 0.8},
                   clamp_type='MINMAX'))
    g = out(t.node("ShaderNodeClamp", {"Value": oy, "Min": 0.7, "Max": 0.2}, clamp_type='RANGE'))
    t.set(em, "Color", t.combine_rgb(r, g, 0.3))


def t_hue_saturation(t, em):
    n = t.node("ShaderNodeHueSaturation", {"Hue": 0.3, "Saturation": 1.4, "Value": 0.9, "Fac": 1.0,
                                            "Color": t.coords("Generated")})
    t.set(em, "Color", out(n, "Color"))


def t_invert(t, em):
    n = t.node("ShaderNodeInvert", {"Fac": 0.8, "Color": t.coords("Generated")})
    t.set(em, "Color", out(n, "Color"))


def t_gamma(t, em):
    n = t.node("ShaderNodeGamma", {"Color": t.coords("Generated"), "Gamma": 2.2})
    t.set(em, "Color", out(n, "Color"))


def t_bright_contrast(t, em):
    n = t.node("ShaderNodeBrightContrast", {"Color": t.coords("Generated"), "Bright": 0.1, "Contrast": 0.4})
    t.set(em, "Color", out(n, "Color"))


def t_rgb_curves(t, em):
    n = t.node("ShaderNodeRGBCurve", {"Fac": 0.9, "Color": t.coords("Generated")})
    m = n.mapping
    m.curves[0].points.new(0.5, 0.8)             # red: lifted mid-tones
    m.curves[2].points[1].location = (1.0, 0.4)  # blue: compressed
    m.curves[3].points.new(0.3, 0.15)            # combined curve
    m.update()
    t.set(em, "Color", out(n, "Color"))


def t_separate_combine_rgb(t, em):
    col = t.node("ShaderNodeMixRGB", {"Fac": 1.0, "Color1": (0, 0, 0), "Color2": t.coords("Generated")},
                 blend_type='MIX')
    s = t.node("ShaderNodeSeparateRGB", {"Image": out(col)})
    c = t.node("ShaderNodeCombineRGB", {"R": s.outputs["B"], "G": s.outputs["R"], "B": s.outputs["G"]})
    t.set(em, "Color", out(c))


def t_separate_combine_xyz(t, em):
    x, y, z = t.separate_xyz(t.coords("Object"))
    c = t.node("ShaderNodeCombineXYZ", {"X": t.math('ABSOLUTE', y), "Y": z, "Z": t.math('ABSOLUTE', x)})
    t.set(em, "Color", out(c))


def t_separate_combine_hsv(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    s = t.node("ShaderNodeSeparateHSV", {"Color": t.combine_rgb(x, y, 0.3)})
    c = t.node("ShaderNodeCombineHSV", {"H": t.math('ADD', s.outputs["H"], 0.4), "S": s.outputs["S"],
                                         "V": s.outputs["V"]})
    t.set(em, "Color", out(c))


def t_separate_combine_color_hsl(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    s = t.node("ShaderNodeSeparateColor", {"Color": t.combine_rgb(0.8, x, y)}, mode='HSL')
    c = t.node("ShaderNodeCombineColor", {"Red": s.outputs[2], "Green": s.outputs[0], "Blue": s.outputs[1]},
               mode='HSV')
    t.set(em, "Color", out(c))


def t_rgb_to_bw(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    n = t.node("ShaderNodeRGBToBW", {"Color": t.combine_rgb(x, y, t.math('SUBTRACT', 1.0, x))})
    t.set(em, "Color", out(n))


def t_blackbody(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    temp = t.math('MULTIPLY_ADD', x, 9000.0, 1200.0)
    n = t.node("ShaderNodeBlackbody", {"Temperature": temp})
    t.set(em, "Color", out(n))


def t_wavelength(t, em):
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    n = t.node("ShaderNodeWavelength", {"Wavelength": t.math('MULTIPLY_ADD', x, 420.0, 370.0)})
    t.set(em, "Color", out(n))
    t.set(em, "Strength", 1.5)


def _mapped_checker(t, em, vector_type):
    n = t.node("ShaderNodeMapping", {"Vector": t.coords("Object"), "Location": (0.2, 0.1, 0.0),
                                      "Rotation": (0.0, 0.0, math.radians(30.0)), "Scale": (1.5, 0.8, 1.0)},
               vector_type=vector_type)
    ch = t.node("ShaderNodeTexChecker", {"Vector": out(n), "Scale": 1.5, "Color1": (0.95, 0.85, 0.2),
                                          "Color2": (0.15, 0.1, 0.5)})
    t.set(em, "Color", out(ch, "Color"))


def t_mapping_point(t, em):
    _mapped_checker(t, em, 'POINT')


def t_mapping_texture(t, em):
    _mapped_checker(t, em, 'TEXTURE')


def t_texcoord_generated(t, em):
    t.set(em, "Color", t.coords("Generated"))


def t_texcoord_object_empty(t, em):
    # Object coordinates of another object (an empty moved, turned and scaled): its inverse matrix.
    empty = bpy.data.objects.new("parity_empty", None)
    bpy.context.scene.collection.objects.link(empty)
    empty.location = TILE_CENTRES["texcoord_object_empty"][0] + 0.3, TILE_CENTRES["texcoord_object_empty"][1] - 0.2, 0.0
    empty.rotation_euler = (0.0, 0.0, math.radians(25.0))
    empty.scale = (0.8, 0.8, 0.8)
    tc = t.node("ShaderNodeTexCoord", object=empty)
    ch = t.node("ShaderNodeTexChecker", {"Vector": tc.outputs["Object"], "Scale": 1.0,
                                          "Color1": (0.9, 0.9, 0.9), "Color2": (0.6, 0.1, 0.2)})
    t.set(em, "Color", out(ch, "Color"))


def t_texcoord_uv(t, em):
    t.set(em, "Color", t.coords("UV"))


def _parity_group():
    """A node group (Vector, Scale -> Color, Fac) wrapping Noise -> Color Ramp and, nested, a second
    group (Value -> Math power)."""
    inner = bpy.data.node_groups.get("ParityInner")
    if inner is None:
        inner = bpy.data.node_groups.new("ParityInner", 'ShaderNodeTree')
        inner.inputs.new('NodeSocketFloat', "Value")
        inner.outputs.new('NodeSocketFloat', "Value")
        gt = Tree(inner)
        gin, gout = gt.node("NodeGroupInput"), gt.node("NodeGroupOutput")
        gt.set(gout, 0, gt.math('POWER', gin.outputs[0], 1.8))
    group = bpy.data.node_groups.get("ParityGroup")
    if group is None:
        group = bpy.data.node_groups.new("ParityGroup", 'ShaderNodeTree')
        group.inputs.new('NodeSocketVector', "Vector")
        group.inputs.new('NodeSocketFloat', "Scale")
        group.outputs.new('NodeSocketColor', "Color")
        group.outputs.new('NodeSocketFloat', "Fac")
        gt = Tree(group)
        gin, gout = gt.node("NodeGroupInput"), gt.node("NodeGroupOutput")
        noise = gt.node("ShaderNodeTexNoise", {"Vector": gin.outputs["Vector"], "Scale": gin.outputs["Scale"],
                                                "Detail": 2.0})
        ramp = _ramp(gt, out(noise, "Fac"), 'LINEAR', [(0.3, (0.1, 0.2, 0.6)), (0.7, (1.0, 0.8, 0.3))])
        sub = gt.node("ShaderNodeGroup", node_tree=inner)
        gt.set(sub, 0, out(noise, "Fac"))
        gt.set(gout, "Color", out(ramp, "Color"))
        gt.set(gout, "Fac", out(sub))
    return group


def t_node_group(t, em):
    g = t.node("ShaderNodeGroup", node_tree=_parity_group())
    t.set(g, "Vector", t.coords("Object"))
    t.set(g, "Scale", 2.5)
    t.set(em, "Color", g.outputs["Color"])
    t.set(em, "Strength", t.math('ADD', g.outputs["Fac"], 0.6))


def t_reroute(t, em):
    r1 = t.node("NodeReroute")
    t.nt.links.new(t.coords("Object"), r1.inputs[0])
    r2 = t.node("NodeReroute")
    t.nt.links.new(r1.outputs[0], r2.inputs[0])
    wave = t.node("ShaderNodeTexWave", {"Vector": r2.outputs[0], "Scale": 1.2}, wave_type='BANDS',
                  bands_direction='Y', wave_profile='TRI')
    r3 = t.node("NodeReroute")
    t.nt.links.new(out(wave, "Color"), r3.inputs[0])
    t.set(em, "Color", r3.outputs[0])


def t_muted_nodes(t, em):
    # A muted Math node passes its first input through, a muted Invert its Color.
    x, y, _ = t.separate_xyz(t.coords("Generated"))
    p = t.node("ShaderNodeMath", {0: x, 1: 4.0}, operation='POWER', mute=True)
    inv = t.node("ShaderNodeInvert", {"Fac": 1.0, "Color": t.combine_rgb(out(p), y, 0.4)}, mute=True)
    t.set(em, "Color", out(inv))


def t_mix_vector_non_uniform(t, em):
    n = t.node("ShaderNodeMix", data_type='VECTOR', factor_mode='NON_UNIFORM')
    t.set(n, "Factor", t.coords("Generated"))
    t.set(n, "A", (0.9, 0.1, 0.3))
    t.set(n, "B", (0.1, 0.9, 0.6))
    t.set(em, "Color", out(n, "Result"))


def t_mix_soft_light(t, em):
    n = t.node("ShaderNodeMix", data_type='RGBA', blend_type='SOFT_LIGHT')
    t.set(n, "Factor", 0.9)
    t.set(n, "A", t.coords("Generated"))
    t.set(n, "B", (0.8, 0.3, 0.5))
    t.set(em, "Color", out(n, "Result"))


def t_mix_hue(t, em):
    n = t.node("ShaderNodeMixRGB", {"Fac": 0.75, "Color1": t.coords("Generated"), "Color2": (0.2, 0.4, 0.9)},
               blend_type='HUE')
    t.set(em, "Color", out(n, "Color"))


def t_gradient_other_types(t, em):
    g = t.coords("Generated")
    o = t.coords("Object")
    chans = []
    for kind, vec in (("RADIAL", o), ("QUADRATIC_SPHERE", o), ("EASING", g)):
        chans.append(out(t.node("ShaderNodeTexGradient", {"Vector": vec}, gradient_type=kind), "Fac"))
    t.set(em, "Color", t.combine_rgb(*chans))


def t_voronoi_2d_chebychev_minkowski(t, em):
    o = t.coords("Object")
    a = t.node("ShaderNodeTexVoronoi", {"Vector": o, "Scale": 2.0}, voronoi_dimensions='2D', feature='F1',
               distance='CHEBYCHEV')
    b = t.node("ShaderNodeTexVoronoi", {"Vector": o, "Scale": 1.5, "Exponent": 0.7}, voronoi_dimensions='2D',
               feature='F1', distance='MINKOWSKI')
    t.set(em, "Color", t.combine_rgb(out(a, "Distance"), out(b, "Distance"), 0.3))


def t_image_cubic_extend(t, em):
    # Cubic interpolation; the UVs reach past 0..1 so Extend repeats the border texels.
    uv = t.vmath('MULTIPLY_ADD', t.coords("UV"), (1.4, 1.4, 1.0), (-0.2, -0.2, 0.0))
    n = t.node("ShaderNodeTexImage", {"Vector": uv}, interpolation='Cubic', extension='EXTEND')
    n.image = _parity_image()
    t.set(em, "Color", out(n, "Color"))


def t_vector_curves(t, em):
    n = t.node("ShaderNodeVectorCurve", {"Fac": 1.0, "Vector": t.coords("Object")})
    m = n.mapping
    m.curves[0].points.new(0.0, 0.6)
    m.curves[1].points[0].location = (-1.0, 0.2)
    m.curves[2].points[1].location = (1.0, 0.5)
    m.update()
    t.set(em, "Color", t.vmath('ABSOLUTE', out(n)))


def t_map_range_vector(t, em):
    n = t.node("ShaderNodeMapRange", data_type='FLOAT_VECTOR', interpolation_type='SMOOTHSTEP', clamp=True)
    t.set(n, "Vector", t.coords("Object"))
    t.set(n, "From Min", (-0.8, -0.5, -1.0))
    t.set(n, "From Max", (0.8, 0.9, 1.0))
    t.set(n, "To Min", (0.1, 0.0, 0.2))
    t.set(n, "To Max", (0.9, 1.0, 0.4))
    t.set(em, "Color", out(n, "Vector"))


TILES = [
    ("checker", t_checker), ("noise_3d", t_noise_3d), ("noise_4d", t_noise_4d),
    ("voronoi_f1_euclidean", t_voronoi_f1_euclidean), ("voronoi_f2_manhattan", t_voronoi_f2_manhattan),
    ("voronoi_smooth_f1", t_voronoi_smooth_f1), ("voronoi_distance_to_edge", t_voronoi_distance_to_edge),
    ("musgrave_fbm", t_musgrave_fbm),
    ("musgrave_ridged", t_musgrave_ridged), ("musgrave_hetero", t_musgrave_hetero), ("wave_bands", t_wave_bands),
    ("wave_rings_distortion", t_wave_rings_distortion), ("magic", t_magic), ("brick", t_brick),
    ("gradient_linear", t_gradient_linear), ("gradient_spherical", t_gradient_spherical),
    ("white_noise_cells", t_white_noise_cells), ("image_closest", t_image_closest),
    ("image_linear", t_image_linear), ("color_ramp_linear", t_color_ramp_linear),
    ("color_ramp_constant", t_color_ramp_constant), ("mix_multiply", t_mix_multiply),
    ("mix_overlay", t_mix_overlay), ("mix_float", t_mix_float),
    ("mixrgb_legacy", t_mixrgb_legacy), ("math_basic", t_math_basic), ("math_wrap", t_math_wrap),
    ("math_safe", t_math_safe), ("vector_math_cross", t_vector_math_cross),
    ("vector_math_misc", t_vector_math_misc), ("map_range", t_map_range), ("clamp", t_clamp),
    ("hue_saturation", t_hue_saturation), ("invert", t_invert), ("gamma", t_gamma),
    ("bright_contrast", t_bright_contrast), ("rgb_curves", t_rgb_curves),
    ("separate_combine_rgb", t_separate_combine_rgb), ("separate_combine_xyz", t_separate_combine_xyz),
    ("separate_combine_hsv", t_separate_combine_hsv),
    ("separate_combine_color_hsl", t_separate_combine_color_hsl), ("rgb_to_bw", t_rgb_to_bw),
    ("blackbody", t_blackbody), ("wavelength", t_wavelength), ("mapping_point", t_mapping_point),
    ("mapping_texture", t_mapping_texture), ("texcoord_generated", t_texcoord_generated),
    ("texcoord_object_empty", t_texcoord_object_empty), ("texcoord_uv", t_texcoord_uv),
    ("node_group", t_node_group), ("reroute", t_reroute), ("muted_nodes", t_muted_nodes),
    ("mix_vector_non_uniform", t_mix_vector_non_uniform), ("mix_soft_light", t_mix_soft_light),
    ("mix_hue", t_mix_hue), ("gradient_other_types", t_gradient_other_types),
    ("voronoi_2d_chebychev_minkowski", t_voronoi_2d_chebychev_minkowski),
    ("image_cubic_extend", t_image_cubic_extend), ("vector_curves", t_vector_curves),
    ("map_range_vector", t_map_range_vector),
]
TILE_CENTRES = {}


# --------------------------------------------------------------------------------------------------
# scenes
# --------------------------------------------------------------------------------------------------
def new_scene(res_x, res_y, samples, max_bounces):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = 'CYCLES'
    sc.render.resolution_x = res_x
    sc.render.resolution_y = res_y
    sc.render.resolution_percentage = 100
    sc.render.film_transparent = False
    sc.view_settings.view_transform = 'Standard'
    sc.view_settings.look = 'None'
    sc.view_settings.exposure = 0.0
    sc.view_settings.gamma = 1.0
    c = sc.cycles
    c.device = 'CPU'
    c.samples = samples
    c.seed = 0
    make_cycles_unbiased(sc, max_bounces=max_bounces)
    _smis_settings(sc, samples, max_bounces)
    return sc


def _smis_settings(sc, samples, max_bounces):
    """The same settings for our engine, when the add-on is enabled (scene.smis exists); otherwise
    they are stored as ID properties, which the add-on reads when it registers."""
    values = {"samples": samples, "max_bounces": max_bounces, "filter_type": 'BOX', "filter_width": 1.0,
              "integrator": 'PATH', "seed": 0}
    smis = getattr(sc, "smis", None)
    if smis is not None:
        for k, v in values.items():
            setattr(smis, k, v)
    else:
        enum_ids = {"filter_type": {'BLACKMAN_HARRIS': 0, 'GAUSSIAN': 1, 'BOX': 2}, "integrator": {'PATH': 0}}
        sc["smis"] = {k: (enum_ids[k][v] if k in enum_ids else v) for k, v in values.items()}


def set_world(sc, color, strength=1.0):
    w = bpy.data.worlds.new("World")
    w.use_nodes = True
    bg = w.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*color, 1.0)
    bg.inputs["Strength"].default_value = strength
    sc.world = w


def plane_mesh(name, half):
    me = bpy.data.meshes.new(name)
    me.from_pydata([(-half, -half, 0.0), (half, -half, 0.0), (half, half, 0.0), (-half, half, 0.0)], [],
                   [(0, 1, 2, 3)])
    uv = me.uv_layers.new(name="UVMap")
    for loop, co in zip(uv.data, [(0, 0), (1, 0), (1, 1), (0, 1)]):
        loop.uv = co
    me.update()
    return me


def build_emission(outdir):
    assert len(TILES) == COLS * ROWS, len(TILES)
    sc = new_scene(COLS * TILE_PX, ROWS * TILE_PX, samples=256, max_bounces=0)
    set_world(sc, (0.0, 0.0, 0.0), 0.0)
    width_m, height_m = COLS * TILE_M, ROWS * TILE_M
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.type = 'ORTHO'
    cam_data.ortho_scale = width_m  # spans the wider (x) side
    cam_data.clip_start, cam_data.clip_end = 0.1, 100.0
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (0.0, 0.0, 10.0)
    sc.collection.objects.link(cam)
    sc.camera = cam
    TILE_CENTRES.clear()
    layout = []
    for k, (name, _) in enumerate(TILES):
        col, row = k % COLS, k // COLS  # row 0 at the top of the image
        cx = -width_m / 2 + (col + 0.5) * TILE_M
        cy = height_m / 2 - (row + 0.5) * TILE_M
        TILE_CENTRES[name] = (cx, cy)
        layout.append({"name": name, "index": k, "x0": col * TILE_PX, "y0": (ROWS - 1 - row) * TILE_PX,
                       "size": TILE_PX})
    for k, (name, build) in enumerate(TILES):
        label = "tile_%02d_%s" % (k, name)
        mat, tree, em = emission_material(label)
        build(tree, em)
        ob = bpy.data.objects.new(label, plane_mesh(label, TILE_M / 2))
        ob.data.materials.append(mat)
        ob.location = (*TILE_CENTRES[name], 0.0)
        sc.collection.objects.link(ob)
        layout[k]["object"] = label
        layout[k]["nodes"] = sorted({n.bl_idname for n in mat.node_tree.nodes
                                     if n.bl_idname not in ("ShaderNodeOutputMaterial", "ShaderNodeEmission")})
    path = os.path.join(outdir, "node_parity_emission.blend")
    save(path)
    with open(os.path.join(outdir, "node_parity_emission.json"), "w") as f:
        json.dump({"tile_px": TILE_PX, "cols": COLS, "rows": ROWS, "tiles": layout}, f, indent=1)


# -- lit scene -------------------------------------------------------------------------------------
def node_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    output = nt.nodes.new("ShaderNodeOutputMaterial")
    return mat, Tree(nt), output


def mesh_object(sc, name, mat, location, primitive, **kw):
    primitive(location=location, **kw)
    ob = bpy.context.active_object
    ob.name = name
    ob.data.materials.append(mat)
    return ob


def lit_floor():
    """Diffuse floor: Brick colour, Bump from Noise."""
    mat, t, output = node_material("lit_floor_brick_bump")
    co = t.coords("Object")
    brick = t.node("ShaderNodeTexBrick", {"Vector": co, "Scale": 0.8, "Mortar Size": 0.04,
                                           "Color1": (0.7, 0.45, 0.3), "Color2": (0.45, 0.5, 0.55),
                                           "Mortar": (0.15, 0.15, 0.15)})
    noise = t.node("ShaderNodeTexNoise", {"Vector": co, "Scale": 3.0, "Detail": 3.0})
    bump = t.node("ShaderNodeBump", {"Strength": 0.6, "Distance": 0.2, "Height": out(noise, "Fac")})
    d = t.node("ShaderNodeBsdfDiffuse", {"Color": out(brick, "Color"), "Roughness": 0.0,
                                          "Normal": out(bump, "Normal")})
    t.set(output, "Surface", out(d))
    return mat


def lit_principled():
    """Principled: Base Color = Noise -> Color Ramp, Roughness = Voronoi -> Map Range,
    Metallic = Checker Fac."""
    mat, t, output = node_material("lit_principled_textured")
    co = t.coords("Object")
    noise = t.node("ShaderNodeTexNoise", {"Vector": co, "Scale": 3.0, "Detail": 2.0})
    ramp = _ramp(t, out(noise, "Fac"), 'LINEAR', [(0.35, (0.8, 0.15, 0.1)), (0.65, (0.2, 0.5, 0.9))])
    vor = t.node("ShaderNodeTexVoronoi", {"Vector": co, "Scale": 4.0}, feature='F1')
    rough = t.node("ShaderNodeMapRange", {"Value": out(vor, "Distance"), "From Min": 0.0, "From Max": 0.8,
                                           "To Min": 0.2, "To Max": 0.7})
    checker = t.node("ShaderNodeTexChecker", {"Vector": co, "Scale": 2.0})
    p = t.node("ShaderNodeBsdfPrincipled", {"Base Color": out(ramp, "Color"), "Roughness": out(rough),
                                             "Metallic": out(checker, "Fac")}, distribution='GGX')
    t.set(output, "Surface", out(p))
    return mat


def lit_layer_weight():
    """Mix Shader (Diffuse, Glossy GGX) by Layer Weight Fresnel; the diffuse colour from a Wave."""
    mat, t, output = node_material("lit_mix_layer_weight")
    wave = t.node("ShaderNodeTexWave", {"Vector": t.coords("Object"), "Scale": 2.0}, bands_direction='Z')
    col = t.node("ShaderNodeMixRGB", {"Fac": out(wave, "Fac"), "Color1": (0.1, 0.5, 0.2),
                                       "Color2": (0.9, 0.8, 0.3)})
    d = t.node("ShaderNodeBsdfDiffuse", {"Color": out(col), "Roughness": 0.0})
    g = t.node("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9), "Roughness": 0.25}, distribution='GGX')
    lw = t.node("ShaderNodeLayerWeight", {"Blend": 0.4})
    mix = t.node("ShaderNodeMixShader", {"Fac": lw.outputs["Fresnel"], 1: out(d), 2: out(g)})
    t.set(output, "Surface", out(mix))
    return mat


def lit_fresnel():
    """Mix Shader (Diffuse, Glossy GGX) by Fresnel (IOR from a Math node); the Glossy roughness from
    Magic -> RGB to BW."""
    mat, t, output = node_material("lit_mix_fresnel")
    d = t.node("ShaderNodeBsdfDiffuse", {"Color": (0.7, 0.2, 0.5), "Roughness": 0.0})
    magic = t.node("ShaderNodeTexMagic", {"Vector": t.coords("Object"), "Scale": 2.0})
    bw = t.node("ShaderNodeRGBToBW", {"Color": out(magic, "Color")})
    rough = t.math('MULTIPLY_ADD', out(bw), 0.4, 0.15)
    g = t.node("ShaderNodeBsdfGlossy", {"Color": (0.95, 0.9, 0.8), "Roughness": rough}, distribution='GGX')
    fr = t.node("ShaderNodeFresnel", {"IOR": t.math('ADD', 1.0, 0.6)})
    mix = t.node("ShaderNodeMixShader", {"Fac": out(fr), 1: out(d), 2: out(g)})
    t.set(output, "Surface", out(mix))
    return mat


def lit_normal_map():
    """Diffuse with a tangent-space Normal Map whose colour is computed from a Wave texture; its
    colour from a Gradient through Hue/Saturation."""
    mat, t, output = node_material("lit_normal_map")
    wave = t.node("ShaderNodeTexWave", {"Vector": t.coords("UV"), "Scale": 3.0}, bands_direction='X')
    tilt = t.math('MULTIPLY_ADD', out(wave, "Fac"), 0.5, 0.25)    # 0.25..0.75: +-0.5 in x
    ncol = t.node("ShaderNodeCombineXYZ", {"X": tilt, "Y": 0.5, "Z": 0.9})
    nmap = t.node("ShaderNodeNormalMap", {"Color": out(ncol), "Strength": 1.0}, space='TANGENT')
    grad = t.node("ShaderNodeTexGradient", {"Vector": t.coords("UV")})
    hsv = t.node("ShaderNodeHueSaturation", {"Color": out(grad, "Color"), "Hue": 0.6, "Saturation": 1.0,
                                              "Value": 1.0})
    col = t.node("ShaderNodeMixRGB", {"Fac": 0.6, "Color1": (0.8, 0.8, 0.8), "Color2": out(hsv)},
                 blend_type='MULTIPLY')
    d = t.node("ShaderNodeBsdfDiffuse", {"Color": out(col), "Roughness": 0.0, "Normal": out(nmap)})
    t.set(output, "Surface", out(d))
    return mat


def build_lit(outdir):
    sc = new_scene(160, 120, samples=2048, max_bounces=4)
    set_world(sc, (0.25, 0.28, 0.32), 1.0)
    col = sc.collection
    bpy.ops.mesh.primitive_plane_add(size=8.0, location=(0.0, 0.0, 0.0))
    floor = bpy.context.active_object
    floor.name = "lit_floor"
    floor.data.materials.append(lit_floor())
    # A wall behind, its normal map from nodes.
    bpy.ops.mesh.primitive_plane_add(size=4.0, location=(0.0, 1.6, 1.6), rotation=(math.radians(90.0), 0, 0))
    wall = bpy.context.active_object
    wall.name = "lit_wall_normal_map"
    wall.scale = (1.6, 0.8, 1.0)
    wall.data.materials.append(lit_normal_map())
    mesh_object(sc, "lit_sphere_principled", lit_principled(), (-1.05, 0.2, 0.6),
                bpy.ops.mesh.primitive_uv_sphere_add, radius=0.6, segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    mesh_object(sc, "lit_sphere_layer_weight", lit_layer_weight(), (0.25, -0.3, 0.5),
                bpy.ops.mesh.primitive_uv_sphere_add, radius=0.5, segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    cube = mesh_object(sc, "lit_cube_fresnel", lit_fresnel(), (1.35, 0.35, 0.45),
                       bpy.ops.mesh.primitive_cube_add, size=0.9)
    cube.rotation_euler = (0.0, 0.0, math.radians(30.0))
    sun_data = bpy.data.lights.new("Sun", 'SUN')
    sun_data.energy = 3.0
    sun_data.angle = math.radians(3.0)
    sun = bpy.data.objects.new("Sun", sun_data)
    sun.rotation_euler = (math.radians(40.0), math.radians(15.0), math.radians(-30.0))
    col.objects.link(sun)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.lens = 32.0
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (0.0, -5.2, 2.4)
    cam.rotation_euler = (math.radians(72.0), 0.0, 0.0)
    col.objects.link(cam)
    sc.camera = cam
    save(os.path.join(outdir, "node_parity_lit.blend"))


# -- geometry: tangent frames and the attributes derived from the mesh ------------------------------
# Low-poly smooth spheres whose emission shows a world-space direction (0.5 + 0.5 v): a tangent-space
# Normal Map, the Tangent node along the UV map and radially, and Geometry > Tangent. Per-triangle
# tangents would show the facets; Cycles interpolates MikkTSpace tangents. One sphere is mirrored and
# squashed (the frame's handedness and the normal transform). Then Pointiness on Suzanne, and on a
# sphere whose every edge is split (Cycles welds the copies back for Pointiness; every face is its
# own island for Random Per Island, shown in red).
GEOMETRY_OBJECTS = ["tangent_normal_map", "tangent_uv", "tangent_radial_x", "geometry_tangent",
                    "tangent_normal_map_mirrored", "pointiness", "pointiness_and_islands_split"]
GEOMETRY_PX = 48  # one column of the image per object


def _direction_material(name, build):
    mat, t, em = emission_material(name)
    direction = build(t)
    t.set(em, "Color", t.vmath('MULTIPLY_ADD', direction, (0.5, 0.5, 0.5), (0.5, 0.5, 0.5)))
    return mat


def _normal_map(t):
    return out(t.node("ShaderNodeNormalMap", {"Color": (0.8, 0.35, 0.75), "Strength": 1.0}, space='TANGENT'))


def _value_material(name, build):
    mat, t, em = emission_material(name)
    t.set(em, "Color", build(t, t.node("ShaderNodeNewGeometry")))
    return mat


def _sphere_with_faces_apart(name, radius, segments, rings):
    """A latitude-longitude sphere whose every face has its own copies of its corners, built with
    vertices, edges and loops in an explicit order: Random Per Island hashes the vertex index the
    union-by-rank over the edges ends at, so the edge order matters, and Blender's primitives and its
    own edge building order faces and edges differently from run to run."""
    def point(ring, seg):
        theta, phi = math.pi * ring / rings, 2.0 * math.pi * seg / segments
        return (radius * math.sin(theta) * math.cos(phi), radius * math.sin(theta) * math.sin(phi),
                radius * math.cos(theta))
    faces = []
    for ring in range(rings):
        for seg in range(segments):
            quad = [(ring, seg), (ring + 1, seg), (ring + 1, seg + 1), (ring, seg + 1)]
            if ring == 0:
                quad.pop(0)          # the pole is one point
            elif ring == rings - 1:
                quad.pop(1)
            faces.append([point(r, k) for r, k in quad])
    me = bpy.data.meshes.new(name)
    corners = [c for f in faces for c in f]
    sizes = [len(f) for f in faces]
    starts = [sum(sizes[:i]) for i in range(len(sizes))]
    me.vertices.add(len(corners))
    me.vertices.foreach_set("co", [x for c in corners for x in c])
    me.edges.add(len(corners))
    me.loops.add(len(corners))
    edge_vertices = [v for start, size in zip(starts, sizes) for i in range(size)
                     for v in (start + i, start + (i + 1) % size)]
    me.edges.foreach_set("vertices", edge_vertices)
    me.loops.foreach_set("vertex_index", list(range(len(corners))))
    me.loops.foreach_set("edge_index", list(range(len(corners))))
    me.polygons.add(len(faces))
    me.polygons.foreach_set("loop_start", starts)
    me.polygons.foreach_set("loop_total", sizes)
    me.update()
    return me


def build_geometry(outdir):
    n = len(GEOMETRY_OBJECTS)
    sc = new_scene(n * GEOMETRY_PX, GEOMETRY_PX, samples=64, max_bounces=0)
    set_world(sc, (0.0, 0.0, 0.0), 0.0)
    directions = {
        "tangent_normal_map": _normal_map,
        "tangent_uv": lambda t: out(t.node("ShaderNodeTangent", direction_type='UV_MAP')),
        "tangent_radial_x": lambda t: out(t.node("ShaderNodeTangent", direction_type='RADIAL', axis='X')),
        "geometry_tangent": lambda t: out(t.node("ShaderNodeNewGeometry"), "Tangent"),
        "tangent_normal_map_mirrored": _normal_map,
    }
    values = {
        "pointiness": lambda t, g: out(g, "Pointiness"),
        "pointiness_and_islands_split": lambda t, g: out(t.node("ShaderNodeCombineXYZ", {
            "X": out(g, "Random Per Island"), "Y": out(g, "Pointiness"), "Z": 0.0})),
    }
    for k, name in enumerate(GEOMETRY_OBJECTS):
        location = (-n + 1.0 + 2.0 * k, 0.0, 0.0)
        if name in directions:
            ob = mesh_object(sc, name, _direction_material(name, directions[name]), location,
                             bpy.ops.mesh.primitive_uv_sphere_add, radius=0.9, segments=10, ring_count=6)
        elif name == "pointiness":
            ob = mesh_object(sc, name, _value_material(name, values[name]), location,
                             bpy.ops.mesh.primitive_monkey_add, size=1.3)
        else:
            ob = bpy.data.objects.new(name, _sphere_with_faces_apart(name, 0.9, 10, 6))
            ob.data.materials.append(_value_material(name, values[name]))
            ob.location = location
            sc.collection.objects.link(ob)
            bpy.context.view_layer.objects.active = ob
            ob.select_set(True)
        bpy.ops.object.shade_smooth()
        ob.rotation_euler = (math.radians(20.0), math.radians(-15.0), math.radians(35.0))
        if name.endswith("mirrored"):
            ob.scale = (-1.0, 1.0, 0.8)
    cam_data = bpy.data.cameras.new("Camera")
    cam_data.type = 'ORTHO'
    cam_data.ortho_scale = 2.0 * n
    cam = bpy.data.objects.new("Camera", cam_data)
    cam.location = (0.0, 0.0, 10.0)
    sc.collection.objects.link(cam)
    sc.camera = cam
    save(os.path.join(outdir, "node_parity_geometry.blend"))


def save(path):
    bpy.ops.wm.save_as_mainfile(filepath=path, compress=True)
    print("node_parity: wrote", path)


def main():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    outdir = os.path.abspath(args[0]) if args else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(outdir, exist_ok=True)
    build_emission(outdir)
    build_lit(outdir)
    build_geometry(outdir)


main()
