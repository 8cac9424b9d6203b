"""Image Texture nodes -> engine textures.

Images go to the engine once per render and sampling set-up (`foreach_get` of
`Image.pixels`, bottom row first, as the engine wants), with what Cycles needs
to read them as it does: colour space, alpha mode, 8-bit or float storage and
whether the node's Alpha output is used (engine/scene/texture.h). A missing or
unreadable image renders magenta, as in Cycles, with a warning naming it.
"""

import numpy as np

# Blender colour spaces holding data, not colour: alpha never changes their RGB.
DATA_SPACES = {"Non-Color", "Raw"}
LINEAR_SPACES = {"Linear", "Linear ACES", "Linear ACEScg", "XYZ"}


class TextureCache:
    """Adds each image (with its sampling settings) to the engine scene once."""

    def __init__(self, scene, warn):
        self._scene = scene
        self._warn = warn
        self._ids = {}
        self._missing = None

    def missing(self):
        """The magenta stand-in Cycles renders for an image it cannot load."""
        if self._missing is None:
            self._missing = self._scene.add_missing_texture()
        return self._missing

    def id_for(self, node):
        """Engine texture id for an Image Texture node; the magenta stand-in (with a warning) when
        its image is missing or unreadable."""
        image = node.image
        if image is None:
            return self.missing()
        alpha_linked = node.outputs["Alpha"].is_linked
        key = (image.name_full, node.interpolation, node.extension, alpha_linked)
        if key not in self._ids:
            self._ids[key] = self._add(node, image, alpha_linked)
        return self._ids[key]

    def _add(self, node, image, alpha_linked):
        try:
            w, h = image.size  # loads the file if needed
            ok = w > 0 and h > 0 and len(image.pixels) == w * h * 4
        except (RuntimeError, ReferenceError):
            ok = False
        if not ok:
            self._warn("Image '%s' (%s, node '%s') cannot be loaded; it renders magenta as in Cycles"
                       % (image.name, image.filepath or "packed", node.name))
            return self.missing()
        pixels = np.empty(w * h * 4, dtype=np.float32)
        image.pixels.foreach_get(pixels)
        space = image.colorspace_settings.name
        byte_image = not image.is_float
        if space in DATA_SPACES:
            colorspace = "data"
        elif space == "sRGB" and byte_image:
            colorspace = "sRGB"
        else:
            # Float images hold scene-linear values whatever their label (as Blender loads them).
            colorspace = "linear"
            if space not in LINEAR_SPACES and space != "sRGB":
                self._warn("Image '%s' uses colour space %s, which is not supported; read as linear"
                           % (image.name, space))
        alpha_mode = image.alpha_mode
        if colorspace != "data":
            rgba = pixels.reshape(-1, 4)
            if not byte_image and alpha_mode == "STRAIGHT":
                # Blender premultiplied the float pixels; Cycles reads the file as stored.
                a = rgba[:, 3:4]
                np.divide(rgba[:, :3], a, out=rgba[:, :3], where=a > 0.0)
            elif byte_image and alpha_mode == "PREMUL":
                # Blender un-premultiplied the bytes; Cycles reads them premultiplied.
                rgba[:, :3] = np.round(255.0 * rgba[:, :3] * rgba[:, 3:4]) / 255.0
        return self._scene.add_texture(pixels.reshape(h, w, 4), colorspace, node.interpolation,
                                       node.extension, alpha_mode, byte_image, alpha_linked)
