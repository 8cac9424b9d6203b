"""The closure scene (issue 19): one sphere per BSDF closure, for parity with Cycles.

Run:
    blender -b --factory-startup --python scenes/closures.py -- OUTDIR [SET]

SET is `closures` (the default: every closure), `closures_principled` (the Principled BSDF's
transmission and Multiscatter GGX, 3 x 2 tiles, PRINCIPLED_CLOSURES), `closures_beckmann` (Glass and
Refraction with the Beckmann distribution, 2 x 1 tiles), `closures_multiglass` (Multiscatter GGX
glass, 4 x 2 tiles, MULTIGLASS_CLOSURES), `closures_aniso` (Ashikhmin-Shirley and several
anisotropic closures in one material, 3 x 2 tiles, ANISO_CLOSURES) or `closures_msaniso` (anisotropic
Multiscatter GGX, 3 x 2 tiles, MSANISO_CLOSURES) or `closures_multiglass_world` (the Principled
multiscatter glass colours under the world alone, not sampled as a light: 2 x 1 tiles). Writes (for the default set)
  OUTDIR/closures.blend  COLS x ROWS tiles of TILE_PX x TILE_PX pixels (COLS*TILE_PX x ROWS*TILE_PX):
      an orthographic camera looking straight down (-Z) at one sphere per tile (radius 0.85 of the
      tile's half size, so every sphere has its own 32 x 32 px square of 4 x 4 blocks of 8 x 8 px),
      lit by a sun (5 degrees wide) from the upper left (so a sphere shows its whole range of angles, and the grazing
      rims that Velvet and Oren-Nayar brighten) and a uniform grey world (which the transmissive
      spheres show through themselves). No floor: each tile depends on its sphere only.
      Objects and materials are named `tile_NN_<closure>`.
  OUTDIR/closures.json   the tiles: name, pixel rectangle (x0, y0, size; row 0 is the image's BOTTOM
      row, as in Blender's pixel buffers) and the closure it shows.

Saved for Cycles with the project's unbiased settings (scenes/cycles_settings.py) and for SMIS
(path tracing, BOX filter 1 px), max bounces 8, view transform Standard.
"""
import json
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_settings import make_cycles_unbiased  # noqa: E402

TILE_PX = 32
TILE_M = 2.0
COLS, ROWS = 4, 6
MAX_BOUNCES = 8


def _bsdf(nt, idname, inputs, **props):
    n = nt.nodes.new(idname)
    for k, v in props.items():
        setattr(n, k, v)
    for k, v in inputs.items():
        sock = n.inputs[k]
        sock.default_value = (*v, 1.0) if sock.type == 'RGBA' and len(v) == 3 else v
    return n


def _add(nt, a, b):
    n = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(a.outputs[0], n.inputs[0])
    nt.links.new(b.outputs[0], n.inputs[1])
    return n


def _mix(nt, fac, a, b):
    n = nt.nodes.new("ShaderNodeMixShader")
    n.inputs[0].default_value = fac
    nt.links.new(a.outputs[0], n.inputs[1])
    nt.links.new(b.outputs[0], n.inputs[2])
    return n


def _textured_oren_nayar(nt):
    """Diffuse whose Roughness varies over the sphere (0 to 1 by height): Lambert and Oren-Nayar per hit."""
    d = _bsdf(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.6, 0.6, 0.6)})
    coords = nt.nodes.new("ShaderNodeTexCoord")
    sep = nt.nodes.new("ShaderNodeSeparateXYZ")
    nt.links.new(coords.outputs["Generated"], sep.inputs[0])
    nt.links.new(sep.outputs["Y"], d.inputs["Roughness"])
    return d


# (name, builder(node_tree) -> shader node). The Lambert and glass spheres are the controls.
CLOSURES = [
    ("diffuse_lambert", lambda nt: _bsdf(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.5, 0.3)})),
    ("oren_nayar_0p5", lambda nt: _bsdf(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.5, 0.3), "Roughness": 0.5})),
    ("oren_nayar_1", lambda nt: _bsdf(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.3, 0.6, 0.8), "Roughness": 1.0})),
    ("velvet_0p5", lambda nt: _bsdf(nt, "ShaderNodeBsdfVelvet", {"Color": (0.7, 0.2, 0.3), "Sigma": 0.5})),
    ("velvet_0p2", lambda nt: _bsdf(nt, "ShaderNodeBsdfVelvet", {"Color": (0.8, 0.8, 0.8), "Sigma": 0.2})),
    # the public glTF sheen scene's set-up: a Principled base plus Velvet (19_sheen.blend)
    ("principled_plus_velvet", lambda nt: _add(nt, _bsdf(nt, "ShaderNodeBsdfPrincipled",
                                                         {"Base Color": (0.8, 0.8, 0.8), "Roughness": 0.5}),
                                               _bsdf(nt, "ShaderNodeBsdfVelvet", {"Color": (0.1, 0.2, 0.3),
                                                                                  "Sigma": 0.8}))),
    ("translucent", lambda nt: _bsdf(nt, "ShaderNodeBsdfTranslucent", {"Color": (0.5, 0.8, 0.3)})),
    # a leaf: half diffuse, half translucent
    ("leaf", lambda nt: _mix(nt, 0.5, _bsdf(nt, "ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.5, 0.1)}),
                             _bsdf(nt, "ShaderNodeBsdfTranslucent", {"Color": (0.4, 0.8, 0.2)}))),
    ("refraction_sharp", lambda nt: _bsdf(nt, "ShaderNodeBsdfRefraction", {"Color": (0.9, 0.9, 1.0), "IOR": 1.45},
                                          distribution='SHARP')),
    ("refraction_ggx_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfRefraction", {"Color": (1.0, 0.9, 0.8), "IOR": 1.45,
                                                                           "Roughness": 0.3}, distribution='GGX')),
    ("glass_ggx_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"IOR": 1.45, "Roughness": 0.3},
                                       distribution='GGX')),
    ("glossy_ggx_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.8, 0.8, 0.8), "Roughness": 0.3},
                                        distribution='GGX')),
    ("glossy_beckmann_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.8, 0.8, 0.8), "Roughness": 0.3},
                                             distribution='BECKMANN')),
    ("glossy_beckmann_0p6", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.6, 0.3), "Roughness": 0.6},
                                             distribution='BECKMANN')),
    ("oren_nayar_textured", lambda nt: _textured_oren_nayar(nt)),
    ("toon_diffuse", lambda nt: _bsdf(nt, "ShaderNodeBsdfToon", {"Color": (0.4, 0.6, 0.9), "Size": 0.5, "Smooth": 0.0},
                                      component='DIFFUSE')),
    # alone: Cycles' Toon Glossy reports its cone's density for every direction above the surface (its
    # value is 0 outside the cone), which biases Cycles' MIS darker wherever another closure of the same
    # material samples outside the cone (measured 7.9% darker for Diffuse + Toon Glossy); alone it is exact.
    ("toon_glossy", lambda nt: _bsdf(nt, "ShaderNodeBsdfToon", {"Color": (0.8, 0.8, 0.8), "Size": 0.3, "Smooth": 0.0},
                                     component='GLOSSY')),
    # multiscatter GGX (Heitz et al. 2016's random walk in Cycles 3.4): little multiple scattering at 0.3,
    # much at 0.8 (white: see test_closures.py's KNOWN for the coloured one, which Cycles' walk tints
    # again at each further bounce)
    ("glossy_multi_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.8, 0.8, 0.8), "Roughness": 0.3},
                                          distribution='MULTI_GGX')),
    ("glossy_multi_0p8", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (1.0, 1.0, 1.0), "Roughness": 0.8},
                                          distribution='MULTI_GGX')),
    # anisotropic GGX and Beckmann with the default tangent (radial around the object's Z, the view axis)
    ("anisotropic_ggx", lambda nt: _bsdf(nt, "ShaderNodeBsdfAnisotropic",
                                         {"Color": (0.8, 0.8, 0.8), "Roughness": 0.4, "Anisotropy": 0.7,
                                          "Rotation": 0.1}, distribution='GGX')),
    ("anisotropic_beckmann", lambda nt: _bsdf(nt, "ShaderNodeBsdfAnisotropic",
                                              {"Color": (0.7, 0.8, 0.9), "Roughness": 0.4, "Anisotropy": -0.5},
                                              distribution='BECKMANN')),
    ("principled_anisotropic", lambda nt: _bsdf(nt, "ShaderNodeBsdfPrincipled",
                                                {"Base Color": (0.9, 0.6, 0.3), "Metallic": 1.0, "Roughness": 0.4,
                                                 "Anisotropic": 0.8, "Anisotropic Rotation": 0.25})),
    ("glossy_multi_0p8_tinted", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy",
                                                 {"Color": (0.9, 0.7, 0.5), "Roughness": 0.8},
                                                 distribution='MULTI_GGX')),
]
assert len(CLOSURES) <= COLS * ROWS


def _principled(inputs, distribution='GGX'):
    return lambda nt: _bsdf(nt, "ShaderNodeBsdfPrincipled", inputs, distribution=distribution)


# The Principled BSDF v1's transmission and its Multiscatter GGX (closures_principled.blend): Cycles 3.4
# reflects untinted glass white and tints it by Specular Tint, colours the refraction by the base, and
# refracts at 1 - (1 - Roughness)(1 - Transmission Roughness) for GGX, at the Roughness for Multiscatter
# GGX (whose smooth glass, Roughness <= 0.05, is the single-scatter pair).
PRINCIPLED_CLOSURES = [
    ("principled_glass_transmission_roughness", _principled({"Base Color": (0.9, 0.6, 0.4), "Transmission": 1.0,
                                                             "Roughness": 0.15, "Transmission Roughness": 0.5,
                                                             "IOR": 1.45})),
    ("principled_glass_specular_tint", _principled({"Base Color": (0.3, 0.6, 0.9), "Transmission": 1.0,
                                                    "Roughness": 0.3, "Specular Tint": 1.0, "IOR": 1.5})),
    ("principled_glass_sharp_reflection", _principled({"Base Color": (0.8, 0.9, 0.8), "Transmission": 1.0,
                                                       "Roughness": 0.0, "Transmission Roughness": 0.35,
                                                       "IOR": 1.45})),
    ("principled_half_glass", _principled({"Base Color": (0.7, 0.4, 0.6), "Transmission": 0.6, "Roughness": 0.35,
                                           "Transmission Roughness": 0.3, "Specular Tint": 0.5, "IOR": 1.45})),
    ("principled_multi_smooth_glass", _principled({"Base Color": (0.9, 0.9, 0.7), "Transmission": 1.0,
                                                   "Roughness": 0.04, "Transmission Roughness": 0.6, "IOR": 1.45},
                                                  distribution='MULTI_GGX')),
    ("principled_multi_metal", _principled({"Base Color": (0.9, 0.7, 0.5), "Metallic": 1.0, "Roughness": 0.8},
                                           distribution='MULTI_GGX')),
]
# Glass and Refraction with the Beckmann distribution (closures_beckmann.blend): Cycles 3.4's pair of
# Beckmann glass closures weighted by the Fresnel term at the normal, and the Beckmann refraction.
BECKMANN_CLOSURES = [
    ("glass_beckmann_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"Color": (0.9, 0.8, 0.6), "Roughness": 0.3,
                                                                        "IOR": 1.45}, distribution='BECKMANN')),
    ("refraction_beckmann_0p4", lambda nt: _bsdf(nt, "ShaderNodeBsdfRefraction",
                                                 {"Color": (0.6, 0.8, 0.9), "Roughness": 0.4, "IOR": 1.5},
                                                 distribution='BECKMANN')),
]
# Multiscatter GGX glass (closures_multiglass.blend): Cycles 3.4's one multiscatter glass closure of the
# Glass BSDF (its colour at every bounce of the walk) and of the Principled BSDF's rough transmission
# (Roughness > 0.05; its base colour at every refraction, and with Specular Tint the interpolated
# Fresnel colour of cspec0 = lerp(1, base, Specular Tint) at every reflection).
MULTIGLASS_CLOSURES = [
    ("glass_multi_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"IOR": 1.45, "Roughness": 0.3},
                                         distribution='MULTI_GGX')),
    ("glass_multi_0p8", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"IOR": 1.45, "Roughness": 0.8},
                                         distribution='MULTI_GGX')),
    ("glass_multi_0p6_tinted", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"Color": (0.9, 0.7, 0.5), "IOR": 1.45,
                                                                          "Roughness": 0.6}, distribution='MULTI_GGX')),
    ("glass_multi_1_ior2", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlass", {"IOR": 2.0, "Roughness": 1.0},
                                            distribution='MULTI_GGX')),
    ("principled_multi_glass_0p5", _principled({"Base Color": (1.0, 1.0, 1.0), "Transmission": 1.0,
                                                "Roughness": 0.5, "IOR": 1.45}, distribution='MULTI_GGX')),
    ("principled_multi_glass_tinted", _principled({"Base Color": (0.9, 0.7, 0.5), "Transmission": 1.0,
                                                   "Roughness": 0.8, "IOR": 1.45}, distribution='MULTI_GGX')),
    ("principled_multi_glass_specular_tint", _principled({"Base Color": (0.3, 0.6, 0.9), "Transmission": 1.0,
                                                          "Roughness": 0.7, "Specular Tint": 1.0, "IOR": 1.45},
                                                         distribution='MULTI_GGX')),
]


def _anisotropic(inputs, distribution='GGX'):
    return lambda nt: _bsdf(nt, "ShaderNodeBsdfAnisotropic", inputs, distribution=distribution)


def _radial_x_tangent(build):
    """`build`'s closure with its Tangent from a Tangent node (radial about the object's X axis)."""
    def with_tangent(nt):
        node = build(nt)
        tangent = nt.nodes.new("ShaderNodeTangent")
        tangent.direction_type = 'RADIAL'
        tangent.axis = 'X'
        nt.links.new(tangent.outputs["Tangent"], node.inputs["Tangent"])
        return node
    return with_tangent


# Ashikhmin-Shirley (Glossy and Anisotropic BSDF) and materials with several anisotropic closures, each
# about its own tangent and rotation (closures_aniso.blend, 3 x 2 tiles; the default tangent is radial
# about the object's Z, the view axis).
ANISO_CLOSURES = [
    ("glossy_ashikhmin_0p3", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.8, 0.8, 0.8), "Roughness": 0.3},
                                              distribution='ASHIKHMIN_SHIRLEY')),
    ("glossy_ashikhmin_0p7", lambda nt: _bsdf(nt, "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.6, 0.3), "Roughness": 0.7},
                                              distribution='ASHIKHMIN_SHIRLEY')),
    ("anisotropic_ashikhmin", _anisotropic({"Color": (0.7, 0.8, 0.9), "Roughness": 0.4, "Anisotropy": 0.7,
                                            "Rotation": 0.1}, 'ASHIKHMIN_SHIRLEY')),
    ("anisotropic_mix_rotations", lambda nt: _mix(
        nt, 0.5, _anisotropic({"Color": (0.9, 0.5, 0.2), "Roughness": 0.3, "Anisotropy": 0.8})(nt),
        _anisotropic({"Color": (0.2, 0.5, 0.9), "Roughness": 0.3, "Anisotropy": 0.8, "Rotation": 0.25})(nt))),
    ("principled_mix_ashikhmin", lambda nt: _mix(
        nt, 0.5, _principled({"Base Color": (0.9, 0.6, 0.3), "Metallic": 1.0, "Roughness": 0.4,
                              "Anisotropic": 0.8})(nt),
        _anisotropic({"Color": (0.3, 0.6, 0.9), "Roughness": 0.35, "Anisotropy": -0.6, "Rotation": 0.15},
                     'ASHIKHMIN_SHIRLEY')(nt))),
    ("anisotropic_mix_tangents", lambda nt: _mix(
        nt, 0.5, _radial_x_tangent(_anisotropic({"Color": (0.8, 0.8, 0.3), "Roughness": 0.3,
                                                  "Anisotropy": 0.8}))(nt),
        _anisotropic({"Color": (0.3, 0.8, 0.8), "Roughness": 0.3, "Anisotropy": 0.8})(nt))),
]
# Anisotropic Multiscatter GGX (closures_msaniso.blend, 3 x 2 tiles): the Anisotropic BSDF and the Principled
# BSDF with Multiscatter GGX and Anisotropy != 0 (lobes/multiscatter_aniso_ggx.h), white where Cycles' eval
# would tint its further bounces twice (see the coloured Glossy), with the single-scatter GGX sphere of the
# first as a control (how much the multiple scattering adds).
MSANISO_CLOSURES = [
    ("aniso_multi_0p8_0p7", _anisotropic({"Color": (1.0, 1.0, 1.0), "Roughness": 0.8, "Anisotropy": 0.7},
                                         'MULTI_GGX')),
    ("aniso_multi_1_m0p5", _anisotropic({"Color": (1.0, 1.0, 1.0), "Roughness": 1.0, "Anisotropy": -0.5,
                                         "Rotation": 0.15}, 'MULTI_GGX')),
    ("aniso_multi_0p6_0p9_tangent", _radial_x_tangent(_anisotropic({"Color": (1.0, 1.0, 1.0), "Roughness": 0.6,
                                                                    "Anisotropy": 0.9}, 'MULTI_GGX'))),
    ("principled_multi_aniso_metal", _principled({"Base Color": (0.95, 0.95, 0.95), "Metallic": 1.0, "Roughness": 0.8,
                                                  "Anisotropic": 0.6}, 'MULTI_GGX')),
    ("principled_multi_aniso_dielectric", _principled({"Base Color": (0.8, 0.3, 0.2), "Roughness": 0.6,
                                                       "Anisotropic": 0.8, "Anisotropic Rotation": 0.1}, 'MULTI_GGX')),
    ("aniso_ggx_0p8_0p7", _anisotropic({"Color": (1.0, 1.0, 1.0), "Roughness": 0.8, "Anisotropy": 0.7})),
]
# The Principled multiscatter glass colours under the grey world alone, which Cycles does not sample as a
# light (closures_multiglass_world.blend, 2 x 1 tiles): Cycles' image is then its sampled walk (mf_sample),
# which ours follows, without its light samples' eval (mf_eval), whose inconsistencies (README, the
# material table) leave the sun-lit sets several percent away.
MULTIGLASS_WORLD_CLOSURES = [c for c in MULTIGLASS_CLOSURES
                             if c[0] in ("principled_multi_glass_tinted", "principled_multi_glass_specular_tint")]
# name -> (closures, columns, rows); a set whose name ends in _world has no sun (see build).
CLOSURE_SETS = {"closures": (CLOSURES, COLS, ROWS), "closures_principled": (PRINCIPLED_CLOSURES, 3, 2),
                "closures_beckmann": (BECKMANN_CLOSURES, 2, 1), "closures_multiglass": (MULTIGLASS_CLOSURES, 4, 2),
                "closures_aniso": (ANISO_CLOSURES, 3, 2), "closures_msaniso": (MSANISO_CLOSURES, 3, 2),
                "closures_multiglass_world": (MULTIGLASS_WORLD_CLOSURES, 2, 1)}


def node_material(name, build):
    """A material whose Surface is the node `build(node_tree)` returns (also used by scenes/hair.py)."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    output = nt.nodes.new("ShaderNodeOutputMaterial")
    nt.links.new(build(nt).outputs[0], output.inputs["Surface"])
    return mat


def build(out_dir, set_name="closures"):
    closures, cols, rows = CLOSURE_SETS[set_name]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.render.resolution_x, scene.render.resolution_y = cols * TILE_PX, rows * TILE_PX
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = 'Standard'
    world = bpy.data.worlds.new("Grey")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.25, 0.25, 0.25, 1.0)
    scene.world = world
    world_only = set_name.endswith("_world")
    if world_only:
        world.cycles.sampling_method = 'NONE'  # Cycles reaches the world by BSDF samples only

    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = max(cols, rows) * TILE_M  # spans the longer side of the image
    cam.location = (0.0, 0.0, 10.0)
    scene.collection.objects.link(cam)
    scene.camera = cam

    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    sun.data.energy = 3.0
    sun.data.angle = math.radians(5.0)  # a soft sun: converges faster through the rough refractors
    sun.rotation_euler = (math.radians(40.0), 0.0, math.radians(-35.0))
    if not world_only:
        scene.collection.objects.link(sun)

    tiles = []
    for i, (name, builder) in enumerate(closures):
        col, row = i % cols, i // cols  # row 0 at the top of the image
        x = (col - (cols - 1) / 2) * TILE_M
        y = ((rows - 1) / 2 - row) * TILE_M
        label = "tile_%02d_%s" % (i, name)
        bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=0.85 * TILE_M / 2,
                                             location=(x, y, 0.0))
        ob = bpy.context.active_object
        ob.name = label
        bpy.ops.object.shade_smooth()
        ob.data.materials.append(node_material(label, builder))
        tiles.append({"index": i, "name": name, "x0": col * TILE_PX, "y0": (rows - 1 - row) * TILE_PX,
                      "size": TILE_PX})

    scene.cycles.max_bounces = MAX_BOUNCES
    make_cycles_unbiased(scene)
    smis = scene.smis if hasattr(scene, "smis") else None
    if smis is not None:
        smis.integrator = 'PATH'
        smis.max_bounces = MAX_BOUNCES
        smis.filter_type = 'BOX'
        smis.filter_width = 1.0
    os.makedirs(out_dir, exist_ok=True)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(out_dir, set_name + ".blend"))
    with open(os.path.join(out_dir, set_name + ".json"), "w") as f:
        json.dump({"tile_px": TILE_PX, "tiles": tiles}, f, indent=1)


if __name__ == "__main__":
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    build(args[0] if args else os.path.dirname(__file__), args[1] if len(args) > 1 else "closures")
