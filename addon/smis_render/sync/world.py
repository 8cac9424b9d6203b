"""The scene's World -> the engine's world: a constant radiance, or the World's Surface compiled
into a shader program (shader_compiler.compile_world) that the engine evaluates per direction and
importance-samples (engine/scene/environment_light.h). A program that folds to a constant (a
Background with unlinked inputs, an RGB node, ...) costs what the constant colour does."""

from . import nodes
from .shader_compiler import compile_world
from .textures import TextureCache
from .volumes import translate_volume

# Cycles' automatic importance map (scene/light.cpp, 3.4): without a single Nishita sun at least
# 4096 x 2048 cells, or the largest Environment Texture image when it is bigger; with one (sampled on
# its own, engine/scene/environment_light.h) at least 512 x 256.
_AUTO_MAP = (4096, 2048)
_AUTO_MAP_WITH_SUN = (512, 256)


class _WorldImages:
    """Stands in for the engine scene in a TextureCache: the World's images travel in its dict (the
    engine keeps them with the program, so a world edit in the viewport frees the old ones)."""

    def __init__(self):
        self.images = []

    def add_texture(self, rgba, colorspace, interpolation, extension, alpha_mode, byte_image, alpha_linked):
        self.images.append({"rgba": rgba, "colorspace": colorspace, "interpolation": interpolation,
                            "extension": extension, "alpha_mode": alpha_mode, "byte_image": bool(byte_image),
                            "alpha_linked": bool(alpha_linked)})
        return len(self.images) - 1

    def add_missing_texture(self):
        self.images.append({"missing": True})
        return len(self.images) - 1


# engine key -> World.cycles_visibility's property (its Camera flag is "visible_camera")
WORLD_RAY_VISIBILITY = (
    ("diffuse", "diffuse"),
    ("glossy", "glossy"),
    ("transmission", "transmission"),
    ("volume_scatter", "scatter"),
)


def evaluated_world(depsgraph):
    """The scene's World as the depsgraph evaluated it for its frame. `depsgraph.scene.world` is the
    original datablock: in a render from the command line it keeps the values last set by hand, not
    the keyed ones of the frame (a keyed Background strength or Sky Texture parameter)."""
    world = depsgraph.scene.world
    return world.evaluated_get(depsgraph) if world is not None else None


def export_world(world, warn):
    """The dict for `_smis.Scene.set_world` / `replace_lights`: {"color", "strength"} (the constant
    World), "visible_camera" and "visibility" (the World's Ray Visibility), and for a node World
    "program", "images", "map_resolution", "volume".
    No world -> black."""
    if world is None:
        return {"color": (0.0, 0.0, 0.0), "strength": 0.0}
    desc = {"color": tuple(world.color), "strength": 1.0}  # Cycles renders world.color without nodes
    visibility = getattr(world, "cycles_visibility", None)
    if visibility is not None:
        desc["visible_camera"] = bool(visibility.camera)
        # Cycles' World > Ray Visibility: bounce rays of a hidden type see no World and its light
        # samples light no lobe of that class (as a lamp's flags).
        flags = {key: bool(getattr(visibility, prop)) for key, prop in WORLD_RAY_VISIBILITY}
        if not all(flags.values()):
            desc["visibility"] = flags
    if not world.use_nodes or world.node_tree is None:
        return desc
    output = nodes.output_node(world.node_tree)
    desc["volume"] = translate_volume(output, "World '%s'" % world.name, warn)
    if output is None:
        warn("World '%s' has no World Output node; using the world colour" % world.name)
        return desc
    desc.update(color=(0.0, 0.0, 0.0), strength=0.0)  # an unlinked Surface is black, as in Cycles
    if nodes.linked_output(output.inputs["Surface"]) is None:
        return desc
    images = _WorldImages()
    program, sizes, suns = compile_world(world, output, warn, TextureCache(images, warn))
    desc.update(program=program, images=images.images, map_resolution=_map_resolution(world, sizes, suns))
    return desc


def _map_resolution(world, environment_sizes, nishita_suns=()):
    """The importance map's (width, height) as Cycles picks it from the World's Settings."""
    settings = getattr(world, "cycles", None)
    method = getattr(settings, "sampling_method", "AUTOMATIC")
    if method == "MANUAL":
        res = max(int(getattr(settings, "sample_map_resolution", 1024)), 4)
        return (res, res // 2)
    if method == "NONE":
        # Cycles then never samples the World as a light; a one-cell map samples it uniformly,
        # which converges to the same image.
        return (1, 1)
    base = _AUTO_MAP_WITH_SUN if list(nishita_suns) == [True] else _AUTO_MAP
    width = max([base[0]] + [w for w, h in environment_sizes])
    height = max([base[1]] + [h for w, h in environment_sizes])
    return (width, height)
