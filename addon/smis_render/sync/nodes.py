"""Following links in shader node trees the way Blender's shader compiler does."""

# Reroute chains and muted nodes are followed at most this far; valid trees are
# acyclic, this only guards against a corrupt file looping forever.
_MAX_HOPS = 1000


def linked_output(input_socket):
    """The output socket that really feeds `input_socket`, or None.

    Walks through reroute nodes and muted nodes (a muted node passes one of its
    inputs through, as listed in `node.internal_links`), and ignores muted or
    invalid links, as Blender does when it compiles a shader.
    """
    socket = input_socket
    for _ in range(_MAX_HOPS):
        if not socket.is_linked:
            return None
        link = socket.links[0]
        if link.is_muted or not link.is_valid:
            return None
        node = link.from_node
        if node.bl_idname == 'NodeReroute':
            socket = node.inputs[0]
        elif node.mute:
            socket = _passed_through(node, link.from_socket)
            if socket is None:
                return None
        else:
            return link.from_socket
    return None


def _passed_through(node, output_socket):
    for internal in node.internal_links:
        if internal.to_socket == output_socket:
            return internal.from_socket
    return None


def output_node(node_tree):
    """The active output node Cycles would use (target ALL or CYCLES), or None."""
    if node_tree is None:
        return None
    return node_tree.get_output_node('CYCLES')


def linked_inputs(node, skip_types=('SHADER',)):
    """Names of the inputs of `node` that have a (live) link, except shader inputs."""
    return [s.name for s in node.inputs
            if s.enabled and s.type not in skip_types and linked_output(s) is not None]
