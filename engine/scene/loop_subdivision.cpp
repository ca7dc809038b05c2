// Loop subdivision (Loop 1987, "Smooth subdivision surfaces based on triangles"), our code.
// Each level builds the edge table of the current mesh (the vertices opposite each edge), then
// the new vertices: every old vertex moved by its neighbours (the even rule), one new vertex
// per edge (the odd rule); every triangle becomes four. Boundaries follow the boundary curve's
// own cubic B-spline, so an open mesh keeps its rim.
#include <cmath>
#include <unordered_map>

#include <stdexcept>
#include "mesh_shapes.h"

namespace foton {

namespace {

struct Edge {
    uint32_t opposite[2] = {0, 0};
    int faces = 0;
    uint32_t midpoint = 0;  // the index of its new vertex
};

uint64_t edge_key(uint32_t a, uint32_t b) {
    return a < b ? (uint64_t(a) << 32 | b) : (uint64_t(b) << 32 | a);
}

// Loop's weight of each neighbour of an interior vertex of valence n (Warren's 3/16 at 3).
float loop_beta(int n) {
    return n == 3 ? 3.f / 16.f : 3.f / (8.f * float(n));
}

struct Neighbourhood {
    std::vector<Vec3> sum, boundary_sum;
    std::vector<int> valence, boundary_count;
};

std::unordered_map<uint64_t, Edge> edge_table(const TriangleMesh& m) {
    std::unordered_map<uint64_t, Edge> edges;
    edges.reserve(m.indices.size());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = m.indices[3 * t + std::size_t(k)];
            const uint32_t b = m.indices[3 * t + std::size_t((k + 1) % 3)];
            const uint32_t c = m.indices[3 * t + std::size_t((k + 2) % 3)];
            if (a == b || b == c || a == c)
                throw std::invalid_argument("triangle " + std::to_string(t) + " repeats a vertex");
            Edge& e = edges[edge_key(a, b)];
            if (e.faces == 2)
                throw std::invalid_argument("the control mesh is not manifold (an edge of " +
                                            std::to_string(t) + " has three triangles)");
            e.opposite[e.faces++] = c;
        }
    }
    return edges;
}

Neighbourhood neighbourhood(const TriangleMesh& m,
                            const std::unordered_map<uint64_t, Edge>& edges) {
    Neighbourhood n;
    const std::size_t nv = m.num_vertices();
    n.sum.assign(nv, Vec3{0, 0, 0});
    n.boundary_sum.assign(nv, Vec3{0, 0, 0});
    n.valence.assign(nv, 0);
    n.boundary_count.assign(nv, 0);
    for (const auto& [key, e] : edges) {
        const uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
        n.sum[a] += m.vertex(b);
        n.sum[b] += m.vertex(a);
        ++n.valence[a];
        ++n.valence[b];
        if (e.faces == 1) {
            n.boundary_sum[a] += m.vertex(b);
            n.boundary_sum[b] += m.vertex(a);
            ++n.boundary_count[a];
            ++n.boundary_count[b];
        }
    }
    return n;
}

// Where vertex i goes: `limit` false for one level's even rule, true for the limit position.
Vec3 moved(const TriangleMesh& m, const Neighbourhood& n, uint32_t i, bool limit) {
    const Vec3 v = m.vertex(i);
    if (n.boundary_count[i] == 2) {
        // The boundary curve's B-spline: 3/4, 1/8, 1/8 (limit 3/5, 1/5, 1/5).
        return limit ? v * 0.6f + n.boundary_sum[i] * 0.2f : v * 0.75f + n.boundary_sum[i] * 0.125f;
    }
    if (n.boundary_count[i] > 0 || n.valence[i] == 0) return v;  // a corner or a lone vertex
    const int k = n.valence[i];
    const float beta = loop_beta(k);
    const float w = limit ? 1.f / (float(k) + 3.f / (8.f * beta)) : beta;
    return v * (1.f - float(k) * w) + n.sum[i] * w;
}

TriangleMesh subdivide_once(const TriangleMesh& m) {
    std::unordered_map<uint64_t, Edge> edges = edge_table(m);
    const Neighbourhood n = neighbourhood(m, edges);
    TriangleMesh out;
    out.name = m.name;
    const std::size_t nv = m.num_vertices();
    out.positions.reserve(3 * (nv + edges.size()));
    for (uint32_t i = 0; i < nv; ++i) {
        const Vec3 p = moved(m, n, i, false);
        out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
    }
    uint32_t next = uint32_t(nv);
    for (auto& [key, e] : edges) {
        const Vec3 a = m.vertex(uint32_t(key >> 32)), b = m.vertex(uint32_t(key & 0xffffffffu));
        const Vec3 p =
            e.faces == 1
                ? (a + b) * 0.5f
                : (a + b) * 0.375f + (m.vertex(e.opposite[0]) + m.vertex(e.opposite[1])) * 0.125f;
        out.positions.insert(out.positions.end(), {p.x, p.y, p.z});
        e.midpoint = next++;
    }
    out.indices.reserve(4 * m.indices.size());
    for (std::size_t t = 0; t < m.num_triangles(); ++t) {
        const uint32_t a = m.indices[3 * t], b = m.indices[3 * t + 1], c = m.indices[3 * t + 2];
        const uint32_t ab = edges[edge_key(a, b)].midpoint, bc = edges[edge_key(b, c)].midpoint,
                       ca = edges[edge_key(c, a)].midpoint;
        out.indices.insert(out.indices.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    return out;
}

}  // namespace

TriangleMesh loop_subdivide(const TriangleMesh& control, int levels) {
    TriangleMesh m = control;
    m.normals.clear();
    m.uvs.clear();
    for (int l = 0; l < levels; ++l) m = subdivide_once(m);
    // Every vertex to its limit position.
    const Neighbourhood n = neighbourhood(m, edge_table(m));
    std::vector<float> limit(m.positions.size());
    for (uint32_t i = 0; i < m.num_vertices(); ++i) {
        const Vec3 p = moved(m, n, i, true);
        limit[3 * i] = p.x;
        limit[3 * i + 1] = p.y;
        limit[3 * i + 2] = p.z;
    }
    m.positions = std::move(limit);
    m.compute_smooth_normals();
    return m;
}

}  // namespace foton
