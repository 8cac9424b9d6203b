"""Blender materials (shader node trees) -> engine material dicts.

A node material becomes a shader program (shader_compiler.py) that the engine
evaluates per hit, after folding whatever does not depend on the hit; a tree of
constants therefore ends as a flat, weighted closure list with an emission
colour, as Cycles' constant folding would leave it. Materials without nodes
are Cycles' diffuse of their viewport colour. Volumes and the spectral settings
are translated beside the program.
"""

import bpy

from . import nodes, textures as tex
from .shader_compiler import compile_material
from ..spectral_properties import material_spectral
from .volumes import translate_volume

NEUTRAL_GREY = (0.8, 0.8, 0.8)
BLACK = (0.0, 0.0, 0.0)
DEFAULT_MATERIAL_NAME = "SMIS default grey"


def closure(kind, weight, roughness=0.0, ior=1.5, fresnel="none", f0=BLACK, **inputs):
    """One engine closure; every key is always present so the engine can be strict.
    `inputs`: texture / object_color / to_f0 (textures.ColorInput.closure_keys)."""
    return {"kind": kind, "fresnel": fresnel, "weight": tuple(weight), "f0": tuple(f0),
            "roughness": float(roughness), "ior": float(ior), **inputs}


def default_material(name=DEFAULT_MATERIAL_NAME):
    return {"name": name, "closures": [closure("diffuse", NEUTRAL_GREY)], "emission": BLACK}


def _rgb(value):
    return (float(value[0]), float(value[1]), float(value[2]))


def translate(material, warn, textures=None, scene=None):
    """Engine material dict for a Blender material. `warn(msg)` receives warnings; `textures`
    (a textures.TextureCache) adds images to the engine, without it image textures render black;
    `scene` interns the attribute names the program reads. The dict's "uv_map" is '' when the
    program reads surface attributes (UVs, colour attributes), None when it needs none."""
    name = material.name_full
    if not material.use_nodes or material.node_tree is None:
        # What Cycles renders for a material without nodes.
        return dict({"name": name, "closures": [closure("diffuse", _rgb(material.diffuse_color))],
                     "emission": BLACK}, **material_spectral(material))

    output = nodes.output_node(material.node_tree)
    volume = None
    pass_through = False
    program, uses_uv, derived_attributes = None, False, []
    if output is None:
        warn("Material '%s' has no Material Output node for Cycles/All; it renders black"
             % material.name)
    else:
        surface = nodes.linked_output(output.inputs["Surface"])
        volume = translate_volume(output, "Material '%s'" % material.name, warn)
        if surface is not None or nodes.linked_output(output.inputs["Displacement"]) is not None:
            program, uses_uv, derived_attributes = compile_material(material, output, warn, textures, scene)
            if material.cycles.displacement_method in ('DISPLACEMENT', 'BOTH'):
                warn("Material '%s' asks for true displacement; SMIS renders it as bump only"
                     % material.name)
        # An unlinked Surface renders black, as in Cycles, unless the material has a volume: then
        # the mesh is only the boundary of the medium and rays pass straight through it.
        pass_through = surface is None and volume is not None
        if surface is None:
            program = None
    desc = dict({"name": name, "closures": [], "emission": BLACK, "uv_map": "" if uses_uv else None,
                 "derived_attributes": derived_attributes, "volume": volume, "pass_through": pass_through},
                **material_spectral(material))
    if program is not None:
        desc["program"] = program
    return desc


class MaterialCache:
    """Adds each Blender material to the engine scene once and remembers its id."""

    def __init__(self, scene, reporter):
        self._scene = scene
        self._reporter = reporter
        self._ids = {}
        self._uv_maps = {}  # engine id -> UV map its textures read ('' = active render)
        self._derived_attributes = {}  # engine id -> attributes the mesh export derives for it
        self._textures = tex.TextureCache(scene, reporter.warning)

    def id_for(self, material):
        """Engine material id for a Blender material, or for the default grey if None."""
        key = material.name_full if material is not None else None
        mat_id = self._ids.get(key)
        if mat_id is None:
            mat_id = self._add(material)
            self._ids[key] = mat_id
        return mat_id

    def _add(self, material):
        if material is None:
            return self._scene.add_material(default_material())
        desc = translate(material, self._reporter.warning, self._textures, self._scene)
        try:
            mat_id = self._scene.add_material(desc)
            if desc.get("uv_map") is not None:
                self._uv_maps[mat_id] = desc["uv_map"]
            if desc.get("derived_attributes"):
                self._derived_attributes[mat_id] = desc["derived_attributes"]
            return mat_id
        except ValueError as exc:
            self._reporter.warning("Material '%s' was refused by the engine (%s); using a "
                                   "neutral diffuse" % (material.name, exc))
            return self._scene.add_material(default_material(desc["name"]))

    def warning(self, message):
        self._reporter.warning(message)

    def replace_all(self):
        """Viewport material edits: translate every material again and replace it in the committed
        engine scene (Scene.replace_material). False when one of them cannot be replaced in place
        (the caller then builds a new scene): a material that is gone, reads another UV map, or
        changes what the scene baked at commit (cut-out, emissive, volume)."""
        for key, mat_id in self._ids.items():
            if key is None:
                continue  # the default grey never changes
            material = bpy.data.materials.get(key)
            if material is None:
                return False
            desc = translate(material, self._reporter.warning, self._textures, self._scene)
            if desc.get("uv_map") != self._uv_maps.get(mat_id):
                return False
            try:
                if not self._scene.replace_material(mat_id, desc):
                    return False
            except ValueError:
                return False
        return True

    def uv_map_for(self, mat_ids):
        """The UV map a mesh with these engine materials must export, or None if none reads UVs."""
        for mat_id in mat_ids:
            if mat_id in self._uv_maps:
                return self._uv_maps[mat_id]
        return None

    def derived_attributes_for(self, mat_ids):
        """The attributes (mesh.TANGENT_PREFIX + UV map, POINTINESS, ...) a mesh with these materials
        must derive."""
        return tuple(sorted({m for mat_id in mat_ids for m in self._derived_attributes.get(mat_id, ())}))

    def __len__(self):
        return len(self._ids)
