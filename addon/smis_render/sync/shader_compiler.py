"""Blender shader node trees -> engine shader programs (engine/shading/shader_program.h).

A program is a flat list of ops over a float register file (colours and vectors take three
registers), as Cycles' SVM compiles a ShaderGraph. The compiler walks back from the Material
Output's Surface input: node groups are flattened (each group instance compiled in its own
context), reroutes and muted nodes are followed as Blender does (nodes.linked_output), unlinked
sockets become constant registers, and Blender's implicit socket conversions are inserted. Mix and
Add Shader become closure weights computed per hit, so a Layer Weight or a texture may drive them.

Nothing is folded here: the engine folds every op that does not read the hit once at load
(ShaderProgram::fold_constants), so a tree of constants costs nothing per hit and keeps the
prepared-BSDF path. Nodes the engine cannot evaluate fall back with one warning naming material
and node.
"""

import math

from . import nodes, sky_hosek_data
from .mesh import ACTIVE_COLOR, POINTINESS, RANDOM_PER_ISLAND, TANGENT_PREFIX

# Enum identifiers in the engine's order (engine/shading/node_math.h, procedural_*.h).
MATH_OPS = ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "POWER", "LOGARITHM", "SQRT",
            "INVERSE_SQRT", "ABSOLUTE", "EXPONENT", "MINIMUM", "MAXIMUM", "LESS_THAN", "GREATER_THAN",
            "SIGN", "COMPARE", "SMOOTH_MIN", "SMOOTH_MAX", "ROUND", "FLOOR", "CEIL", "TRUNC", "FRACT",
            "MODULO", "WRAP", "SNAP", "PINGPONG", "SINE", "COSINE", "TANGENT", "ARCSINE", "ARCCOSINE",
            "ARCTANGENT", "ARCTAN2", "SINH", "COSH", "TANH", "RADIANS", "DEGREES"]
VECTOR_MATH_OPS = ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "CROSS_PRODUCT", "PROJECT",
                   "REFLECT", "REFRACT", "FACEFORWARD", "DOT_PRODUCT", "DISTANCE", "LENGTH", "SCALE",
                   "NORMALIZE", "ABSOLUTE", "MINIMUM", "MAXIMUM", "FLOOR", "CEIL", "FRACTION", "MODULO",
                   "WRAP", "SNAP", "SINE", "COSINE", "TANGENT"]
BLEND_TYPES = ["MIX", "DARKEN", "MULTIPLY", "BURN", "LIGHTEN", "SCREEN", "DODGE", "ADD", "OVERLAY",
               "SOFT_LIGHT", "LINEAR_LIGHT", "DIFFERENCE", "SUBTRACT", "DIVIDE", "HUE", "SATURATION",
               "COLOR", "VALUE"]
MAP_RANGE_TYPES = ["LINEAR", "STEPPED", "SMOOTHSTEP", "SMOOTHERSTEP"]
MUSGRAVE_TYPES = ["MULTIFRACTAL", "FBM", "HYBRID_MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HETERO_TERRAIN"]
GRADIENT_TYPES = ["LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "RADIAL", "QUADRATIC_SPHERE", "SPHERICAL"]
VORONOI_FEATURES = ["F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"]
VORONOI_METRICS = ["EUCLIDEAN", "MANHATTAN", "CHEBYCHEV", "MINKOWSKI"]
DIMENSIONS = {"1D": 1, "2D": 2, "3D": 3, "4D": 4}
MAPPING_TYPES = ["POINT", "TEXTURE", "VECTOR", "NORMAL"]
PROJECTIONS = ["FLAT", "BOX", "SPHERE", "TUBE"]
NORMAL_MAP_SPACES = ["TANGENT", "OBJECT", "WORLD", "BLENDER_OBJECT", "BLENDER_WORLD"]
TRANSFORM_SPACES = ["WORLD", "OBJECT", "CAMERA"]
COLOR_MODES = ["RGB", "HSV", "HSL"]
ROTATE_TYPES = ["AXIS_ANGLE", "X_AXIS", "Y_AXIS", "Z_AXIS", "EULER_XYZ"]
# Principled BSDF inputs in the engine's order (shader_program.cpp, principled_in), after the weight.
PRINCIPLED_INPUTS = ["Base Color", "Subsurface", "Subsurface Radius", "Subsurface Color", "Subsurface IOR",
                     "Subsurface Anisotropy", "Metallic", "Specular", "Specular Tint", "Roughness",
                     "Anisotropic", "Anisotropic Rotation", "Sheen", "Sheen Tint", "Clearcoat",
                     "Clearcoat Roughness", "IOR", "Transmission", "Transmission Roughness", "Emission",
                     "Emission Strength", "Alpha", "Normal", "Clearcoat Normal", "Tangent"]
VECTOR_INPUTS_OF_PRINCIPLED = {"Subsurface Radius", "Normal", "Clearcoat Normal", "Tangent"}
RAMP_TABLE_SIZE = 256
NO = -1  # no register: the op's default applies

FLOAT, VEC, COLOR, SHADER = "float", "vec", "color", "shader"
_SOCKET_KIND = {"VALUE": FLOAT, "INT": FLOAT, "BOOLEAN": FLOAT, "VECTOR": VEC, "RGBA": COLOR,
                "SHADER": SHADER}


def _index(table, name, default=0):
    return table.index(name) if name in table else default


class Value:
    """A compiled socket value: its kind and first register."""
    __slots__ = ("kind", "reg")

    def __init__(self, kind, reg):
        self.kind, self.reg = kind, reg


class _Context:
    """Where a node sits: the chain of group nodes it is inside (outermost first)."""

    def __init__(self, groups=()):
        self.groups = tuple(groups)

    def key(self):
        return tuple(g.as_pointer() for g in self.groups)

    def enter(self, group_node):
        return _Context(self.groups + (group_node,))

    def parent(self):
        return _Context(self.groups[:-1])


class ShaderCompiler:
    """Compiles one material's Surface (and Displacement, as bump) into a program dict."""

    def __init__(self, material_name, warn, textures, scene):
        self.name = material_name
        self.warn = warn
        self.textures = textures      # textures.TextureCache or None
        self.scene = scene            # for attribute ids
        self.registers = []
        self.ops = []
        self.data = []
        self.texture_ids = []
        self._values = {}             # (context key, node pointer) -> {output identifier: Value}
        self._warned = set()
        self._bump = None             # 0 / 1 while compiling a Bump node's shifted heights
        self.uses_uv = False
        self.derived_attributes = set()  # attributes the mesh export derives (tangents, Pointiness, ...)
        self.surface_normal = None    # Value of the Displacement output's bump normal

    # -- registers and ops --------------------------------------------------------------------

    def constant(self, value, kind):
        reg = len(self.registers)
        if kind == FLOAT:
            self.registers.append(float(value))
        else:
            v = list(value) + [0.0, 0.0, 0.0]
            self.registers.extend(float(x) for x in v[:3])
        return Value(kind, reg)

    def alloc(self, kind):
        return self.constant(0.0 if kind == FLOAT else (0.0, 0.0, 0.0), kind)

    def op(self, name, ins=(), outs=(), ints=(), floats=(), data=0):
        self.ops.append((name, [NO if v is None else v.reg for v in ins],
                         [NO if v is None else v.reg for v in outs], list(ints), [float(f) for f in floats],
                         int(data)))

    def warn_node(self, node, text):
        key = (node.as_pointer(), text)
        if key in self._warned:
            return
        self._warned.add(key)
        self.warn("Material '%s': node '%s' (%s) %s" % (self.name, node.name, node.bl_idname, text))

    def convert(self, value, kind):
        """Blender's implicit conversion between socket kinds."""
        if value is None or value.kind == kind or kind == SHADER:
            return value
        if value.kind == SHADER:
            return self.constant(0.0 if kind == FLOAT else (0.0, 0.0, 0.0), kind)
        out = self.alloc(kind)
        if value.kind == FLOAT:
            self.op("convert", [value], [out], [0])
        elif kind == FLOAT:
            self.op("convert", [value], [out], [1 if value.kind == COLOR else 2])
        else:  # colour <-> vector: the same three numbers
            return Value(kind, value.reg)
        return out

    # -- sockets ------------------------------------------------------------------------------

    def input(self, node, name, ctx, kind=None, default="const"):
        """The value feeding input `name` of node (by name or index): its link's, or its own constant.
        `default` (a Value or None) replaces an unlinked socket's constant (texture vectors, normals)."""
        socket = node.inputs[name] if not isinstance(name, int) else node.inputs[name]
        return self.socket_value(socket, ctx, kind, default)

    def socket_value(self, socket, ctx, kind=None, default="const"):
        kind = kind or _SOCKET_KIND.get(socket.type, FLOAT)
        src = nodes.linked_output(socket)
        if src is None:
            if default != "const" and default is not None:
                return default() if callable(default) else default
            if default is None:
                return None
            return self._socket_constant(socket, kind)
        return self.convert(self.output_value(src, ctx), kind)

    def _socket_constant(self, socket, kind):
        if not hasattr(socket, "default_value"):
            return self.constant(0.0 if kind == FLOAT else (0.0, 0.0, 0.0), kind)
        v = socket.default_value
        try:
            seq = list(v)
        except TypeError:
            seq = None
        if seq is None:
            return self.constant(float(v), FLOAT) if kind == FLOAT else self.constant((float(v),) * 3, kind)
        if kind == FLOAT:  # a vector/colour socket's constant read as a float
            return self.constant(sum(seq[:3]) / 3.0, FLOAT)
        return self.constant(seq[:3], kind)

    def output_value(self, out_socket, ctx):
        """The value of an output socket, compiling its node (once per context) if needed."""
        node = out_socket.node
        if node.bl_idname == "NodeGroupInput":
            if not ctx.groups:
                return self.constant(0.0, FLOAT)
            group_node = ctx.groups[-1]
            idx = list(node.outputs).index(out_socket)
            if idx >= len(group_node.inputs):
                return self.constant(0.0, FLOAT)
            return self.socket_value(group_node.inputs[idx], ctx.parent())
        if node.bl_idname in ("ShaderNodeGroup", "NodeGroup") or node.type == "GROUP":
            return self._group_output(node, out_socket, ctx)
        key = (ctx.key(), node.as_pointer(), self._bump)
        outs = self._values.get(key)
        if outs is None:
            handler = VALUE_NODES.get(node.bl_idname)
            if handler is None:
                self.warn_node(node, "is not supported by the SMIS shader evaluator; its outputs are "
                                     "taken as 0")
                outs = {}
            else:
                outs = handler(self, node, ctx) or {}
            self._values[key] = outs
        value = outs.get(out_socket.identifier) or outs.get(out_socket.name)
        if value is None:
            kind = _SOCKET_KIND.get(out_socket.type, FLOAT)
            return self.constant(0.0 if kind == FLOAT else (0.0, 0.0, 0.0), kind)
        return value

    def _group_output(self, group_node, out_socket, ctx):
        tree = group_node.node_tree
        if tree is None:
            self.warn_node(group_node, "has no node group; its outputs are taken as 0")
            return self.constant(0.0, FLOAT)
        out_node = None
        for n in tree.nodes:
            if n.bl_idname == "NodeGroupOutput" and (out_node is None or n.is_active_output):
                out_node = n
        if out_node is None:
            self.warn_node(group_node, "has a node group without a Group Output; its outputs are 0")
            return self.constant(0.0, FLOAT)
        idx = list(group_node.outputs).index(out_socket)
        if idx >= len(out_node.inputs):
            return self.constant(0.0, FLOAT)
        return self.socket_value(out_node.inputs[idx], ctx.enter(group_node))

    # -- common defaults -------------------------------------------------------------------------

    def texcoord(self, which):
        """A Texture Coordinate output ('generated', 'uv', 'object', ...) as a default vector."""
        outs = [None] * 7
        names = ["generated", "normal", "uv", "object", "camera", "window", "reflection"]
        v = self.alloc(VEC)
        outs[names.index(which)] = v
        if which == "uv":
            self.uses_uv = True
        self.op("texcoord", [], outs, [0])
        return v

    def vector_input(self, node, ctx, default_coord="generated"):
        return self.input(node, "Vector", ctx, VEC, lambda: self.texcoord(default_coord))

    def normal_input(self, node, name, ctx):
        if name not in node.inputs:
            return None
        return self.input(node, name, ctx, VEC, default=None) if node.inputs[name].is_linked else None

    # -- closures -----------------------------------------------------------------------------

    def shader(self, socket, weight, ctx):
        """Compile the closures feeding a shader input socket with the given weight Value."""
        src = nodes.linked_output(socket)
        if src is None:
            return
        node = src.node
        if node.bl_idname == "NodeGroupInput":
            if ctx.groups:
                idx = list(node.outputs).index(src)
                group_node = ctx.groups[-1]
                if idx < len(group_node.inputs):
                    self.shader(group_node.inputs[idx], weight, ctx.parent())
            return
        if node.bl_idname in ("ShaderNodeGroup", "NodeGroup") or node.type == "GROUP":
            tree = node.node_tree
            out_node = next((n for n in (tree.nodes if tree else []) if n.bl_idname == "NodeGroupOutput"
                             and n.is_active_output), None)
            if out_node is None:
                self.warn_node(node, "has no Group Output; it renders black")
                return
            idx = list(node.outputs).index(src)
            if idx < len(out_node.inputs):
                self.shader(out_node.inputs[idx], weight, ctx.enter(node))
            return
        if src.type != "SHADER":
            # A colour or value plugged into a shader socket: Cycles renders it as emission.
            self.op("emission", [weight, self.convert(self.output_value(src, ctx), COLOR), None])
            return
        handler = SHADER_NODES.get(node.bl_idname)
        if handler is None:
            self.warn_node(node, "is not supported, using a neutral diffuse")
            self.op("diffuse", [weight, self.constant((0.8, 0.8, 0.8), COLOR), None, None])
            return
        handler(self, node, ctx, weight)

    def compile_surface(self, output_node):
        ctx = _Context()
        weight = self.constant(1.0, FLOAT)
        disp = output_node.inputs.get("Displacement")
        if disp is not None and nodes.linked_output(disp) is not None:
            self.surface_normal = self._displacement_bump(disp, ctx)
        self.shader(output_node.inputs["Surface"], weight, ctx)

    def _displacement_bump(self, socket, ctx):
        """The Displacement output as Cycles' 'Bump Only': the displacement's normal component is
        the height of a bump map (the surface is not moved)."""
        heights = []
        for shift in (None, 0, 1):
            self._bump = shift
            if shift is not None:
                self.op("bump_enter", ints=[shift])
            d = self.socket_value(socket, ctx, VEC)
            h = self.alloc(FLOAT)
            n = self.alloc(VEC)
            self.op("geometry", [], [None, n])
            self.op("vector_math", [d, n, None, None], [None, h], [VECTOR_MATH_OPS.index("DOT_PRODUCT")])
            if shift is not None:
                self.op("bump_leave", ints=[shift])
            heights.append(h)
        self._bump = None
        out = self.alloc(VEC)
        self.op("bump", [self.constant(1.0, FLOAT), self.constant(1.0, FLOAT), heights[0], heights[1],
                         heights[2], None], [out], [0])
        return out

    def program(self):
        return {"registers": self.registers, "ops": self.ops, "data": self.data,
                "textures": self.texture_ids}


# -- value nodes -----------------------------------------------------------------------------------

def _outs(c, node, kinds):
    """Allocate registers for the node's linked outputs: ({identifier: Value}, the op's output list
    in the given order, None for an output nothing reads, so the engine can skip computing it)."""
    result, regs = {}, []
    for name, kind in kinds:
        sock = node.outputs.get(name)
        if sock is not None and not sock.is_linked:
            regs.append(None)
            continue
        v = c.alloc(kind)
        regs.append(v)
        if sock is not None:
            result[sock.identifier] = v
        result[name] = v
    return result, regs


def _value(c, node, ctx):
    return {node.outputs[0].identifier: c.constant(node.outputs[0].default_value, FLOAT)}


def _rgb(c, node, ctx):
    return {node.outputs[0].identifier: c.constant(node.outputs[0].default_value[:3], COLOR)}


def _texcoord(c, node, ctx):
    names = ["Generated", "Normal", "UV", "Object", "Camera", "Window", "Reflection"]
    res, regs = _outs(c, node, [(n, VEC) for n in names])
    ints, data = [0], 0
    obj = getattr(node, "object", None)
    if obj is not None:
        m = obj.matrix_world.inverted_safe()
        data = len(c.data)
        c.data.extend(float(m[r][k]) for r in range(3) for k in range(4))
        ints = [1]
    if node.outputs["UV"].is_linked:
        c.uses_uv = True
    if getattr(node, "from_instancer", False):
        c.warn_node(node, "uses From Instancer, which is not supported")
    c.op("texcoord", [], regs, ints, data=data)
    return res


def _attribute_id(c, name):
    return c.scene.attribute_id(name) if c.scene is not None and name else -1


def _derived_attribute_id(c, name):
    """The id of an attribute the mesh export derives on request (a UV map's MikkTSpace tangents,
    Pointiness, Random Per Island: mesh.py), and marks it as needed."""
    c.uses_uv = c.uses_uv or name.startswith(TANGENT_PREFIX)
    c.derived_attributes.add(name)
    return c.scene.attribute_id(name) if c.scene is not None else -1


def _uvmap(c, node, ctx):
    res, regs = _outs(c, node, [("UV", VEC)])
    c.uses_uv = True
    c.op("uvmap", [], regs, [_attribute_id(c, node.uv_map) if node.uv_map else -1])
    return res


def _attribute(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Vector", VEC), ("Fac", FLOAT), ("Alpha", FLOAT)])
    name = getattr(node, "attribute_name", "") or getattr(node, "layer_name", "")
    if node.bl_idname == "ShaderNodeVertexColor" and not name:
        name = ACTIVE_COLOR
    if getattr(node, "attribute_type", "GEOMETRY") != "GEOMETRY":
        c.warn_node(node, "reads an object or instancer attribute, which is not supported (0)")
        name = ""
    # Named attributes travel with the UVs (mesh corners, hair strands): ask the export for them.
    c.uses_uv = c.uses_uv or bool(name)
    c.op("attribute", [], regs, [_attribute_id(c, name), 0])
    return res


def _geometry(c, node, ctx):
    names = [("Position", VEC), ("Normal", VEC), ("Tangent", VEC), ("True Normal", VEC), ("Incoming", VEC),
             ("Parametric", VEC), ("Backfacing", FLOAT), ("Pointiness", FLOAT), ("Random Per Island", FLOAT)]
    res, regs = _outs(c, node, names)
    derived = [_derived_attribute_id(c, attr) if node.outputs[name].is_linked else -1
               for name, attr in (("Pointiness", POINTINESS), ("Random Per Island", RANDOM_PER_ISLAND))]
    c.op("geometry", [], regs, derived)
    return res


def _object_info(c, node, ctx):
    names = [("Location", VEC), ("Color", COLOR), ("Alpha", FLOAT), ("Object Index", FLOAT),
             ("Material Index", FLOAT), ("Random", FLOAT)]
    res, regs = _outs(c, node, names)
    c.op("object_info", [], regs)
    return res


def _hair_info(c, node, ctx):
    """Hair Info as Cycles 3.4: Is Strand, Random (per strand, Cycles' hash of the curve's index),
    Intercept (along the strand, 0 at the root), Length (the strand's, object space), Thickness
    (2 x the radius at the hit) and Tangent Normal (the view direction across the strand); all 0
    off hair (Scene::curve_shader_context, the hair_info op)."""
    res, regs = _outs(c, node, [("Is Strand", FLOAT), ("Random", FLOAT), ("Intercept", FLOAT), ("Length", FLOAT),
                                ("Thickness", FLOAT), ("Tangent Normal", VEC)])
    c.op("hair_info", [], regs)
    return res


def _light_path(c, node, ctx):
    names = ["Is Camera Ray", "Is Shadow Ray", "Is Diffuse Ray", "Is Glossy Ray", "Is Singular Ray",
             "Is Reflection Ray", "Is Transmission Ray", "Ray Length", "Ray Depth", "Diffuse Depth",
             "Glossy Depth", "Transparent Depth", "Transmission Depth"]
    res, regs = _outs(c, node, [(n, FLOAT) for n in names])
    c.op("light_path", [], regs)
    return res


def _fresnel(c, node, ctx):
    res, regs = _outs(c, node, [("Fac", FLOAT)])
    c.op("fresnel", [c.input(node, "IOR", ctx, FLOAT), c.normal_input(node, "Normal", ctx)], regs)
    return res


def _layer_weight(c, node, ctx):
    res, regs = _outs(c, node, [("Fresnel", FLOAT), ("Facing", FLOAT)])
    c.op("layer_weight", [c.input(node, "Blend", ctx, FLOAT), c.normal_input(node, "Normal", ctx)], regs)
    return res


def _camera_data(c, node, ctx):
    res, regs = _outs(c, node, [("View Vector", VEC), ("View Z Depth", FLOAT), ("View Distance", FLOAT)])
    c.op("camera_data", [], regs)
    return res


def _tangent(c, node, ctx):
    res, regs = _outs(c, node, [("Tangent", VEC)])
    uv = node.direction_type == "UV_MAP"
    tangents = _derived_attribute_id(c, TANGENT_PREFIX + node.uv_map) if uv else -1
    c.op("tangent", [], regs, [1 if uv else 0, "XYZ".index(node.axis[0]), tangents])
    return res


def _new_geometry(c, node, ctx):
    return _geometry(c, node, ctx)


def _bump(c, node, ctx):
    res, regs = _outs(c, node, [("Normal", VEC)])
    if c._bump is not None:  # a bump inside a bump's height: Cycles keeps the inner one's normal
        height = c.input(node, "Height", ctx, FLOAT)
        c.op("bump", [c.input(node, "Strength", ctx, FLOAT), c.input(node, "Distance", ctx, FLOAT), height,
                      height, height, c.normal_input(node, "Normal", ctx)], regs, [int(node.invert)])
        return res
    heights = []
    saved = c._bump
    for shift in (None, 0, 1):
        c._bump = shift
        if shift is not None:
            c.op("bump_enter", ints=[shift])
        heights.append(c.input(node, "Height", ctx, FLOAT))
        if shift is not None:
            c.op("bump_leave", ints=[shift])
    c._bump = saved
    c.op("bump", [c.input(node, "Strength", ctx, FLOAT), c.input(node, "Distance", ctx, FLOAT), heights[0],
                  heights[1], heights[2], c.normal_input(node, "Normal", ctx)], regs, [int(node.invert)])
    return res


def _normal_map(c, node, ctx):
    res, regs = _outs(c, node, [("Normal", VEC)])
    space = _index(NORMAL_MAP_SPACES, node.space)
    tangents = _derived_attribute_id(c, TANGENT_PREFIX + node.uv_map) if space == 0 else -1
    c.op("normal_map", [c.input(node, "Strength", ctx, FLOAT), c.input(node, "Color", ctx, COLOR)], regs,
         [space, tangents])
    return res


def _tex_image(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Alpha", FLOAT)])
    tex_id = c.textures.id_for(node) if c.textures is not None else None
    if tex_id is None:
        if c.textures is not None:
            tex_id = c.textures.missing()
        else:
            c.op("convert", [c.constant(0.0, FLOAT)], [regs[0]], [0])
            return res
    local = len(c.texture_ids)
    c.texture_ids.append(tex_id)
    vec = c.vector_input(node, ctx, "uv")
    c.op("tex_image", [vec], regs, [local, _index(PROJECTIONS, node.projection)],
         [getattr(node, "projection_blend", 0.0)])
    return res


def _tex_noise(c, node, ctx):
    res, regs = _outs(c, node, [("Fac", FLOAT), ("Color", COLOR)])
    ins = [c.vector_input(node, ctx)] + [c.input(node, n, ctx, FLOAT)
                                          for n in ("W", "Scale", "Detail", "Roughness", "Distortion")]
    c.op("tex_noise", ins, regs, [DIMENSIONS.get(node.noise_dimensions, 3)])
    return res


def _tex_voronoi(c, node, ctx):
    res, regs = _outs(c, node, [("Distance", FLOAT), ("Color", COLOR), ("Position", VEC), ("W", FLOAT),
                                ("Radius", FLOAT)])
    ins = [c.vector_input(node, ctx)] + [c.input(node, n, ctx, FLOAT)
                                          for n in ("W", "Scale", "Smoothness", "Exponent", "Randomness")]
    c.op("tex_voronoi", ins, regs, [DIMENSIONS.get(node.voronoi_dimensions, 3),
                                    _index(VORONOI_FEATURES, node.feature), _index(VORONOI_METRICS, node.distance)])
    return res


def _tex_musgrave(c, node, ctx):
    res, regs = _outs(c, node, [("Fac", FLOAT)])
    ins = [c.vector_input(node, ctx)] + [c.input(node, n, ctx, FLOAT) for n in
                                          ("W", "Scale", "Detail", "Dimension", "Lacunarity", "Offset", "Gain")]
    c.op("tex_musgrave", ins, regs, [DIMENSIONS.get(node.musgrave_dimensions, 3),
                                     _index(MUSGRAVE_TYPES, node.musgrave_type)])
    return res


def _tex_wave(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Fac", FLOAT)])
    ins = [c.vector_input(node, ctx)] + [c.input(node, n, ctx, FLOAT) for n in
                                          ("Scale", "Distortion", "Detail", "Detail Scale", "Detail Roughness",
                                           "Phase Offset")]
    rings = node.wave_type == "RINGS"
    direction = node.rings_direction if rings else node.bands_direction
    dirs = {"X": 0, "Y": 1, "Z": 2, "DIAGONAL": 3, "SPHERICAL": 4}
    c.op("tex_wave", ins, regs, [int(rings), dirs.get(direction, 0),
                                 {"SIN": 0, "SAW": 1, "TRI": 2}.get(node.wave_profile, 0)])
    return res


def _tex_magic(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Fac", FLOAT)])
    c.op("tex_magic", [c.vector_input(node, ctx), c.input(node, "Scale", ctx, FLOAT),
                       c.input(node, "Distortion", ctx, FLOAT)], regs, [int(node.turbulence_depth)])
    return res


def _tex_checker(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Fac", FLOAT)])
    c.op("tex_checker", [c.vector_input(node, ctx), c.input(node, "Color1", ctx, COLOR),
                         c.input(node, "Color2", ctx, COLOR), c.input(node, "Scale", ctx, FLOAT)], regs)
    return res


def _tex_brick(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Fac", FLOAT)])
    ins = [c.vector_input(node, ctx), c.input(node, "Color1", ctx, COLOR), c.input(node, "Color2", ctx, COLOR),
           c.input(node, "Mortar", ctx, COLOR)] + [c.input(node, n, ctx, FLOAT) for n in
                                                   ("Scale", "Mortar Size", "Mortar Smooth", "Bias",
                                                    "Brick Width", "Row Height")]
    c.op("tex_brick", ins, regs, [node.offset_frequency, node.squash_frequency], [node.offset, node.squash])
    return res


def _tex_gradient(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Fac", FLOAT)])
    c.op("tex_gradient", [c.vector_input(node, ctx)], regs, [_index(GRADIENT_TYPES, node.gradient_type)])
    return res


def _tex_white_noise(c, node, ctx):
    res, regs = _outs(c, node, [("Value", FLOAT), ("Color", COLOR)])
    c.op("tex_white_noise", [c.vector_input(node, ctx), c.input(node, "W", ctx, FLOAT)], regs,
         [DIMENSIONS.get(node.noise_dimensions, 3)])
    return res


def _mix_rgb(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR)])
    c.op("mix", [c.input(node, "Fac", ctx, FLOAT), c.input(node, 1, ctx, COLOR), c.input(node, 2, ctx, COLOR)],
         regs, [_index(BLEND_TYPES, node.blend_type), 1, int(node.use_clamp)])
    return res


def _mix(c, node, ctx):
    """Blender 3.4's Mix node: the enabled sockets depend on data_type (and factor_mode)."""
    by_type = {"FLOAT": (FLOAT, "mix_float"), "VECTOR": (VEC, "mix_vector"), "RGBA": (COLOR, "mix")}
    kind, opname = by_type.get(node.data_type, (COLOR, "mix"))
    fac_socket = next(s for s in node.inputs if s.enabled and s.name == "Factor")
    a = next(s for s in node.inputs if s.enabled and s.name == "A")
    b = next(s for s in node.inputs if s.enabled and s.name == "B")
    out_socket = next(s for s in node.outputs if s.enabled)
    out = c.alloc(kind)
    non_uniform = kind == VEC and node.factor_mode == "NON_UNIFORM"
    fac = c.socket_value(fac_socket, ctx, VEC if non_uniform else FLOAT)
    av, bv = c.socket_value(a, ctx, kind), c.socket_value(b, ctx, kind)
    if opname == "mix":
        c.op("mix", [fac, av, bv], [out], [_index(BLEND_TYPES, node.blend_type), int(node.clamp_factor),
                                          int(node.clamp_result)])
    elif opname == "mix_float":
        c.op("mix_float", [fac, av, bv], [out], [int(node.clamp_factor)])
    else:
        c.op("mix_vector", [fac, av, bv], [out], [int(node.clamp_factor), int(non_uniform)])
    return {out_socket.identifier: out, "Result": out}


def _curve_table(c, mapping, channels):
    """Bake a CurveMapping into RAMP_TABLE_SIZE RGBA entries over [min_x, max_x], as Cycles does."""
    mapping.initialize()
    curves = mapping.curves
    used = curves[:4] if channels == "rgb" else curves[:3]
    min_x = min(p.location[0] for cv in used for p in cv.points)
    max_x = max(p.location[0] for cv in used for p in cv.points)
    if not max_x > min_x:
        min_x, max_x = 0.0, 1.0
    offset = len(c.data)
    for i in range(RAMP_TABLE_SIZE):
        x = min_x + (max_x - min_x) * i / (RAMP_TABLE_SIZE - 1)
        row = [0.0, 0.0, 0.0, 0.0]
        for ch in range(3):
            # RGB Curves: the combined (C) curve first, then the channel's (Cycles' table).
            t = mapping.evaluate(curves[3], x) if channels == "rgb" else x
            row[ch] = mapping.evaluate(curves[ch], t)
        c.data.extend(row)
    return offset, min_x, max_x


def _curves(opname, socket, kind, channels):
    """RGB Curves and Vector Curves: the mapping baked into a table (_curve_table), looked up per hit."""
    def handler(c, node, ctx):
        res, regs = _outs(c, node, [(socket, kind)])
        offset, lo, hi = _curve_table(c, node.mapping, channels)
        c.op(opname, [c.input(node, "Fac", ctx, FLOAT), c.input(node, socket, ctx, kind)], regs,
             [RAMP_TABLE_SIZE, int(node.mapping.extend == "EXTRAPOLATED")], [lo, hi], data=offset)
        return res
    return handler


def _color_ramp(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Alpha", FLOAT)])
    ramp = node.color_ramp
    offset = len(c.data)
    for i in range(RAMP_TABLE_SIZE):
        c.data.extend(float(x) for x in ramp.evaluate(i / (RAMP_TABLE_SIZE - 1)))
    c.op("color_ramp", [c.input(node, "Fac", ctx, FLOAT)], regs,
         [RAMP_TABLE_SIZE, int(ramp.interpolation != "CONSTANT")], data=offset)
    return res


def _simple(opname, inputs, outputs, ints_fn=None):
    def handler(c, node, ctx):
        res, regs = _outs(c, node, outputs)
        ins = [c.input(node, name, ctx, kind) for name, kind in inputs]
        c.op(opname, ins, regs, ints_fn(node) if ints_fn else [])
        return res
    return handler


def _math(c, node, ctx):
    res, regs = _outs(c, node, [("Value", FLOAT)])
    ins = [c.input(node, i, ctx, FLOAT) for i in range(3)]
    c.op("math", ins, regs, [_index(MATH_OPS, node.operation), int(node.use_clamp)])
    return res


def _vector_math(c, node, ctx):
    res, regs = _outs(c, node, [("Vector", VEC), ("Value", FLOAT)])
    ins = [c.input(node, i, ctx, VEC) for i in range(3)] + [c.input(node, "Scale", ctx, FLOAT)]
    c.op("vector_math", ins, regs, [_index(VECTOR_MATH_OPS, node.operation)])
    return res


def _map_range(c, node, ctx):
    vector = getattr(node, "data_type", "FLOAT") == "FLOAT_VECTOR"
    kind = VEC if vector else FLOAT
    names = ["Value", "From Min", "From Max", "To Min", "To Max", "Steps"]
    if vector:
        names = ["Vector"] + names[1:]
    socks = {s.name: s for s in node.inputs if s.enabled}
    ins = [c.socket_value(socks[n], ctx, kind) if n in socks else None for n in names]
    out_sock = next(s for s in node.outputs if s.enabled)
    out = c.alloc(kind)
    c.op("map_range_vector" if vector else "map_range", ins, [out],
         [_index(MAP_RANGE_TYPES, node.interpolation_type), int(node.clamp)])
    return {out_sock.identifier: out}


def _separate_color(c, node, ctx, mode=None):
    mode = mode if mode is not None else _index(COLOR_MODES, getattr(node, "mode", "RGB"))
    color = c.input(node, 0, ctx, COLOR)
    if mode != 0:
        conv = c.alloc(COLOR)
        c.op("separate_color", [color], [conv], [mode])
        color = conv
    res = {}
    for k, sock in enumerate(node.outputs[:3]):
        res[sock.identifier] = Value(FLOAT, color.reg + k)
    return res


def _separate_xyz(c, node, ctx):
    vec = c.input(node, 0, ctx, VEC)
    return {s.identifier: Value(FLOAT, vec.reg + k) for k, s in enumerate(node.outputs[:3])}


def _combine_color(c, node, ctx, mode=None):
    mode = mode if mode is not None else _index(COLOR_MODES, getattr(node, "mode", "RGB"))
    out = c.alloc(COLOR)
    c.op("combine_color", [c.input(node, k, ctx, FLOAT) for k in range(3)], [out], [mode])
    return {node.outputs[0].identifier: out}


def _combine_xyz(c, node, ctx):
    out = c.alloc(VEC)
    c.op("combine_xyz", [c.input(node, k, ctx, FLOAT) for k in range(3)], [out])
    return {node.outputs[0].identifier: out}


def _mapping(c, node, ctx):
    res, regs = _outs(c, node, [("Vector", VEC)])
    t = _index(MAPPING_TYPES, node.vector_type)
    # Location applies to points and texture coordinates only (Blender hides it for the others).
    ins = [c.input(node, "Vector", ctx, VEC), c.input(node, "Location", ctx, VEC) if t in (0, 1) else None,
           c.input(node, "Rotation", ctx, VEC), c.input(node, "Scale", ctx, VEC)]
    c.op("mapping", ins, regs, [t])
    return res


def _vector_transform(c, node, ctx):
    res, regs = _outs(c, node, [("Vector", VEC)])
    c.op("vector_transform", [c.input(node, "Vector", ctx, VEC)], regs,
         [_index(["POINT", "VECTOR", "NORMAL"], node.vector_type), _index(TRANSFORM_SPACES, node.convert_from),
          _index(TRANSFORM_SPACES, node.convert_to)])
    return res


def _normal(c, node, ctx):
    res, regs = _outs(c, node, [("Normal", VEC), ("Dot", FLOAT)])
    direction = list(node.outputs["Normal"].default_value)
    c.op("normal", [c.input(node, "Normal", ctx, VEC)], regs, [], direction)
    return res


def _vector_rotate(c, node, ctx):
    res, regs = _outs(c, node, [("Vector", VEC)])
    socks = {s.name: s for s in node.inputs}
    ins = [c.socket_value(socks["Vector"], ctx, VEC), c.socket_value(socks["Center"], ctx, VEC),
           c.socket_value(socks["Axis"], ctx, VEC), c.socket_value(socks["Angle"], ctx, FLOAT),
           c.socket_value(socks["Rotation"], ctx, VEC)]
    c.op("vector_rotate", ins, regs, [_index(ROTATE_TYPES, node.rotation_type), int(node.invert)])
    return res


def _displacement(c, node, ctx):
    res, regs = _outs(c, node, [("Displacement", VEC)])
    c.op("displacement", [c.input(node, "Height", ctx, FLOAT), c.input(node, "Midlevel", ctx, FLOAT),
                          c.input(node, "Scale", ctx, FLOAT), c.normal_input(node, "Normal", ctx)], regs,
         [0 if node.space == "OBJECT" else 1])
    return res


def _clamp(c, node, ctx):
    res, regs = _outs(c, node, [("Result", FLOAT)])
    c.op("clamp", [c.input(node, n, ctx, FLOAT) for n in ("Value", "Min", "Max")], regs,
         [int(node.clamp_type == "RANGE")])
    return res


def _ambient_occlusion(c, node, ctx):
    c.warn_node(node, "(Ambient Occlusion) is not supported; its Color passes through and AO is 1")
    color = c.input(node, "Color", ctx, COLOR)
    return {node.outputs["Color"].identifier: color, node.outputs["AO"].identifier: c.constant(1.0, FLOAT)}


def _bevel(c, node, ctx):
    c.warn_node(node, "(Bevel) is not supported; its Normal is the surface's")
    n = c.normal_input(node, "Normal", ctx)
    if n is None:
        n = c.alloc(VEC)
        c.op("geometry", [], [None, n])
    return {node.outputs["Normal"].identifier: n}


VALUE_NODES = {
    "ShaderNodeAmbientOcclusion": _ambient_occlusion,
    "ShaderNodeBevel": _bevel,
    "ShaderNodeValue": _value,
    "ShaderNodeRGB": _rgb,
    "ShaderNodeTexCoord": _texcoord,
    "ShaderNodeUVMap": _uvmap,
    "ShaderNodeAttribute": _attribute,
    "ShaderNodeVertexColor": _attribute,
    "ShaderNodeNewGeometry": _new_geometry,
    "ShaderNodeObjectInfo": _object_info,
    "ShaderNodeHairInfo": _hair_info,
    "ShaderNodeLightPath": _light_path,
    "ShaderNodeFresnel": _fresnel,
    "ShaderNodeLayerWeight": _layer_weight,
    "ShaderNodeCameraData": _camera_data,
    "ShaderNodeTangent": _tangent,
    "ShaderNodeBump": _bump,
    "ShaderNodeNormalMap": _normal_map,
    "ShaderNodeTexImage": _tex_image,
    "ShaderNodeTexNoise": _tex_noise,
    "ShaderNodeTexVoronoi": _tex_voronoi,
    "ShaderNodeTexMusgrave": _tex_musgrave,
    "ShaderNodeTexWave": _tex_wave,
    "ShaderNodeTexMagic": _tex_magic,
    "ShaderNodeTexChecker": _tex_checker,
    "ShaderNodeTexBrick": _tex_brick,
    "ShaderNodeTexGradient": _tex_gradient,
    "ShaderNodeTexWhiteNoise": _tex_white_noise,
    "ShaderNodeMixRGB": _mix_rgb,
    "ShaderNodeMix": _mix,
    "ShaderNodeRGBCurve": _curves("rgb_curves", "Color", COLOR, "rgb"),
    "ShaderNodeVectorCurve": _curves("vector_curves", "Vector", VEC, "vector"),
    "ShaderNodeInvert": _simple("invert", [("Fac", FLOAT), ("Color", COLOR)], [("Color", COLOR)]),
    "ShaderNodeHueSaturation": _simple("hue_sat_val", [("Hue", FLOAT), ("Saturation", FLOAT), ("Value", FLOAT),
                                                       ("Fac", FLOAT), ("Color", COLOR)], [("Color", COLOR)]),
    "ShaderNodeBrightContrast": _simple("bright_contrast", [("Color", COLOR), ("Bright", FLOAT),
                                                            ("Contrast", FLOAT)], [("Color", COLOR)]),
    "ShaderNodeGamma": _simple("gamma", [("Color", COLOR), ("Gamma", FLOAT)], [("Color", COLOR)]),
    "ShaderNodeMapping": _mapping,
    "ShaderNodeVectorTransform": _vector_transform,
    "ShaderNodeNormal": _normal,
    "ShaderNodeVectorRotate": _vector_rotate,
    "ShaderNodeDisplacement": _displacement,
    "ShaderNodeMath": _math,
    "ShaderNodeVectorMath": _vector_math,
    "ShaderNodeMapRange": _map_range,
    "ShaderNodeClamp": _clamp,
    "ShaderNodeValToRGB": _color_ramp,
    "ShaderNodeSeparateColor": _separate_color,
    "ShaderNodeCombineColor": _combine_color,
    "ShaderNodeSeparateRGB": lambda c, n, ctx: _separate_color(c, n, ctx, 0),
    "ShaderNodeCombineRGB": lambda c, n, ctx: _combine_color(c, n, ctx, 0),
    "ShaderNodeSeparateHSV": lambda c, n, ctx: _separate_color(c, n, ctx, 1),
    "ShaderNodeCombineHSV": lambda c, n, ctx: _combine_color(c, n, ctx, 1),
    "ShaderNodeSeparateXYZ": _separate_xyz,
    "ShaderNodeCombineXYZ": _combine_xyz,
    "ShaderNodeRGBToBW": _simple("rgb_to_bw", [("Color", COLOR)], [("Val", FLOAT)]),
    "ShaderNodeBlackbody": _simple("blackbody", [("Temperature", FLOAT)], [("Color", COLOR)]),
    "ShaderNodeWavelength": _simple("wavelength", [("Wavelength", FLOAT)], [("Color", COLOR)]),
}


# -- closure nodes --------------------------------------------------------------------------------

def _mix_shader(c, node, ctx, weight):
    wa, wb = c.alloc(FLOAT), c.alloc(FLOAT)
    c.op("mix_weights", [weight, c.input(node, "Fac", ctx, FLOAT)], [wa, wb])
    c.shader(node.inputs[1], wa, ctx)
    c.shader(node.inputs[2], wb, ctx)


def _add_shader(c, node, ctx, weight):
    c.shader(node.inputs[0], weight, ctx)
    c.shader(node.inputs[1], weight, ctx)


def _closure_normal(c, node, ctx):
    n = c.normal_input(node, "Normal", ctx)
    return n if n is not None else c.surface_normal


def _diffuse(c, node, ctx, weight):
    """Lambert, or Oren-Nayar where Roughness > 0 (decided per hit, as Cycles does)."""
    c.op("diffuse", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Roughness", ctx, FLOAT),
                     _closure_normal(c, node, ctx)])


def _velvet(c, node, ctx, weight):
    c.op("velvet", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Sigma", ctx, FLOAT),
                    _closure_normal(c, node, ctx)])


def _translucent(c, node, ctx, weight):
    c.op("translucent", [weight, c.input(node, "Color", ctx, COLOR), None, _closure_normal(c, node, ctx)])


def _toon(c, node, ctx, weight):
    c.op("toon", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Size", ctx, FLOAT),
                  c.input(node, "Smooth", ctx, FLOAT), _closure_normal(c, node, ctx)],
         ints=[1 if node.component == "GLOSSY" else 0])


def _refraction(c, node, ctx, weight):
    c.op("refraction", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Roughness", ctx, FLOAT),
                        c.input(node, "IOR", ctx, FLOAT), _closure_normal(c, node, ctx)],
         ints=[_dielectric_distribution(c, node)])


def _dielectric_distribution(c, node):
    """Glass and Refraction: Sharp (0), GGX (1) or Beckmann (2) (lobes/dielectric.h)."""
    return 2 if node.distribution == "BECKMANN" else _distribution(c, node)


def _distribution(c, node, supported=("SHARP", "GGX")):
    if node.distribution not in supported:
        c.warn_node(node, "uses the %s distribution, which is not supported; using GGX" % node.distribution)
    return 0 if node.distribution == "SHARP" else 1


GLOSSY_MODES = {"BECKMANN": 2, "MULTI_GGX": 3, "ASHIKHMIN_SHIRLEY": 4}


def _glossy(c, node, ctx, weight):
    """Sharp (0), GGX (1), Beckmann (2), multiscatter GGX (3) or Ashikhmin-Shirley (4)."""
    mode = GLOSSY_MODES.get(node.distribution) or _distribution(c, node)
    c.op("glossy", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Roughness", ctx, FLOAT),
                    _closure_normal(c, node, ctx)], ints=[mode])


ANISOTROPIC_MODES = {"GGX": 1, "BECKMANN": 2, "ASHIKHMIN_SHIRLEY": 3, "MULTI_GGX": 4}


def _tangent_input(c, node, ctx):
    """A closure's Tangent: its link, or Cycles' default for an unlinked one (the radial tangent around
    the object's Z axis, as Geometry > Tangent)."""
    t = c.normal_input(node, "Tangent", ctx)
    if t is None:
        t = c.alloc(VEC)
        c.op("tangent", [], [t], [0, 2, -1])
    return t


def _anisotropic(c, node, ctx, weight):
    """Anisotropic GGX (1), Beckmann (2), Ashikhmin-Shirley (3) or multiscatter GGX (4, its two lobes:
    engine/scene/lobes/multiscatter_aniso_ggx.h) about the Tangent turned by Rotation."""
    mode = ANISOTROPIC_MODES.get(node.distribution)
    if mode is None:
        c.warn_node(node, "uses the %s distribution, which is not supported; using GGX" % node.distribution)
        mode = 1
    c.op("anisotropic", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Roughness", ctx, FLOAT),
                         c.input(node, "Anisotropy", ctx, FLOAT), c.input(node, "Rotation", ctx, FLOAT),
                         _closure_normal(c, node, ctx), _tangent_input(c, node, ctx)], ints=[mode])


def _hair(c, node, ctx, weight):
    """Cycles' Hair BSDF, Reflection (0) or Transmission (1) (lobes/hair.h), about the Tangent, by
    default the curve's own (a `tangent` op of mode 2: it reads the hit, so the material stays a
    program and the shading frame follows the strand). With hair_cycles_sampling, Cycles' own sampler
    (lobes/hair.h, kCyclesSampler), told by the hair_geometry op's LCG number."""
    t = c.normal_input(node, "Tangent", ctx)
    if t is None:
        t = c.alloc(VEC)
        c.op("tangent", [], [t], [2, 0, -1])
    cycles = c.alloc(FLOAT)  # >= 0 with hair_cycles_sampling: Cycles' sampler (the hair_geometry op's LCG number)
    c.op("hair_geometry", [t], [None, None, cycles, None])
    c.op("hair", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Offset", ctx, FLOAT),
                  c.input(node, "RoughnessU", ctx, FLOAT), c.input(node, "RoughnessV", ctx, FLOAT), t, cycles],
         ints=[1 if node.component == "Transmission" else 0])


PRINCIPLED_HAIR_MODES = {"ABSORPTION": 0, "MELANIN": 1, "COLOR": 2}


def _principled_hair(c, node, ctx, weight):
    """Cycles' Principled Hair BSDF (Chiang et al. 2016) as its four paths (lobes/principled_hair.h):
    the hair_geometry op reads wo in the strand's frame at the hit, from which the closure op
    computes each path's attenuation, and the numbers Cycles' per-bounce LCG gives the path's
    longitudinal sample there (principled_hair.h, cycles_bounce_lcg)."""
    t = c.normal_input(node, "Tangent", ctx) if "Tangent" in node.inputs else None
    if t is None:
        t = c.alloc(VEC)
        c.op("tangent", [], [t], [2, 0, -1])
    sin_o, abs_h, lcg0, lcg1 = c.alloc(FLOAT), c.alloc(FLOAT), c.alloc(FLOAT), c.alloc(FLOAT)
    c.op("hair_geometry", [t], [sin_o, abs_h, lcg0, lcg1])
    rand, rand_color, rand_roughness = _principled_hair_random(c, node, ctx)
    c.op("principled_hair", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Melanin", ctx, FLOAT),
                             c.input(node, "Melanin Redness", ctx, FLOAT), c.input(node, "Tint", ctx, COLOR),
                             c.input(node, "Absorption Coefficient", ctx, VEC), c.input(node, "Roughness", ctx, FLOAT),
                             c.input(node, "Radial Roughness", ctx, FLOAT), c.input(node, "Coat", ctx, FLOAT),
                             c.input(node, "IOR", ctx, FLOAT), c.input(node, "Offset", ctx, FLOAT), t, sin_o, abs_h,
                             lcg0, lcg1, rand, rand_color, rand_roughness],
         ints=[PRINCIPLED_HAIR_MODES.get(node.parametrization, 2)])


def _principled_hair_random(c, node, ctx):
    """Random, Random Color and Random Roughness of a Principled Hair BSDF (None each when neither
    amount is used: Cycles' factors are then 1). Random is the linked input's, or unlinked, Hair
    Info's per-strand Random on hair and the socket's own value elsewhere (Cycles' PrincipledHairBsdfNode
    asks for ATTR_STD_CURVE_RANDOM when Random is unlinked; svm/closure.h falls back to the socket)."""
    amounts = [node.inputs.get(n) for n in ("Random Color", "Random Roughness")]
    if not any(s is not None and (nodes.linked_output(s) is not None or s.default_value != 0.0) for s in amounts):
        return None, None, None
    sock = node.inputs["Random"]
    if nodes.linked_output(sock) is not None:
        rand = c.input(node, "Random", ctx, FLOAT)
    else:
        rand = c.alloc(FLOAT)
        c.op("hair_info", [c.input(node, "Random", ctx, FLOAT)], [None, rand])
    return rand, c.input(node, "Random Color", ctx, FLOAT), c.input(node, "Random Roughness", ctx, FLOAT)


def _glass(c, node, ctx, weight):
    """One dielectric lobe; rough, it weights reflection and refraction by the Fresnel term at the
    shading normal as Cycles 3.4's pair of closures does (lobes/dielectric.h). Multiscatter GGX (3):
    Cycles' one multiscatter glass closure (lobes/multi_glass.h, glass_multiple.h); Beckmann (2)."""
    mode = 3 if node.distribution == "MULTI_GGX" else _dielectric_distribution(c, node)
    c.op("glass", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Roughness", ctx, FLOAT),
                   c.input(node, "IOR", ctx, FLOAT), _closure_normal(c, node, ctx)], ints=[mode])


def _transparent(c, node, ctx, weight):
    c.op("transparent", [weight, c.input(node, "Color", ctx, COLOR)])


def _emission(c, node, ctx, weight):
    c.op("emission", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Strength", ctx, FLOAT)])


# Subsurface methods in the engine's order (scene/subsurface_closure.h).
SUBSURFACE_METHODS = {"RANDOM_WALK": 0, "RANDOM_WALK_FIXED_RADIUS": 1, "BURLEY": 2}


def _subsurface(c, node, ctx, weight):
    """Subsurface Scattering: walked by the RGB path tracer (integrators/subsurface_walk.h), or
    Christensen-Burley's disk sampling (integrators/subsurface_disk.h)."""
    c.op("subsurface", [weight, c.input(node, "Color", ctx, COLOR), c.input(node, "Scale", ctx, FLOAT),
                        c.input(node, "Radius", ctx, VEC), c.input(node, "IOR", ctx, FLOAT),
                        c.input(node, "Anisotropy", ctx, FLOAT), _closure_normal(c, node, ctx)],
         ints=[SUBSURFACE_METHODS.get(node.falloff, 0)])


def _holdout(c, node, ctx, weight):
    c.op("holdout", [weight])


def _principled(c, node, ctx, weight):
    ins = [weight]
    used = lambda name: node.inputs[name].is_linked or node.inputs[name].default_value != 0.0  # noqa: E731
    for name in PRINCIPLED_INPUTS:
        sock = node.inputs.get(name)
        if sock is None:
            ins.append(None)
        elif name == "Tangent":
            ins.append(_tangent_input(c, node, ctx) if used("Anisotropic") else None)
        elif name in ("Normal", "Clearcoat Normal"):
            n = c.normal_input(node, name, ctx)
            ins.append(n if n is not None or name != "Normal" else c.surface_normal)
        else:
            ins.append(c.socket_value(sock, ctx, VEC if name in VECTOR_INPUTS_OF_PRINCIPLED else None))
    # ints: the distribution (1: Multiscatter GGX), the subsurface method
    c.op("principled", ins, ints=[1 if node.distribution == "MULTI_GGX" else 0,
                                  SUBSURFACE_METHODS.get(node.subsurface_method, 0)])


SHADER_NODES = {
    "ShaderNodeMixShader": _mix_shader,
    "ShaderNodeAddShader": _add_shader,
    "ShaderNodeBsdfDiffuse": _diffuse,
    "ShaderNodeBsdfGlossy": _glossy,
    "ShaderNodeBsdfGlass": _glass,
    "ShaderNodeBsdfAnisotropic": _anisotropic,
    "ShaderNodeBsdfHair": _hair,
    "ShaderNodeBsdfHairPrincipled": _principled_hair,
    "ShaderNodeBsdfVelvet": _velvet,
    "ShaderNodeBsdfTranslucent": _translucent,
    "ShaderNodeBsdfRefraction": _refraction,
    "ShaderNodeBsdfToon": _toon,
    "ShaderNodeBsdfTransparent": _transparent,
    "ShaderNodeEmission": _emission,
    "ShaderNodeBsdfPrincipled": _principled,
    "ShaderNodeHoldout": _holdout,
    "ShaderNodeSubsurfaceScattering": _subsurface,
}


def compile_material(material, output_node, warn, textures, scene):
    """The program dict for a material's Surface (and Displacement as bump), whether it reads surface
    attributes (UVs, colours), and the attributes the mesh export must derive for it."""
    c = ShaderCompiler(material.name, warn, textures, scene)
    c.compile_surface(output_node)
    return c.program(), c.uses_uv, sorted(c.derived_attributes)


# -- the World --------------------------------------------------------------------------------------
# A World's Surface compiles with the same nodes, evaluated per direction (engine/scene/
# environment_light.h): Background (and Emission, which Cycles' background treats alike) add to the
# radiance; Texture Coordinate, Geometry and Light Path read the direction and the ray's kind.

class _EnvironmentNode:
    """An Environment Texture node as TextureCache reads an Image Texture node: Cycles repeats it,
    and it has no Alpha output (the colour stays as stored)."""
    extension = "REPEAT"

    class _Unlinked:
        is_linked = False

    outputs = {"Alpha": _Unlinked()}

    def __init__(self, node):
        self._node = node

    def __getattr__(self, name):
        return getattr(self._node, name)


def _position(c):
    """Geometry's Position: the shading point, or the direction in the World (Cycles' default vector
    of the Environment Texture)."""
    v = c.alloc(VEC)
    c.op("geometry", [], [v])
    return v


def _tex_environment(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR), ("Alpha", FLOAT)])
    if c.textures is None:
        c.op("convert", [c.constant(0.0, FLOAT)], [regs[0]], [0])
        return res
    tex_id = c.textures.id_for(_EnvironmentNode(node))  # no image: Cycles' magenta
    local = len(c.texture_ids)
    c.texture_ids.append(tex_id)
    vec = c.input(node, "Vector", ctx, VEC, lambda: _position(c))
    c.op("tex_environment", [vec], regs, [local, 1 if node.projection == "MIRROR_BALL" else 0])
    sizes = getattr(c, "environment_sizes", None)
    if sizes is not None and node.image is not None:
        try:
            w, h = node.image.size
            if w > 0 and h > 0:
                sizes.append((int(w), int(h)))
        except (RuntimeError, ReferenceError):
            pass
    return res


def _sky_perez(lam, theta, gamma):
    return ((1.0 + lam[0] * math.exp(lam[1] / math.cos(theta))) *
            (1.0 + lam[2] * math.exp(lam[3] * gamma) + lam[4] * math.cos(gamma) ** 2))


def _sky_preetham(sun_direction, turbidity):
    """Cycles 3.4's Preetham precomputation (scene/shader_nodes.cpp): the sun's spherical angles, the
    zenith Y, x, y over the Perez function at the zenith and the Perez coefficients of Y, x, y, in
    the layout of the engine's tex_sky op (shader_program.cpp, sky_preetham)."""
    sx, sy, sz = sun_direction
    theta = math.acos(max(-1.0, min(1.0, sz)))
    phi = math.atan2(sx, sy)
    t, t2 = turbidity, turbidity * turbidity
    th, th2, th3 = theta, theta * theta, theta ** 3
    chi = (4.0 / 9.0 - t / 120.0) * (math.pi - 2.0 * theta)
    zenith_Y = ((4.0453 * t - 4.9710) * math.tan(chi) - 0.2155 * t + 2.4192) * 0.06
    zenith_x = ((0.00166 * th3 - 0.00375 * th2 + 0.00209 * th) * t2 +
                (-0.02903 * th3 + 0.06377 * th2 - 0.03202 * th + 0.00394) * t +
                (0.11693 * th3 - 0.21196 * th2 + 0.06052 * th + 0.25886))
    zenith_y = ((0.00275 * th3 - 0.00610 * th2 + 0.00317 * th) * t2 +
                (-0.04214 * th3 + 0.08970 * th2 - 0.04153 * th + 0.00516) * t +
                (0.15346 * th3 - 0.26756 * th2 + 0.06670 * th + 0.26688))
    perez_Y = [0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
               -0.0670 * t + 0.3703]
    perez_x = [-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
               -0.0033 * t + 0.0452]
    perez_y = [-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
               -0.0109 * t + 0.0529]
    return ([theta, phi, 0.0, zenith_Y / _sky_perez(perez_Y, 0.0, theta),
             zenith_x / _sky_perez(perez_x, 0.0, theta), zenith_y / _sky_perez(perez_y, 0.0, theta)]
            + perez_Y + perez_x + perez_y)


def _bezier5(points, t):
    """The quintic Bezier curve through 6 control points at t (Hosek-Wilkie's elevation curve)."""
    s = 1.0 - t
    return (s ** 5 * points[0] + 5 * s ** 4 * t * points[1] + 10 * s ** 3 * t ** 2 * points[2] +
            10 * s ** 2 * t ** 3 * points[3] + 5 * s * t ** 4 * points[4] + t ** 5 * points[5])


def _hosek_cook(table, stride, turbidity, albedo, elevation):
    """One channel's `stride` values (9 configuration parameters, or 1 radiance scale) for the
    conditions: each (albedo, turbidity) entry of the table is a Bezier curve over
    (elevation / (pi/2))^(1/3), interpolated linearly in albedo and between integer turbidities
    (Hosek and Wilkie 2012, the model's reference implementation)."""
    t_int = int(turbidity)
    t_rem = turbidity - t_int
    e = (elevation / (math.pi / 2.0)) ** (1.0 / 3.0)
    out = [0.0] * stride
    block = 6 * stride
    for alb_weight, alb in ((1.0 - albedo, 0), (albedo, 1)):
        for t_weight, t in ((1.0 - t_rem, t_int - 1), (t_rem, t_int)):
            if t_weight == 0.0 or t > 9:
                continue
            base = alb * 10 * block + t * block
            for i in range(stride):
                pts = [table[base + i + stride * k] for k in range(6)]
                out[i] += alb_weight * t_weight * _bezier5(pts, e)
    return out


def _sky_hosek(sun_direction, turbidity, ground_albedo):
    """Cycles 3.4's Hosek-Wilkie precomputation (scene/shader_nodes.cpp, SKY_arhosek_xyz_skymodelstate_
    alloc_init): the sun's spherical angles (clamped to the horizon), each XYZ channel's radiance
    scale and nine configuration values, in the layout of the engine's tex_sky op (sky_hosek)."""
    sx, sy, sz = sun_direction
    theta = min(max(math.acos(max(-1.0, min(1.0, sz))), 0.0), math.pi / 2.0)
    phi = math.atan2(sx, sy)
    # Cycles clamps to [0, 10]; the model's tables start at turbidity 1 (below it reads before them).
    turbidity = min(max(turbidity, 1.0), 10.0)
    elevation = math.pi / 2.0 - theta
    configs, radiances = [], []
    for channel in range(3):
        configs += _hosek_cook(sky_hosek_data.CONFIG[channel], 9, turbidity, ground_albedo, elevation)
        radiances += _hosek_cook(sky_hosek_data.RADIANCE[channel], 1, turbidity, ground_albedo, elevation)
    return [theta, phi] + radiances + configs


def _reads_plain_direction(node):
    """Whether the node's Vector is the World direction itself (unlinked, or Texture Coordinate's
    Generated): then Cycles samples a Nishita sun on its own (scene/light.cpp), and so does the engine."""
    src = nodes.linked_output(node.inputs["Vector"])
    return src is None or (src.node.bl_idname == "ShaderNodeTexCoord" and src.name == "Generated")


def _tex_sky(c, node, ctx):
    res, regs = _outs(c, node, [("Color", COLOR)])
    offset = len(c.data)
    if node.sky_type == "NISHITA":
        # The node's parameters as the user set them: the engine precomputes the sky's table and
        # the sun's disc as Cycles does (engine/shading/sky_nishita.h).
        c.data.extend(float(v) for v in (node.sun_elevation, node.sun_rotation, 1.0 if node.sun_disc else 0.0,
                                          node.sun_size, node.sun_intensity, node.altitude, node.air_density,
                                          node.dust_density, node.ozone_density))
        plain = _reads_plain_direction(node)
        model = [2, 0, 1 if plain else 0]
        suns = getattr(c, "nishita_suns", None)
        if suns is not None and node.sun_disc:
            suns.append(plain)
    elif node.sky_type == "HOSEK_WILKIE":
        c.data.extend(float(v) for v in _sky_hosek(tuple(node.sun_direction), float(node.turbidity),
                                                   float(node.ground_albedo)))
        model = [1]
    else:
        c.data.extend(float(v) for v in _sky_preetham(tuple(node.sun_direction), float(node.turbidity)))
        model = [0]
    c.op("tex_sky", [c.vector_input(node, ctx)], regs, model, data=offset)
    return res


VALUE_NODES["ShaderNodeTexEnvironment"] = _tex_environment
VALUE_NODES["ShaderNodeTexSky"] = _tex_sky

# Shader nodes with a meaning in the World (Cycles keeps only background and emission closures there).
_WORLD_SHADER_NODES = {"ShaderNodeBackground", "ShaderNodeEmission", "ShaderNodeMixShader", "ShaderNodeAddShader"}


class _WorldCompiler(ShaderCompiler):
    """Compiles a World's Surface: Background becomes the "background" closure op, BSDFs add nothing."""

    def __init__(self, world_name, warn, textures):
        super().__init__(world_name, warn, textures, None)
        self.environment_sizes = []  # (width, height) of the Environment Texture images
        self.nishita_suns = []  # per Nishita Sky Texture with a sun disc: whether it reads the plain direction

    def warn_node(self, node, text):
        key = (node.as_pointer(), text)
        if key in self._warned:
            return
        self._warned.add(key)
        self.warn("World '%s': node '%s' (%s) %s" % (self.name, node.name, node.bl_idname, text))

    def shader(self, socket, weight, ctx):
        src = nodes.linked_output(socket)
        if src is not None and src.type == "SHADER":
            node = src.node
            if node.bl_idname == "ShaderNodeBackground":
                self.op("background", [weight, self.input(node, "Color", ctx, COLOR),
                                       self.input(node, "Strength", ctx, FLOAT)])
                return
            group = node.bl_idname in ("ShaderNodeGroup", "NodeGroup", "NodeGroupInput") or node.type == "GROUP"
            if not group and node.bl_idname not in _WORLD_SHADER_NODES:
                self.warn_node(node, "is not a World shader (Background, Emission, Mix or Add Shader); it adds "
                                     "nothing, as in Cycles")
                return
        super().shader(socket, weight, ctx)


def compile_world(world, output_node, warn, textures):
    """The program dict for a World's Surface (textures: a TextureCache), the sizes of its
    Environment Texture images and, per Nishita sun disc, whether it reads the plain direction (for
    Cycles' automatic importance map resolution)."""
    c = _WorldCompiler(world.name, warn, textures)
    c.shader(output_node.inputs["Surface"], c.constant(1.0, FLOAT), _Context())
    return c.program(), c.environment_sizes, c.nishita_suns
