"""Image Texture, Object Info and Normal Map nodes -> engine texture inputs.

A colour socket of a BSDF is either constant (its own value), or fed by an
Image Texture's Color (UV mapped), or by Object Info's Color; anything else is
not translated and the caller warns. Images go to the engine once per render
(`foreach_get` of `Image.pixels`, bottom row first, as the engine wants), in
their own colour space: sRGB is decoded by the engine, linear data kept.
"""

import numpy as np

from . import nodes

# Blender colour spaces whose pixels are already scene-linear (or data) for the engine.
LINEAR_SPACES = {"Linear", "Non-Color", "Raw", "Linear ACES", "Linear ACEScg", "XYZ"}
SUPPORTED_INTERPOLATION = {"Linear", "Closest"}


class TextureCache:
    """Adds each image (with its sampling settings) to the engine scene once."""

    def __init__(self, scene, warn):
        self._scene = scene
        self._warn = warn
        self._ids = {}

    def id_for(self, node):
        """Engine texture id for an Image Texture node, or None (with a warning) if unusable."""
        image = node.image
        if image is None:
            return None
        key = (image.name_full, node.interpolation, node.extension)
        if key in self._ids:
            return self._ids[key]
        tex_id = self._ids[key] = self._add(node, image)
        return tex_id

    def _add(self, node, image):
        w, h = image.size  # loads the file if needed
        if w == 0 or h == 0 or len(image.pixels) != w * h * 4:
            self._warn("Image '%s' (node '%s') has no pixels (missing file?); ignored"
                       % (image.name, node.name))
            return None
        pixels = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        space = image.colorspace_settings.name
        if space == "sRGB" and not image.is_float:
            colorspace = "sRGB"
        else:
            # Float images hold scene-linear values whatever their label (as Blender loads them).
            colorspace = "linear"
            if space not in LINEAR_SPACES and space != "sRGB":
                self._warn("Image '%s' uses colour space %s, which is not supported; read as linear"
                           % (image.name, space))
        if node.interpolation not in SUPPORTED_INTERPOLATION:
            self._warn("Image Texture '%s': %s interpolation is not supported, using Linear"
                       % (node.name, node.interpolation))
        if node.projection != 'FLAT':
            self._warn("Image Texture '%s': %s projection is not supported, using Flat"
                       % (node.name, node.projection))
        extension = node.extension if node.extension in {"REPEAT", "EXTEND", "CLIP"} else "REPEAT"
        return self._scene.add_texture(pixels.reshape(h, w, 4), colorspace,
                                       "Closest" if node.interpolation == "Closest" else "Linear",
                                       extension)


def uv_map_of(image_node):
    """(name or '' for the active render UV map, translated?) for an Image Texture's Vector input."""
    src = nodes.linked_output(image_node.inputs["Vector"])
    if src is None:
        return "", True
    if src.node.bl_idname == 'ShaderNodeUVMap':
        return src.node.uv_map, True
    if src.node.bl_idname == 'ShaderNodeTexCoord' and src.name == "UV":
        return "", True
    return "", False


class ColorInput:
    """What feeds a colour socket: a constant, or an engine texture / the object colour."""

    def __init__(self, constant=None, texture=None, object_color=False, uv_map=None):
        self.constant = constant          # RGB tuple when the socket is not linked
        self.texture = texture            # engine texture id
        self.object_color = object_color
        self.uv_map = uv_map              # UV map name the texture reads ('' = active render)

    def closure_keys(self, to_f0=False):
        keys = {}
        if self.texture is not None:
            keys["texture"] = self.texture
        if self.object_color:
            keys["object_color"] = True
        if keys and to_f0:
            keys["to_f0"] = True
        return keys


def color_input(socket, textures, warn_node):
    """Translate a colour socket. Returns a ColorInput, or None if its link is not translatable
    (the caller then uses the socket's own value and warns)."""
    src = nodes.linked_output(socket)
    if src is None:
        value = socket.default_value
        return ColorInput(constant=(float(value[0]), float(value[1]), float(value[2])))
    node = src.node
    if node.bl_idname == 'ShaderNodeObjectInfo' and src.name == "Color":
        return ColorInput(object_color=True)
    if node.bl_idname == 'ShaderNodeTexImage' and src.name == "Color" and textures is not None:
        uv_map, ok = uv_map_of(node)
        if not ok:
            warn_node(node, "has a Vector input other than a UV map; using the default UV map")
        tex = textures.id_for(node)
        if tex is None:
            return ColorInput(constant=(0.0, 0.0, 0.0))
        return ColorInput(texture=tex, uv_map=uv_map)
    return None


def alpha_input(socket, textures):
    """Principled Alpha: ({"value": a}, None) for a constant below 1, ({"value": 1, "texture": id},
    uv_map) for an Image Texture's Alpha output, None when opaque or not translatable."""
    src = nodes.linked_output(socket)
    if src is None:
        value = float(socket.default_value)
        return ({"value": value}, None) if value < 1.0 else None
    node = src.node
    if node.bl_idname != 'ShaderNodeTexImage' or src.name != "Alpha" or textures is None:
        return None
    tex = textures.id_for(node)
    if tex is None:
        return None
    return {"value": 1.0, "texture": tex}, uv_map_of(node)[0]


def normal_map(socket, textures, warn_node):
    """A shader's Normal input fed by Normal Map (tangent space) <- Image Texture: returns
    ({"texture": id, "strength": s}, uv_map) or None if not linked; (None, None) if not
    translatable (the caller warns)."""
    src = nodes.linked_output(socket)
    if src is None:
        return None
    node = src.node
    if node.bl_idname != 'ShaderNodeNormalMap' or node.space != 'TANGENT' or textures is None:
        return None, None
    image = nodes.linked_output(node.inputs["Color"])
    if image is None or image.node.bl_idname != 'ShaderNodeTexImage' or image.name != "Color":
        return None, None
    if nodes.linked_output(node.inputs["Strength"]) is not None:
        warn_node(node, "has a linked Strength, which is not supported; using its value")
    tex = textures.id_for(image.node)
    if tex is None:
        return None, None
    uv_map, _ = uv_map_of(image.node)
    return {"texture": tex, "strength": float(node.inputs["Strength"].default_value)}, node.uv_map or uv_map
