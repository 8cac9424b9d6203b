// Cell-based procedural textures as Cycles 3.4 evaluates them: the Voronoi Texture node (F1, F2,
// Smooth F1, Distance to Edge, N-Sphere Radius in 1-4 dimensions) and the Brick Texture node.
// Pure functions of the node's inputs; the caller applies the node's texture mapping first.
#pragma once

#include "core/math.h"

namespace smis::shading {

enum class VoronoiFeature { F1, F2, SmoothF1, DistanceToEdge, NSphereRadius };
enum class VoronoiMetric { Euclidean, Manhattan, Chebychev, Minkowski };

// The node's output sockets. Position is in input space (divided by Scale again); for 1D it stays
// zero and W carries the point, for 2D its z is zero, for 4D W carries the fourth coordinate.
// Color and Position stay zero for Distance to Edge and N-Sphere Radius, Radius is only set by
// N-Sphere Radius.
struct VoronoiOut {
    float distance = 0.0f;
    Color color{0.0f};
    Vec3 position{0.0f};
    float w = 0.0f;
    float radius = 0.0f;
};

// dimensions 1-4 (1D reads w; 2D co.x, co.y; 3D co; 4D co and w). smoothness and randomness are the
// raw socket values (clamped inside as Cycles does); exponent only matters for Minkowski. 1D always
// measures |a - b| whatever the metric, and Distance to Edge / N-Sphere Radius are always Euclidean.
VoronoiOut voronoi_texture(int dimensions, VoronoiFeature feature, VoronoiMetric metric,
                           const Vec3& co, float w, float scale, float smoothness, float exponent,
                           float randomness);

struct BrickOut {
    float fac = 0.0f;  // mortar amount: 1 in the mortar, 0 inside a brick
    Color color{0.0f};
};

// offset / squash are the node's Offset and Squash properties with their frequencies. Blender keeps
// the frequencies in 1..99; the kernel (and this function) skips both when either one is 0.
BrickOut brick_texture(const Vec3& co, const Color& color1, const Color& color2, const Color& mortar,
                       float scale, float mortar_size, float mortar_smooth, float bias,
                       float brick_width, float row_height, float offset, int offset_frequency,
                       float squash, int squash_frequency);

}  // namespace smis::shading
