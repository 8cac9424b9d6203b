#include "integrators/photon_plane_set.h"

#include <algorithm>

#include "core/stratified.h"
#include "scene/embree_ray.h"
#include "scene/medium.h"

namespace smis {

Chord chord_through(float x, float y, float width, float height, float c, float s, float inv_c, float inv_s) {
    Chord ch{-kInf, kInf};
    auto slab = [&](float p, float d, float inv_d, float size) {
        if (d == 0.0f) return;  // parallel to this pair of edges: p is between them already
        float t1 = -p * inv_d, t2 = (size - p) * inv_d;
        ch.t_lo = std::max(ch.t_lo, std::min(t1, t2));
        ch.t_hi = std::min(ch.t_hi, std::max(t1, t2));
    };
    slab(x, c, inv_c, width);
    slab(y, s, inv_s, height);
    if (!(ch.t_hi > ch.t_lo)) ch.t_hi = ch.t_lo = 0.0f;
    return ch;
}

Chord chord_through(float x, float y, float width, float height, float c, float s) {
    return chord_through(x, y, width, height, c, s, c != 0.0f ? 1.0f / c : 0.0f, s != 0.0f ? 1.0f / s : 0.0f);
}

float PlaneSequence::light_u(uint32_t i) {
    return stratified_ ? stratified::sample_1d(i, key_, 0) : rng_.next_float();
}

PlaneUniforms PlaneSequence::plane(uint32_t light, uint32_t j, bool point_light) {
    PlaneUniforms u{};
    if (stratified_) {
        // Dimension groups of light `light`: 1 + 3 light, 2 + 3 light, 3 + 3 light.
        const uint32_t g = 1 + 3 * light;
        float v[2];
        stratified::sample_2d(j, key_, g, v);
        u.point = {v[0], v[1]};
        stratified::sample_2d(j, key_, g + 1, v);
        u.dir = {v[0], v[1]};
        stratified::sample_2d(j, key_, g + 2, v);
        u.alpha = v[0];
        u.flight = v[1];
        return u;
    }
    // The order the planes drew their numbers in before the stratified sets (images unchanged).
    u.point.x = rng_.next_float();
    u.point.y = rng_.next_float();
    if (!point_light) {
        u.alpha = rng_.next_float();
        u.dir.x = rng_.next_float();
        u.dir.y = rng_.next_float();
    }
    u.flight = rng_.next_float();
    return u;
}

PhotonPlane sample_photon_plane(const PlaneLight& l, uint32_t light_index, const PlaneUniforms& u) {
    // Fig. 10b: a uniform point on the light, an orientation alpha ~ U[0, pi) and the chord through
    // the point at that angle; the offset of the chord then has density |s| / A given alpha (eq. 25).
    float x = u.point.x * l.width, y = u.point.y * l.height;
    float alpha = kPi * u.alpha;
    float c = std::cos(alpha), s = std::sin(alpha);
    Chord ch = chord_through(x, y, l.width, l.height, c, s);
    PhotonPlane p;
    p.alpha = alpha;
    p.cos_alpha = c;
    p.sin_alpha = s;
    p.inv_cos_alpha = c != 0.0f ? 1.0f / c : 0.0f;
    p.inv_sin_alpha = s != 0.0f ? 1.0f / s : 0.0f;
    p.x1 = x + ch.t_lo * c;
    p.y1 = y + ch.t_lo * s;
    p.s_hat = l.u_hat * c + l.v_hat * s;
    p.chord_length = ch.length();
    p.origin = l.corner + l.u_hat * p.x1 + l.v_hat * p.y1;
    p.edge0 = p.s_hat * p.chord_length;
    // w_l ~ cos / pi around the emitting normal; the free flight with a grey rate truncates the
    // sweep, standing in for the light-side transmittance (the integrator corrects the colour).
    p.w_l = Frame(l.normal).to_world(sample_cosine_hemisphere(u.dir));
    p.sweep_length = std::min(sample_free_flight(l.flight_rate, u.flight), l.max_length);
    p.edge1 = p.w_l * p.sweep_length;
    p.light = light_index;
    return p;
}

PhotonPlane sample_point_photon_plane(const PlaneLight& l, uint32_t light_index, const PlaneUniforms& uniforms) {
    // Every photon path y -> x from a point light y lies in the planes through y that contain x - y;
    // a uniform normal gives the crossing of a camera ray a closed-form density (photon_planes.cpp).
    const Point2 u = uniforms.point;
    PhotonPlane p{};
    p.light = light_index;
    if (l.normal_band < 1.0f) {
        // A spot: the normal uniform on the band |n . axis| <= sin(half angle) = normal_band
        // (Archimedes: uniform in the axial coordinate), the planes that cut the cone. A plane
        // through the apex with n . axis = c cuts the cone in a wedge around the axis' projection
        // w, of half angle phi with cos phi = cos(half angle) / sqrt(1 - c^2); the quad is the
        // rectangle around that wedge's part of the disk, [0, reach] along w and
        // +-reach sin(phi) across. Crossings outside the wedge have zero falloff anyway.
        const float c = l.normal_band * (2.0f * u.x - 1.0f), ring = std::sqrt(std::max(0.0f, 1.0f - c * c));
        const float phi = 2.0f * kPi * u.y;
        const Frame axis(l.emitter.axis);
        const Vec3 n = axis.to_world(Vec3(ring * std::cos(phi), ring * std::sin(phi), c));
        p.w_l = normalize(l.emitter.axis - n * c);
        p.s_hat = cross(n, p.w_l);
        const float cos_wedge = std::min(1.0f, l.emitter.cos_half / std::max(ring, 1e-12f));
        const float sin_wedge = std::sqrt(std::max(0.0f, 1.0f - cos_wedge * cos_wedge));
        p.reach = std::min(sample_free_flight(l.flight_rate, uniforms.flight), l.max_length);
        p.chord_length = 2.0f * p.reach * std::max(sin_wedge, 1e-6f);
        p.sweep_length = p.reach;
        p.origin = l.emitter.position - p.s_hat * (0.5f * p.chord_length);
    } else {
        Frame f(sample_uniform_sphere(u));
        p.s_hat = f.s;
        p.w_l = f.t;
        p.reach = std::min(sample_free_flight(l.flight_rate, uniforms.flight), l.max_length);
        p.chord_length = p.sweep_length = 2.0f * p.reach;
        p.origin = l.emitter.position - (p.s_hat + p.w_l) * p.reach;
    }
    p.edge0 = p.s_hat * p.chord_length;
    p.edge1 = p.w_l * p.sweep_length;
    return p;
}

namespace {

// RTCIntersectContext extended with the hit list (Embree passes the context through unchanged).
struct GatherContext {
    RTCIntersectContext base;
    const std::vector<PhotonPlane>* planes;
    std::vector<PlaneHit>* hits;
    uint64_t* parallel;
    float tmin, tmax;  // the segment (the ray's tfar holds the candidate's distance inside a filter)
};

}  // namespace

// Each plane is a parallelogram: one Embree quad (origin, + edge0, + edge0 + edge1, + edge1), so the
// BVH's leaves test planes with Embree's SIMD quad intersector and only actual crossings reach the
// filter below (a user-geometry callback ran for every plane in every leaf the ray visited).
PhotonPlaneSet::PhotonPlaneSet(RTCDevice device, std::vector<PhotonPlane> planes) : planes_(std::move(planes)) {
    scene_ = rtcNewScene(device);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_QUAD);
    const size_t n = planes_.size();
    auto* vertices = static_cast<float*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 4 * n));
    auto* quads = static_cast<uint32_t*>(
        rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4, 4 * sizeof(uint32_t), n));
    for (size_t i = 0; i < n; ++i) {
        const PhotonPlane& p = planes_[i];
        const Vec3 corners[4] = {p.origin, p.origin + p.edge0, p.origin + p.edge0 + p.edge1, p.origin + p.edge1};
        for (int c = 0; c < 4; ++c) {
            vertices[12 * i + 3 * c + 0] = corners[c].x;
            vertices[12 * i + 3 * c + 1] = corners[c].y;
            vertices[12 * i + 3 * c + 2] = corners[c].z;
            quads[4 * i + c] = uint32_t(4 * i + c);
        }
    }
    rtcSetGeometryIntersectFilterFunction(geom, &PhotonPlaneSet::record_crossing);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
}

PhotonPlaneSet::~PhotonPlaneSet() {
    if (scene_) rtcReleaseScene(scene_);
}

// Embree found the ray crossing a plane's quad: the crossing is recomputed from the plane itself
// (so its t, a, b and the parallel test do not depend on the intersector), recorded, and rejected,
// so that traversal goes on to every other plane.
void PhotonPlaneSet::record_crossing(const RTCFilterFunctionNArguments* args) {
    auto* ctx = reinterpret_cast<GatherContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        args->valid[i] = 0;
        const unsigned prim = RTCHitN_primID(args->hit, args->N, i);
        const PhotonPlane& p = (*ctx->planes)[prim];
        auto* ray = const_cast<RTCRayN*>(args->ray);
        Vec3 o(RTCRayN_org_x(ray, args->N, i), RTCRayN_org_y(ray, args->N, i), RTCRayN_org_z(ray, args->N, i));
        Vec3 d(RTCRayN_dir_x(ray, args->N, i), RTCRayN_dir_y(ray, args->N, i), RTCRayN_dir_z(ray, args->N, i));
        // o + t d = origin + a edge0 + b edge1 (Moller-Trumbore without the triangle's a + b <= 1).
        Vec3 pvec = cross(d, p.edge1);
        float det = dot(p.edge0, pvec);
        // |det| = |edge0| |edge1| |(s_hat x w_l) . d|: below this the crossing has no usable Jacobian.
        if (!(std::fabs(det) > 1e-7f * p.chord_length * p.sweep_length)) {
            ++*ctx->parallel;
            continue;
        }
        float inv = 1.0f / det;
        Vec3 tvec = o - p.origin;
        float a = dot(tvec, pvec) * inv;
        if (!(a >= 0.0f && a <= 1.0f)) continue;
        Vec3 qvec = cross(tvec, p.edge0);
        float b = dot(d, qvec) * inv;
        if (!(b >= 0.0f && b <= 1.0f)) continue;
        float t = dot(p.edge1, qvec) * inv;
        if (!(t > ctx->tmin && t < ctx->tmax)) continue;
        ctx->hits->push_back({prim, t, a, b});
    }
}

void PhotonPlaneSet::gather(const Ray& ray, std::vector<PlaneHit>* hits, uint64_t* parallel) const {
    hits->clear();
    GatherContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.planes = &planes_;
    ctx.hits = hits;
    ctx.parallel = parallel;
    ctx.tmin = ray.tmin;
    ctx.tmax = ray.tmax;
    RTCRayHit rh = embree_ray_hit(ray);
    rtcIntersect1(scene_, &ctx.base, &rh);
    // A crossing on a quad's diagonal can be reported by both of its triangles: keep each plane once.
    std::sort(hits->begin(), hits->end(), [](const PlaneHit& x, const PlaneHit& y) { return x.plane < y.plane; });
    hits->erase(std::unique(hits->begin(), hits->end(),
                            [](const PlaneHit& x, const PlaneHit& y) { return x.plane == y.plane; }),
                hits->end());
}

}  // namespace smis
