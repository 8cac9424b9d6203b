// Per-mesh attributes Cycles derives from the mesh itself when a shader reads them (Geometry >
// Pointiness and Random Per Island), computed the same way at export, from Blender's vertices,
// vertex normals and edges in Blender's order.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace smis {

// Pointiness per vertex in [0, 1] (0.5 on flat regions, above on convex edges and corners):
// vertices at the same position are welded, the angle between the welded vertex normal and the
// mean direction of its edges (over pi) is averaged with its neighbours' (a two-ring blur).
// positions, normals: nv x 3; edges: ne x 2 vertex indices.
std::vector<float> mesh_pointiness(const float* positions, const float* normals, size_t nv, const int32_t* edges,
                                   size_t ne);

// Random Per Island per triangle: the connected components of the edge graph (union by rank in
// edge order, as Cycles' DisjointSet), each triangle the hash of its first vertex's component root.
std::vector<float> mesh_random_per_island(size_t nv, const int32_t* edges, size_t ne, const int32_t* triangle_vertex0,
                                          size_t nt);

}  // namespace smis
