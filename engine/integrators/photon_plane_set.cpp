#include "integrators/photon_plane_set.h"

#include <algorithm>

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

PhotonPlane sample_photon_plane(const PlaneLight& l, uint32_t light_index, Rng& rng) {
    // Fig. 10b: a uniform point on the light, an orientation alpha ~ U[0, pi) and the chord through
    // the point at that angle; the offset of the chord then has density |s| / A given alpha (eq. 25).
    float x = rng.next_float() * l.width, y = rng.next_float() * l.height;
    float alpha = kPi * rng.next_float();
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
    Point2 u{rng.next_float(), rng.next_float()};
    p.w_l = Frame(l.normal).to_world(sample_cosine_hemisphere(u));
    p.sweep_length = std::min(sample_free_flight(l.flight_rate, rng.next_float()), l.max_length);
    p.edge1 = p.w_l * p.sweep_length;
    p.light = light_index;
    return p;
}

namespace {

// RTCIntersectContext extended with the hit list (Embree passes the context through unchanged).
struct GatherContext {
    RTCIntersectContext base;
    const std::vector<PhotonPlane>* planes;
    std::vector<PlaneHit>* hits;
    uint64_t* parallel;
};

}  // namespace

PhotonPlaneSet::PhotonPlaneSet(RTCDevice device, std::vector<PhotonPlane> planes) : planes_(std::move(planes)) {
    scene_ = rtcNewScene(device);
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(geom, static_cast<unsigned>(planes_.size()));
    rtcSetGeometryUserData(geom, &planes_);
    rtcSetGeometryBoundsFunction(geom, &PhotonPlaneSet::bounds, nullptr);
    rtcSetGeometryIntersectFunction(geom, &PhotonPlaneSet::intersect);
    rtcSetGeometryOccludedFunction(geom, &PhotonPlaneSet::occluded);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(scene_);
}

PhotonPlaneSet::~PhotonPlaneSet() {
    if (scene_) rtcReleaseScene(scene_);
}

void PhotonPlaneSet::bounds(const RTCBoundsFunctionArguments* args) {
    const auto& planes = *static_cast<const std::vector<PhotonPlane>*>(args->geometryUserPtr);
    const PhotonPlane& p = planes[args->primID];
    Vec3 lo = p.origin, hi = p.origin;
    for (const Vec3& q : {p.origin + p.edge0, p.origin + p.edge1, p.origin + p.edge0 + p.edge1}) {
        lo = vmin(lo, q);
        hi = vmax(hi, q);
    }
    RTCBounds* b = args->bounds_o;
    b->lower_x = lo.x, b->lower_y = lo.y, b->lower_z = lo.z;
    b->upper_x = hi.x, b->upper_y = hi.y, b->upper_z = hi.z;
}

void PhotonPlaneSet::intersect(const RTCIntersectFunctionNArguments* args) {
    if (args->N != 1 || !args->valid[0]) return;
    auto* ctx = reinterpret_cast<GatherContext*>(args->context);
    const PhotonPlane& p = (*ctx->planes)[args->primID];
    const RTCRay& r = reinterpret_cast<RTCRayHit*>(args->rayhit)->ray;
    Vec3 o(r.org_x, r.org_y, r.org_z), d(r.dir_x, r.dir_y, r.dir_z);
    // o + t d = origin + a edge0 + b edge1 (Moller-Trumbore without the triangle's a + b <= 1).
    Vec3 pvec = cross(d, p.edge1);
    float det = dot(p.edge0, pvec);
    // |det| = |edge0| |edge1| |(s_hat x w_l) . d|: below this the crossing has no usable Jacobian.
    if (!(std::fabs(det) > 1e-7f * p.chord_length * p.sweep_length)) {
        ++*ctx->parallel;
        return;
    }
    float inv = 1.0f / det;
    Vec3 tvec = o - p.origin;
    float a = dot(tvec, pvec) * inv;
    if (!(a >= 0.0f && a <= 1.0f)) return;
    Vec3 qvec = cross(tvec, p.edge0);
    float b = dot(d, qvec) * inv;
    if (!(b >= 0.0f && b <= 1.0f)) return;
    float t = dot(p.edge1, qvec) * inv;
    if (!(t > r.tnear && t < r.tfar)) return;
    ctx->hits->push_back({args->primID, t, a, b});
    // No hit is reported (tfar unchanged), so traversal goes on to every other plane.
}

void PhotonPlaneSet::occluded(const RTCOccludedFunctionNArguments*) {}

void PhotonPlaneSet::gather(const Ray& ray, std::vector<PlaneHit>* hits, uint64_t* parallel) const {
    hits->clear();
    GatherContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.planes = &planes_;
    ctx.hits = hits;
    ctx.parallel = parallel;
    RTCRayHit rh = embree_ray_hit(ray);
    rtcIntersect1(scene_, &ctx.base, &rh);
    // A primitive may sit in several BVH leaves: sort and keep each plane once.
    std::sort(hits->begin(), hits->end(), [](const PlaneHit& x, const PlaneHit& y) { return x.plane < y.plane; });
    hits->erase(std::unique(hits->begin(), hits->end(),
                            [](const PlaneHit& x, const PlaneHit& y) { return x.plane == y.plane; }),
                hits->end());
}

}  // namespace smis
