// The Image Texture node's projections (Cycles 3.4, svm/image.h): how the node turns its Vector input
// into the UV it looks the image up at. Flat uses (x, y); Sphere and Tube first map the vector from the
// [0, 1] box to [-1, 1] (centre 0.5) and then wrap it around the z axis; Box blends up to three flat
// lookups, one per axis, by the object-space normal.
#pragma once

#include "core/math.h"
#include "core/sampling.h"

namespace smis::shading {

Point2 project_flat(const Vec3& co);
// u: angle around z (0 towards -y, 0.25 towards +x, 0.5 towards +y: counter-clockwise seen from +z),
// v: polar angle from -z (0) to +z (1). The centre itself and points on the z axis get u = 0.
Point2 project_sphere(const Vec3& co);
// u as for the sphere, v: height z from -1 to 1 (after the remap: co.z from 0 to 1).
Point2 project_tube(const Vec3& co);

// Box projection: weight and UV of the X, Y and Z faces. The node's result is the sum over the faces
// with w[i] > 0 of w[i] x the image (Color and Alpha) at uv[i]; the weights sum to 1 (none are
// positive for a degenerate normal with blend > 0, where Cycles outputs black). n: the shading normal
// in object space (need not be normalised); blend: the node's Blend in [0, 1], the width of the
// transition between faces (0: hard edges).
struct BoxWeights {
    float w[3] = {0.0f, 0.0f, 0.0f};
    Point2 uv[3];
};
BoxWeights project_box(const Vec3& co, const Vec3& n, float blend);

}  // namespace smis::shading
