// Photon planes (Deng et al. 2019; West et al. 2020, §6.1, Fig. 10): one iteration's set of planes
// swept from rectangular area lights, and the query that returns every plane a camera ray crosses.
// A plane is a chord s of the light at angle alpha through a uniformly sampled light point, swept
// along a cosine-sampled direction w_l for a free-flight length. The planes live in an Embree scene
// of user primitives whose intersection callback records each crossing and never reports a hit, so
// one traversal visits exactly the planes whose bounds the ray passes (not pixels x planes).
#pragma once
#include <embree3/rtcore.h>

#include <vector>

#include "core/rng.h"
#include "scene/scene.h"

namespace smis {

// A rectangular light as the planes use it: an orthonormal frame in its plane and the medium
// the planes start in. 2D light coordinates are metres along (u_hat, v_hat) from the corner.
// Or a point or spot light without radius (`point`): then only `emitter`, the flight rate and the
// reach are used.
struct PlaneLight {
    uint32_t light;        // index into Scene::lights()
    bool point = false;
    LightPoint emitter;
    Vec3 corner, u_hat, v_hat, normal;
    float width, height;   // |u|, |v|
    Color radiance;
    float area;
    // Point lights: the fraction of the sphere of plane normals drawn. A spot light's planes have
    // normals in the band |n . axis| <= sin(half angle) only, the planes that cut its cone.
    float normal_band = 1.0f;
    float flight_rate;     // free-flight rate: min channel of sigma_t in the light's medium
    float max_length;      // planes never need to reach further than the scene's bounds
};

// The chord through 2D point (x, y) of a width x height rectangle in direction (c, s): the part of
// the line inside the rectangle is p + t (c, s) for t in [t_lo, t_hi].
struct Chord {
    float t_lo = 0.0f, t_hi = 0.0f;
    float length() const { return t_hi - t_lo; }
};
Chord chord_through(float x, float y, float width, float height, float c, float s);
// The same with 1/c and 1/s given (any value where c or s is 0): no division.
Chord chord_through(float x, float y, float width, float height, float c, float s, float inv_c, float inv_s);

struct PhotonPlane {
    Vec3 origin;           // chord start p1 (3D)
    Vec3 edge0, edge1;     // chord vector (length |s|) and w_l * sweep length
    Vec3 s_hat, w_l;       // unit chord direction and sweep direction
    float x1, y1;          // chord start in 2D light coordinates
    float alpha;           // orientation in [0, pi): s_hat = cos(alpha) u_hat + sin(alpha) v_hat
    float cos_alpha, sin_alpha, inv_cos_alpha, inv_sin_alpha;
    float chord_length, sweep_length;
    uint32_t light;        // index into the PlaneLight table
    // A point light's plane is the disk of radius `reach` around the light in the plane spanned by
    // s_hat and w_l (its quad: the square around that disk, or for a spot the rectangle around the
    // disk's wedge inside the cone); unused for rectangles.
    float reach = 0.0f;
};

struct PlaneHit {
    uint32_t plane;
    float t;       // along the camera ray
    float a, b;    // position on the plane: y = origin + a edge0 (the light point), x - y = b edge1
};

class PhotonPlaneSet {
public:
    PhotonPlaneSet(RTCDevice device, std::vector<PhotonPlane> planes);
    ~PhotonPlaneSet();
    PhotonPlaneSet(const PhotonPlaneSet&) = delete;
    PhotonPlaneSet& operator=(const PhotonPlaneSet&) = delete;

    // Every plane crossed by the ray within (tmin, tmax), sorted by plane index (a fixed order, so
    // sums over them do not depend on the BVH). `hits` is cleared first. Crossings nearly parallel
    // to the plane (no finite Jacobian in float) are skipped and counted in *parallel.
    void gather(const Ray& ray, std::vector<PlaneHit>* hits, uint64_t* parallel) const;
    const PhotonPlane& plane(uint32_t i) const { return planes_[i]; }
    size_t size() const { return planes_.size(); }

private:
    static void record_crossing(const RTCFilterFunctionNArguments* args);

    std::vector<PhotonPlane> planes_;
    RTCScene scene_ = nullptr;
};

// The random numbers of one plane, each uniform on [0, 1).
struct PlaneUniforms {
    Point2 point;   // rectangle: the light point; point light: the plane's normal
    Point2 dir;     // rectangle: the sweep direction w_l; unused for point lights
    float alpha;    // rectangle: the chord's orientation
    float flight;   // the free flight that truncates the sweep
};

// The random numbers of a plane set, stratified over the set (`stratified`) or independent. Plane
// i chooses its light with light_u(i) (van der Corput, Owen-scrambled: the planes of each light
// number N pmf to within one); the j-th plane of light l takes point j of padded, Owen-scrambled 2D
// Sobol sequences of its own (core/stratified.h) for its light point, its sweep direction and its
// (orientation, flight). Every plane alone is still distributed as with independent numbers (each
// scrambled point is uniform), so the planes' sum, linear in each plane, keeps its expectation:
// the estimator stays unbiased. What changes is that the planes of one set cover the light, the
// directions and the normals evenly, so the number of planes a camera ray crosses (Poisson-like
// with independent planes, the grain of the image) varies much less.
class PlaneSequence {
public:
    // `seed`, `iteration`: the set's own stream (independent of the pixels' streams).
    PlaneSequence(uint64_t seed, uint32_t iteration, bool stratified)
        : key_(mix64(seed ^ mix64(iteration))), stratified_(stratified), rng_(seed, iteration) {}
    // Call light_u(i), then plane() for plane i, in the order of i (the independent numbers are
    // one stream, drawn in that order).
    float light_u(uint32_t i);
    PlaneUniforms plane(uint32_t light, uint32_t j, bool point_light);

private:
    uint64_t key_;
    bool stratified_;
    Rng rng_;  // the independent numbers (stratified_ false)
};

// One plane from light `l` (chosen with probability `pmf` by the caller).
PhotonPlane sample_photon_plane(const PlaneLight& l, uint32_t light_index, const PlaneUniforms& u);
// One plane from a point light: a plane through the light with a uniformly distributed normal,
// covering the disk of a free flight's radius around it.
PhotonPlane sample_point_photon_plane(const PlaneLight& l, uint32_t light_index, const PlaneUniforms& u);

}  // namespace smis
