#include "scene/mesh_attributes.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/math.h"
#include "shading/lookup3.h"

namespace smis {
namespace {

Vec3 vertex(const float* v, size_t i) { return Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]); }

void check_edges(const int32_t* edges, size_t ne, size_t nv) {
    for (size_t k = 0; k < 2 * ne; ++k)
        if (edges[k] < 0 || size_t(edges[k]) >= nv) throw std::invalid_argument("mesh edge refers to a missing vertex");
}

// Each vertex's representative among the vertices at its position: Cycles sorts by coordinate sum
// (ties: higher index first) and points each vertex at the next one within FLT_EPSILON, then follows
// the chain, so exact duplicates end at their lowest index.
std::vector<int32_t> welded_vertices(const float* positions, size_t nv) {
    std::vector<int32_t> order(nv);
    std::iota(order.begin(), order.end(), 0);
    auto sum = [&](int32_t i) { return positions[3 * i] + positions[3 * i + 1] + positions[3 * i + 2]; };
    std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
        const Vec3 va = vertex(positions, a), vb = vertex(positions, b);
        if (va.x == vb.x && va.y == vb.y && va.z == vb.z) return a > b;
        return sum(a) < sum(b);
    });
    constexpr float kEps = 1.1920929e-7f;  // FLT_EPSILON
    std::vector<int32_t> orig(nv);
    for (size_t s = 0; s < nv; ++s) {
        const int32_t v = order[s];
        orig[v] = v;
        const Vec3 p = vertex(positions, v);
        for (size_t t = s + 1; t < nv; ++t) {
            const int32_t w = order[t];
            if (sum(w) - sum(v) > 3.0f * kEps) break;
            if (length_sq(vertex(positions, w) - p) < kEps) {
                orig[v] = w;
                break;
            }
        }
    }
    for (size_t v = 0; v < nv; ++v) {
        int32_t o = orig[v];
        while (o != orig[o]) o = orig[o];
        orig[v] = o;
    }
    return orig;
}

// The edges between welded vertices, each unordered pair once, in Blender's edge order.
std::vector<std::pair<int32_t, int32_t>> welded_edges(const int32_t* edges, size_t ne, const std::vector<int32_t>& orig) {
    std::vector<std::pair<int32_t, int32_t>> out;
    std::set<std::pair<int32_t, int32_t>> seen;
    for (size_t e = 0; e < ne; ++e) {
        const int32_t v0 = orig[edges[2 * e]], v1 = orig[edges[2 * e + 1]];
        // An edge between two welded copies has no direction (Cycles would add a NaN here).
        if (v0 == v1 || !seen.insert({std::min(v0, v1), std::max(v0, v1)}).second) continue;
        out.push_back({v0, v1});
    }
    return out;
}

}  // namespace

std::vector<float> mesh_pointiness(const float* positions, const float* normals, size_t nv, const int32_t* edges,
                                   size_t ne) {
    check_edges(edges, ne, nv);
    const std::vector<int32_t> orig = welded_vertices(positions, nv);
    std::vector<Vec3> normal(nv, Vec3(0.0f));
    for (size_t v = 0; v < nv; ++v) normal[orig[v]] += vertex(normals, v);
    const auto welded = welded_edges(edges, ne, orig);
    // One ring: the angle between the normal and the mean edge direction, over pi.
    std::vector<Vec3> accum(nv, Vec3(0.0f));
    std::vector<int> count(nv, 0);
    for (const auto& [v0, v1] : welded) {
        const Vec3 d = normalize(vertex(positions, v1) - vertex(positions, v0));
        accum[v0] += d;
        accum[v1] -= d;
        ++count[v0], ++count[v1];
    }
    std::vector<float> raw(nv, 0.0f);
    for (size_t v = 0; v < nv; ++v) {
        if (orig[v] != int32_t(v) || count[v] == 0) continue;
        const float c = dot(normalize(normal[v]), accum[v] / float(count[v]));
        raw[v] = std::acos(clampf(c, -1.0f, 1.0f)) * (1.0f / kPi);
    }
    // Blurred over the neighbours (the two-ring neighbourhood), then copied to the welded copies.
    std::vector<float> data = raw;
    std::fill(count.begin(), count.end(), 0);
    for (const auto& [v0, v1] : welded) {
        data[v0] += raw[v1];
        data[v1] += raw[v0];
        ++count[v0], ++count[v1];
    }
    for (size_t v = 0; v < nv; ++v) data[v] /= float(count[v] + 1);
    for (size_t v = 0; v < nv; ++v) data[v] = data[orig[v]];
    return data;
}

std::vector<float> mesh_random_per_island(size_t nv, const int32_t* edges, size_t ne, const int32_t* triangle_vertex0,
                                          size_t nt) {
    check_edges(edges, ne, nv);
    std::vector<uint32_t> parent(nv), rank(nv, 0);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        uint32_t root = x;
        while (parent[root] != root) root = parent[root];
        while (parent[x] != root) {
            const uint32_t next = parent[x];
            parent[x] = root;
            x = next;
        }
        return root;
    };
    for (size_t e = 0; e < ne; ++e) {
        uint32_t x = find(uint32_t(edges[2 * e])), y = find(uint32_t(edges[2 * e + 1]));
        if (x == y) continue;
        if (rank[x] < rank[y]) std::swap(x, y);
        parent[y] = x;
        if (rank[x] == rank[y]) ++rank[x];
    }
    std::vector<float> out(nt);
    for (size_t t = 0; t < nt; ++t) {
        const int32_t v = triangle_vertex0[t];
        if (v < 0 || size_t(v) >= nv) throw std::invalid_argument("triangle refers to a missing vertex");
        // Cycles' hash_uint_to_float: the hash converted to float, then divided in float.
        out[t] = float(shading::lookup3::hash1(find(uint32_t(v)))) / float(0xFFFFFFFFu);
    }
    return out;
}

}  // namespace smis
