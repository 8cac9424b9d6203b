"""The scene's World -> a constant background radiance."""

from . import nodes
from .volumes import translate_volume

# Emission behaves exactly like Background when plugged into the World Output.
_BACKGROUND_NODES = {'ShaderNodeBackground', 'ShaderNodeEmission'}


def export_world(world, warn):
    """{"color", "strength", "volume"} for `_smis.Scene.set_world`. No world -> black."""
    desc = _export_background(world, warn)
    if world is not None and world.use_nodes and world.node_tree is not None:
        desc["volume"] = translate_volume(nodes.output_node(world.node_tree), "World '%s'" % world.name, warn)
    return desc


def _export_background(world, warn):
    if world is None:
        return {"color": (0.0, 0.0, 0.0), "strength": 0.0}
    fallback = {"color": tuple(world.color), "strength": 1.0}
    if not world.use_nodes or world.node_tree is None:
        return fallback  # Cycles renders world.color for a world without nodes

    output = nodes.output_node(world.node_tree)
    if output is None:
        warn("World '%s' has no World Output node; using the world colour" % world.name)
        return fallback
    src = nodes.linked_output(output.inputs["Surface"])
    if src is None:
        return {"color": (0.0, 0.0, 0.0), "strength": 0.0}  # unlinked Surface: black, as Cycles
    node = src.node
    if node.bl_idname not in _BACKGROUND_NODES:
        warn("World '%s': node '%s' (%s) is not supported, using the world colour"
             % (world.name, node.name, node.bl_idname))
        return fallback

    linked = nodes.linked_inputs(node)
    if linked:
        warn("World '%s': node '%s' has linked inputs (%s); textures are not supported, "
             "using the inputs' own values" % (world.name, node.name, ", ".join(linked)))
    color = node.inputs["Color"].default_value
    return {"color": (float(color[0]), float(color[1]), float(color[2])),
            "strength": float(node.inputs["Strength"].default_value)}
