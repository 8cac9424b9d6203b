"""The hair scene (issue 19): a field of particle hair on a plane under a sun and a grey world, for
parity with Cycles' curves and hair closures.

Run:
    blender -b --factory-startup --python scenes/hair.py -- OUTDIR [MATERIAL ...]

MATERIAL: `hair_bsdf` (default: Cycles' Hair BSDF, a Reflection plus a Transmission closure), or the
Principled Hair BSDF `principled_color`, `principled_melanin`, `principled_absorption` (its three
colour parametrisations), `principled_random` (melanin and roughness varied per strand by Random Color
and Random Roughness), `info_intercept` and `info_geometry` (a Diffuse BSDF coloured by Hair
Info's Intercept through a colour ramp, and by Length, Thickness and Tangent Normal), `emissive`
(glowing strands: an Emission coloured along the strand plus a Diffuse BSDF), `uv` (a Diffuse BSDF
coloured by the strand's UV, the emitter's UV map at its root), `vcol` (one coloured by the emitter's
colour layer at the root); with the suffix `_direct`, the same
lit by the sun alone (black world, max bounces 0: direct light only, where Cycles' Hair BSDF
evaluates what it defines, lobes/hair.h); with
`_curves` (before `_direct`), the strands converted to a Curves object (hair curves) instead; with
`_ribbons` (before `_direct`), Cycles' "Rounded Ribbons" curve shape instead of "3D Curves"; with
`_close` (after `_ribbons`), a 400 mm lens instead of 40 (strands several pixels wide); with
`_moving` (after `_close`), the emitter and its hair sliding MOVE (0.05 m) along x per frame, motion blur on
(shutter 0.5, frame 1); with
the suffix `_sun`, lit by the sun alone through max bounces 8 (light bounced between strands).
Writes OUTDIR/hair_<MATERIAL>.blend for each: a 64 x 48 px view at 45 degrees down onto a 2 x 2 m
plane (a grey diffuse emitter) growing 400 parent strands with 8 interpolated children each (3,600
strands of 9 points as Cycles renders them: render_step 3), 0.5 m long and tilted at random, of
radius 0.01 m at the root to 0 at the tip (Cycles' default thick round curves), lit by a sun
(3 W/m^2, 20 for principled_random; 5 degrees wide) from the side and a uniform grey world (0.25). Saved for Cycles with the
project's unbiased settings (scenes/cycles_settings.py) and for SMIS (path tracing, BOX filter 1 px),
max bounces 8, view transform Standard.
"""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from closures import node_material  # noqa: E402
from cycles_settings import make_cycles_unbiased  # noqa: E402

MAX_BOUNCES = 8
# The lens of the `_close` views (40 mm otherwise): a tenth of the field, strands several pixels wide.
CLOSE_LENS = 400
# How far the `_moving` hair slides per frame (m): about 16 pixels of the close view per frame.
MOVE = 0.05
WIDTH, HEIGHT = 64, 48


def _hair_bsdf(nt, parts=("Reflection", "Transmission")):
    r = nt.nodes.new("ShaderNodeBsdfHair")
    r.component = 'Reflection'
    r.inputs["Color"].default_value = (0.5, 0.4, 0.3, 1.0)
    r.inputs["Offset"].default_value = math.radians(3.0)
    r.inputs["RoughnessU"].default_value = 0.2
    r.inputs["RoughnessV"].default_value = 0.6
    t = nt.nodes.new("ShaderNodeBsdfHair")
    t.component = 'Transmission'
    t.inputs["Color"].default_value = (0.4, 0.3, 0.2, 1.0)
    t.inputs["RoughnessU"].default_value = 0.3
    t.inputs["RoughnessV"].default_value = 0.8
    if len(parts) == 1:
        return r if parts[0] == "Reflection" else t
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(r.outputs[0], add.inputs[0])
    nt.links.new(t.outputs[0], add.inputs[1])
    return add


def _principled_hair(parametrization, **inputs):
    def build(nt):
        n = nt.nodes.new("ShaderNodeBsdfHairPrincipled")
        n.parametrization = parametrization
        for k, v in inputs.items():
            sock = n.inputs[k]
            sock.default_value = (*v, 1.0) if sock.type == 'RGBA' else v
        return n
    return build


def _diffuse(nt):
    n = nt.nodes.new("ShaderNodeBsdfDiffuse")
    n.inputs["Color"].default_value = (0.6, 0.5, 0.4, 1.0)
    return n


def _hair_info_diffuse(which):
    """A Diffuse BSDF whose colour is Hair Info's `which`: 'intercept', a colour ramp of Intercept
    (root blue, middle green at 0.5, tip red); 'geometry', (Length, Thickness x 50, 0) plus the
    Tangent Normal mapped into 0..1 (x 0.25 + 0.25)."""
    def build(nt):
        info = nt.nodes.new("ShaderNodeHairInfo")
        em = nt.nodes.new("ShaderNodeBsdfDiffuse")
        if which == 'intercept':
            ramp = nt.nodes.new("ShaderNodeValToRGB")
            els = ramp.color_ramp.elements
            els[0].color = (0.05, 0.1, 0.9, 1.0)
            els[1].color = (0.9, 0.1, 0.05, 1.0)
            mid = els.new(0.5)
            mid.color = (0.1, 0.8, 0.1, 1.0)
            nt.links.new(info.outputs["Intercept"], ramp.inputs["Fac"])
            nt.links.new(ramp.outputs["Color"], em.inputs["Color"])
        else:
            comb = nt.nodes.new("ShaderNodeCombineXYZ")
            thick = nt.nodes.new("ShaderNodeMath")
            thick.operation = 'MULTIPLY'
            thick.inputs[1].default_value = 50.0
            nt.links.new(info.outputs["Thickness"], thick.inputs[0])
            nt.links.new(info.outputs["Length"], comb.inputs["X"])
            nt.links.new(thick.outputs[0], comb.inputs["Y"])
            tn = _multiply_add(nt, info.outputs["Tangent Normal"], (0.25, 0.25, 0.25), (0.25, 0.25, 0.25))
            add = nt.nodes.new("ShaderNodeVectorMath")
            add.operation = 'ADD'
            nt.links.new(comb.outputs[0], add.inputs[0])
            nt.links.new(tn.outputs[0], add.inputs[1])
            nt.links.new(add.outputs[0], em.inputs["Color"])
        return em
    return build


def _multiply_add(nt, vector, scale, offset):
    """A Vector Math node: vector x scale + offset."""
    node = nt.nodes.new("ShaderNodeVectorMath")
    node.operation = 'MULTIPLY_ADD'
    node.inputs[1].default_value = scale
    node.inputs[2].default_value = offset
    nt.links.new(vector, node.inputs[0])
    return node


def _emissive(nt):
    """Glowing strands (issue 19: emission on hair): an Emission whose colour runs along the strand
    through a colour ramp of Hair Info's Intercept (dim red at the root to orange-yellow at the tip;
    strength 2), added to a Diffuse BSDF."""
    info = nt.nodes.new("ShaderNodeHairInfo")
    ramp = nt.nodes.new("ShaderNodeValToRGB")
    els = ramp.color_ramp.elements
    els[0].color = (0.3, 0.05, 0.02, 1.0)
    els[1].color = (1.0, 0.6, 0.1, 1.0)
    nt.links.new(info.outputs["Intercept"], ramp.inputs["Fac"])
    em = nt.nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 2.0
    nt.links.new(ramp.outputs["Color"], em.inputs["Color"])
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (0.4, 0.4, 0.4, 1.0)
    add = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(em.outputs[0], add.inputs[0])
    nt.links.new(diffuse.outputs[0], add.inputs[1])
    return add


def _uv_diffuse(nt):
    """A Diffuse BSDF coloured by the strand's UV (Texture Coordinate > UV: the emitter's UV map at the
    strand's root): (u, v, 0.3), so red grows across the plane and green along it."""
    coord = nt.nodes.new("ShaderNodeTexCoord")
    mad = _multiply_add(nt, coord.outputs["UV"], (1.0, 1.0, 0.0), (0.0, 0.0, 0.3))
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(mad.outputs[0], diffuse.inputs["Color"])
    return diffuse


def _vcol_diffuse(nt):
    """A Diffuse BSDF coloured by the emitter's colour layer "Col" at the strand's root (Attribute
    node; the plane's corners coloured by position: red across, green along)."""
    attr = nt.nodes.new("ShaderNodeAttribute")
    attr.attribute_name = "Col"
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(attr.outputs["Color"], diffuse.inputs["Color"])
    return diffuse


MATERIALS = {
    "hair_bsdf": _hair_bsdf,
    "hair_reflection": lambda nt: _hair_bsdf(nt, ("Reflection",)),
    "hair_transmission": lambda nt: _hair_bsdf(nt, ("Transmission",)),
    "diffuse": _diffuse,  # the geometry alone
    # Chiang's model in its three colour parametrisations (Cycles' defaults otherwise: roughness 0.3,
    # radial roughness 0.3, IOR 1.55, offset 2 degrees, no coat)
    "principled_color": _principled_hair('COLOR', Color=(0.7, 0.45, 0.25)),
    # without the cuticle tilt, where Cycles' sampling and evaluation agree (lobes/principled_hair.h)
    "principled_color_untilted": _principled_hair('COLOR', Color=(0.7, 0.45, 0.25), Offset=0.0),
    "principled_melanin": _principled_hair('MELANIN', Melanin=0.4, **{"Melanin Redness": 0.7, "Roughness": 0.4}),
    "principled_absorption": _principled_hair('ABSORPTION', **{"Absorption Coefficient": (0.3, 0.6, 1.2),
                                                               "Radial Roughness": 0.5, "Coat": 0.0}),
    # per-strand variation from Hair Info's Random (the node's Random unlinked): melanin from 0.07 to
    # 0.63 and roughnesses from 0.15x to 1.85x their values, strand by strand
    "principled_random": _principled_hair('MELANIN', Melanin=0.35, **{"Melanin Redness": 0.6, "Roughness": 0.4,
                                                                     "Random Color": 0.8, "Random Roughness": 0.85}),
    # Hair Info's Intercept, Length, Thickness and Tangent Normal as the strands' diffuse colour
    # (node parity; with `_direct`, sun-lit, nothing bounces)
    "info_intercept": _hair_info_diffuse('intercept'),
    "info_geometry": _hair_info_diffuse('geometry'),
    # emissive strands (with `_sun`: lit by the sun, the floor lit by them too; no world)
    "emissive": _emissive,
    # the strands' UV (hair UVs), as their diffuse colour
    "uv": _uv_diffuse,
    # the emitter's colour layer at the strand's root (hair vertex colours), as the diffuse colour
    "vcol": _vcol_diffuse,
}
# The sun's strength (W/m^2) where not 3: bright enough that the direct-light image's 8x8 blocks lie
# above the error's floor (EPS 0.02 in blender_tests/test_hair.py), so its error is relative.
SUN_STRENGTH = {"principled_random": 20.0}


def build(out_dir, material, direct=False, curves=False, sun_only=False, ribbons=False, close=False, moving=False):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.render.resolution_x, scene.render.resolution_y = WIDTH, HEIGHT
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = 'Standard'
    world = bpy.data.worlds.new("Grey")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0) if direct or sun_only else \
        (0.25, 0.25, 0.25, 1.0)
    scene.world = world

    bpy.ops.mesh.primitive_plane_add(size=2.0)
    plane = bpy.context.object
    plane.name = "emitter"
    ground = bpy.data.materials.new("ground")
    ground.use_nodes = True
    ground.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.3, 0.3, 0.3, 1.0)
    ground.node_tree.nodes["Principled BSDF"].inputs["Specular"].default_value = 0.0
    plane.data.materials.append(ground)
    plane.data.materials.append(node_material(material, MATERIALS[material]))
    if material == "vcol":
        col = plane.data.vertex_colors.new(name="Col")
        for loop, c in zip(plane.data.loops, col.data):
            x, y, _ = plane.data.vertices[loop.vertex_index].co
            c.color = ((x + 1.0) * 0.5, (y + 1.0) * 0.5, 0.2, 1.0)
    mod = plane.modifiers.new("hair", 'PARTICLE_SYSTEM')
    st = mod.particle_system.settings
    mod.particle_system.seed = 7
    st.type = 'HAIR'
    st.count = 400
    st.hair_length = 0.5
    st.use_advanced_hair = True
    st.normal_factor = 1.0
    st.factor_random = 0.6
    st.child_type = 'INTERPOLATED'
    st.child_nbr = 8
    st.rendered_child_count = 8
    st.render_step = 3
    st.material = 2
    st.radius_scale = 0.02
    st.root_radius = 1.0
    st.tip_radius = 0.0
    st.use_close_tip = True

    if curves:
        # The same strands as a Curves object (3.4's hair curves: 5 points per strand from the
        # display steps, no radius attribute, so Cycles' 0.005), the particle system off for render.
        bpy.context.view_layer.objects.active = plane
        plane.select_set(True)
        bpy.ops.curves.convert_from_particle_system()
        hair = next(o for o in bpy.data.objects if o.type == 'CURVES')
        hair.data.materials.append(plane.data.materials[1])
        # The conversion leaves the curves without a surface UV: give each the plane's UV at its
        # root as `surface_uv_coordinate` (what 3.4's hair curves carry when attached to a surface;
        # the default UV plane maps x, y in -1..1 to 0..1), which Cycles reads as the strands' UV.
        n = len(hair.data.curves)
        offsets = [0] * (n + 1)
        hair.data.curve_offset_data.foreach_get("value", offsets)
        roots = [hair.data.points[offsets[c]].position for c in range(n)]
        uv = hair.data.attributes.new("surface_uv_coordinate", 'FLOAT2', 'CURVE')
        uv.data.foreach_set("vector", [w for p in roots for w in ((p.x + 1.0) * 0.5, (p.y + 1.0) * 0.5)])
        mod.show_render = False
        mod.show_viewport = False

    if moving:
        # Transform motion blur: the emitter (with its hair; the Curves object too) slides along x,
        # MOVE m per frame, rendered at frame 1 with Cycles' shutter 0.5 (half of it blurred).
        scene.render.use_motion_blur = True
        scene.render.motion_blur_shutter = 0.5
        scene.frame_set(1)
        for obj in [o for o in bpy.data.objects if o.type in ('MESH', 'CURVES')]:
            for frame, x in ((0, -MOVE), (1, 0.0), (2, MOVE)):
                obj.location.x = x
                obj.keyframe_insert("location", index=0, frame=frame)
            for fc in obj.animation_data.action.fcurves:
                for k in fc.keyframe_points:
                    k.interpolation = 'LINEAR'
        scene.frame_set(1)

    bpy.ops.object.light_add(type='SUN', rotation=(math.radians(50), math.radians(-20), math.radians(30)))
    sun = bpy.context.object
    sun.data.energy = SUN_STRENGTH.get(material, 3.0)
    sun.data.angle = math.radians(5.0)

    bpy.ops.object.camera_add(location=(0.0, -2.6, 2.2), rotation=(math.radians(52), 0.0, 0.0))
    cam = bpy.context.object
    cam.data.lens = CLOSE_LENS if close else 40
    scene.camera = cam

    bounces = 0 if direct else MAX_BOUNCES
    scene.cycles.max_bounces = bounces
    make_cycles_unbiased(scene, bounces)
    scene.cycles_curves.shape = 'RIBBONS' if ribbons else 'THICK'
    smis = scene.smis if hasattr(scene, "smis") else None
    if smis is not None:
        smis.integrator = 'PATH'
        smis.max_bounces = bounces
        smis.filter_type = 'BOX'
        smis.filter_width = 1.0
    path = os.path.join(out_dir, "hair_%s%s%s%s%s%s.blend" % (material, "_curves" if curves else "",
                                                           "_ribbons" if ribbons else "",
                                                           "_close" if close else "", "_moving" if moving else "",
                                                           "_direct" if direct else "_sun" if sun_only else ""))
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def main():
    argv = sys.argv
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    out_dir = os.path.abspath(args[0] if args else ".")
    os.makedirs(out_dir, exist_ok=True)
    for name in args[1:] or ["hair_bsdf"]:
        direct, curves, sun_only = name.endswith("_direct"), "_curves" in name, name.endswith("_sun")
        ribbons, close, moving = "_ribbons" in name, "_close" in name, "_moving" in name
        material = name
        for suffix in ("_direct", "_sun", "_curves", "_ribbons", "_close", "_moving"):
            material = material.replace(suffix, "")
        print("wrote", build(out_dir, material, direct, curves, sun_only, ribbons, close, moving))


if __name__ == "__main__":
    main()
