"""Blender mesh -> numpy buffers for `_smis.Scene.add_mesh`.

Everything goes through `foreach_get` into preallocated numpy arrays: a Python
loop over the triangles of a 4 M triangle mesh costs seconds, `foreach_get`
a fraction of that, and no pointer into Blender's memory is kept.
"""

from dataclasses import dataclass
from typing import Optional

import numpy as np

from .. import native


@dataclass
class MeshBuffers:
    vertices: np.ndarray                   # (N, 3) float32, object space
    triangles: np.ndarray                  # (M, 3) int32, indices into vertices
    corner_normals: Optional[np.ndarray]   # (M, 3, 3) float32, or None: flat shading
    material_index: Optional[np.ndarray]   # (M,) int32 slot per triangle, or None: slot 0
    corner_uvs: Optional[np.ndarray] = None  # (M, 3, 2) float32, only for textured materials
    # Named per-corner attributes for shader programs (UV maps by name, colour attributes):
    # {name: (M, 3, k) float32}; ACTIVE_COLOR names the active render colour attribute.
    attributes: Optional[dict] = None
    texspace: Optional[tuple] = None          # (location, size) of Blender's texture space

    @property
    def triangle_count(self):
        return len(self.triangles)


def _needs_corner_normals(mesh):
    """True unless every face is flat shaded without custom normals.

    For an all-flat mesh the split normals are the polygon normals, which the
    engine's geometric normal replaces exactly (as Cycles does), so we skip
    `calc_normals_split` and 36 bytes per triangle.
    """
    if mesh.has_custom_normals:
        return True
    n = len(mesh.polygons)
    if n == 0:
        return False
    smooth = np.empty(n, dtype=bool)
    mesh.polygons.foreach_get("use_smooth", smooth)
    return bool(smooth.any())


def _corner_uvs(mesh, loops, uv_map):
    """UVs of every triangle corner (`loops`: the corners' loop indices) from the named UV map
    ('' = the active render map), or None when the mesh has no such map."""
    layers = mesh.uv_layers
    layer = layers.get(uv_map) if uv_map else None
    if layer is None:
        layer = next((l for l in layers if l.active_render), None)
    if layer is None:
        return None
    uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
    layer.data.foreach_get("uv", uv)
    return uv.reshape(-1, 2)[loops].reshape(-1, 3, 2)


ACTIVE_COLOR = "\x00active color"
# Attributes derived from the mesh on request, as Cycles derives them when a shader reads them:
# TANGENT_PREFIX + UV map name ('' = the active render map): per corner the MikkTSpace tangent (object
# space) and the bitangent sign; POINTINESS per vertex; RANDOM_PER_ISLAND per triangle.
TANGENT_PREFIX = "\x00tangent:"
POINTINESS = "\x00pointiness"
RANDOM_PER_ISLAND = "\x00random per island"


def _corner_tangents(mesh, loops, uv_maps, warn, object_name):
    """{TANGENT_PREFIX + name: (M, 3, 4)} for each UV map in `uv_maps` the mesh has. Blender's
    calc_tangents is MikkTSpace, Cycles' tangent space; it refuses n-gons (Cycles triangulates
    them first): such meshes get none and normal maps fall back to per-triangle tangents."""
    out = {}
    for name in uv_maps:
        layer = mesh.uv_layers.get(name) if name else next((l for l in mesh.uv_layers if l.active_render), None)
        if layer is None:
            continue
        try:
            with native.load().SerialTbb():
                mesh.calc_tangents(uvmap=layer.name)
        except RuntimeError:
            if warn is not None:
                warn("Object '%s' has faces with more than four corners; its normal maps use "
                     "per-triangle tangents instead of MikkTSpace (triangulate it to match Cycles)" % object_name)
            continue
        n = len(mesh.loops)
        tangent = np.empty(n * 3, dtype=np.float32)
        sign = np.empty(n, dtype=np.float32)
        mesh.loops.foreach_get("tangent", tangent)
        mesh.loops.foreach_get("bitangent_sign", sign)
        corner = np.concatenate([tangent.reshape(n, 3), sign[:, None]], axis=1)[loops]
        out[TANGENT_PREFIX + name] = np.ascontiguousarray(corner.reshape(-1, 3, 4))
    return out


def _derived_attributes(mesh, vertices, loops, verts, names, warn, object_name):
    """{name: (M, 3, k)} for the derived attributes in `names` (see TANGENT_PREFIX); `vertices`:
    the positions, `loops` and `verts`: each triangle corner's loop and vertex index."""
    out = _corner_tangents(mesh, loops, [n[len(TANGENT_PREFIX):] for n in names if n.startswith(TANGENT_PREFIX)],
                           warn, object_name)
    if POINTINESS not in names and RANDOM_PER_ISLAND not in names:
        return out
    smis = native.load()
    edges = np.empty(len(mesh.edges) * 2, dtype=np.int32)
    mesh.edges.foreach_get("vertices", edges)
    if POINTINESS in names:
        normal = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("normal", normal)
        per_vertex = smis.mesh_pointiness(vertices, normal, edges)
        out[POINTINESS] = np.ascontiguousarray(per_vertex[verts].reshape(-1, 3, 1))
    if RANDOM_PER_ISLAND in names:
        per_triangle = smis.mesh_random_per_island(len(mesh.vertices), edges, verts[0::3].copy())
        out[RANDOM_PER_ISLAND] = np.ascontiguousarray(np.repeat(per_triangle, 3).reshape(-1, 3, 1))
    return out


def _corner_attributes(mesh, loops, verts):
    """Every UV map (by name) and colour attribute (by name, and the active render one as
    ACTIVE_COLOR) at every triangle corner (`loops`, `verts`: its loop and vertex indices), for
    shader programs that read them by name."""
    out = {}
    for layer in mesh.uv_layers:
        uv = np.empty(len(mesh.loops) * 2, dtype=np.float32)
        layer.data.foreach_get("uv", uv)
        out[layer.name] = uv.reshape(-1, 2)[loops].reshape(-1, 3, 2)
    colors = getattr(mesh, "color_attributes", None)
    if colors is not None:
        active = colors.render_color_index if hasattr(colors, "render_color_index") else -1
        for i, attr in enumerate(colors):
            n = len(attr.data)
            data = np.empty(n * 4, dtype=np.float32)
            attr.data.foreach_get("color", data)  # scene-linear, as Cycles reads them
            data = data.reshape(n, 4)
            if attr.domain == 'CORNER':
                corner = data[loops]
            elif attr.domain == 'POINT':
                corner = data[verts]
            else:
                continue
            arr = np.ascontiguousarray(corner.reshape(-1, 3, 4))
            out[attr.name] = arr
            if i == active or (active < 0 and i == 0):
                out[ACTIVE_COLOR] = arr
    return out


def mesh_buffers(mesh, slot_count, uv_map=None, derived=(), warn=None, object_name=""):
    """Triangulated buffers of a (temporary, evaluated) mesh.

    `slot_count` is the number of material slots the triangles' material
    indices refer to; out-of-range indices are clamped as Blender does.
    `uv_map`: the UV map textured materials read ('' = active render map), None
    when no material needs UVs (then none are exported). `derived`: the attributes derived from
    the mesh that materials read (TANGENT_PREFIX + UV map, POINTINESS, RANDOM_PER_ISLAND); `warn`
    reports meshes whose tangents cannot be computed.
    """
    mesh.calc_loop_triangles()
    tris = mesh.loop_triangles
    n_verts, n_tris = len(mesh.vertices), len(tris)

    vertices = np.empty(n_verts * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", vertices)
    triangles = np.empty(n_tris * 3, dtype=np.int32)
    tris.foreach_get("vertices", triangles)

    corner_normals = None
    if n_tris and _needs_corner_normals(mesh):
        # Blender sums normals in parallel in a varying order; one thread makes them reproducible.
        with native.load().SerialTbb():
            mesh.calc_normals_split()
        corner_normals = np.empty(n_tris * 9, dtype=np.float32)
        tris.foreach_get("split_normals", corner_normals)
        corner_normals = corner_normals.reshape(n_tris, 3, 3)

    material_index = None
    if slot_count > 1 and n_tris:
        material_index = np.empty(n_tris, dtype=np.int32)
        tris.foreach_get("material_index", material_index)
        np.clip(material_index, 0, slot_count - 1, out=material_index)

    corner_uvs = attributes = None
    if n_tris and (uv_map is not None or derived):
        loops = np.empty(n_tris * 3, dtype=np.int32)  # each corner's loop, read once for every attribute
        tris.foreach_get("loops", loops)
        if uv_map is not None:
            corner_uvs = _corner_uvs(mesh, loops, uv_map)
            attributes = _corner_attributes(mesh, loops, triangles)
        if derived:
            attributes = dict(attributes or {},
                              **_derived_attributes(mesh, vertices, loops, triangles, derived, warn, object_name))
    texspace = None
    if hasattr(mesh, "texspace_location"):
        texspace = (tuple(mesh.texspace_location), tuple(mesh.texspace_size))

    return MeshBuffers(vertices.reshape(n_verts, 3), triangles.reshape(n_tris, 3),
                       corner_normals, material_index, corner_uvs, attributes, texspace)
