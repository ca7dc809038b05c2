#pragma once
// The light subpaths' vertices of one iteration, structure of arrays: what connections and
// merges read. A vertex is stored where the light path met a BSDF with a non-delta lobe
// (a connection or merge through a delta lobe has zero density). Paths are numbered; the
// vertices of path k are [first[k], first[k + 1]) in order from the light.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "engine/core/cluster.h"
#include "engine/core/math.h"
#include "engine/core/rgb.h"
#include "engine/core/sampler.h"

namespace foton {

struct LightVertices {
    std::vector<float> px, py, pz;      // position
    std::vector<Vec3> ng, ns;           // geometric and shading normal, facing the arriving ray
    std::vector<Vec3> ss;               // the shading tangent (SurfacePoint::ss; zero: none)
    std::vector<Vec3> wo;               // towards the previous vertex (where the light came from)
    std::vector<RGB> beta;              // the light subpath's throughput arriving here
    std::vector<float> adj;             // |wo.ns| / |wo.ng|: the adjoint shading-normal factor
    std::vector<float> dvcm, dvc, dvm;  // the MIS sums (vcm_mis.h)
    std::vector<uint16_t> length;       // segments from the light (1: the first hit)
    std::vector<uint8_t> front;         // the ray arrived on the geometry's front side
    std::vector<uint32_t> geom;         // what was hit: the material
    std::vector<Point2> uv;             // its texture coordinates
    std::vector<uint32_t> path;         // the light path's number within the iteration
    // kNoMedium: a surface vertex; else the medium it scattered in (a medium vertex: its phase
    // function in place of a BSDF, normals zero, adj 1, never merged at).
    std::vector<int32_t> medium;

    std::size_t size() const { return px.size(); }
    Vec3 position(std::size_t i) const { return {px[i], py[i], pz[i]}; }
    bool in_medium(std::size_t i) const { return medium[i] >= 0; }
    void clear() { resize(0); }
    void resize(std::size_t n) {
        px.resize(n), py.resize(n), pz.resize(n), ng.resize(n), ns.resize(n), ss.resize(n);
        wo.resize(n);
        beta.resize(n), adj.resize(n), dvcm.resize(n), dvc.resize(n), dvm.resize(n);
        length.resize(n), front.resize(n), geom.resize(n), uv.resize(n), path.resize(n);
        medium.resize(n);
    }
    // Copies all of `o` to positions [at, at + o.size()) (resized before).
    void copy_from(const LightVertices& o, std::size_t at) {
        auto put = [&](const auto& src, auto& dst) {
            std::copy(src.begin(), src.end(), dst.begin() + std::ptrdiff_t(at));
        };
        put(o.px, px), put(o.py, py), put(o.pz, pz), put(o.ng, ng), put(o.ns, ns), put(o.ss, ss);
        put(o.wo, wo);
        put(o.beta, beta), put(o.adj, adj), put(o.dvcm, dvcm), put(o.dvc, dvc), put(o.dvm, dvm);
        put(o.length, length), put(o.front, front), put(o.geom, geom), put(o.uv, uv);
        put(o.path, path), put(o.medium, medium);
    }
    // Replaces these vertices, on every MPI rank, by every rank's in rank order: the whole
    // iteration's when each rank traced a contiguous share of the light paths. Collective.
    void all_gather(const Cluster& c) {
        c.all_gather_concat(px), c.all_gather_concat(py), c.all_gather_concat(pz);
        c.all_gather_concat(ng), c.all_gather_concat(ns), c.all_gather_concat(ss);
        c.all_gather_concat(wo);
        c.all_gather_concat(beta), c.all_gather_concat(adj);
        c.all_gather_concat(dvcm), c.all_gather_concat(dvc), c.all_gather_concat(dvm);
        c.all_gather_concat(length), c.all_gather_concat(front), c.all_gather_concat(geom);
        c.all_gather_concat(uv), c.all_gather_concat(path), c.all_gather_concat(medium);
    }
    // Appends vertex i of `o`.
    void push(const LightVertices& o, std::size_t i) {
        px.push_back(o.px[i]), py.push_back(o.py[i]), pz.push_back(o.pz[i]);
        ng.push_back(o.ng[i]), ns.push_back(o.ns[i]), ss.push_back(o.ss[i]);
        wo.push_back(o.wo[i]);
        beta.push_back(o.beta[i]), adj.push_back(o.adj[i]);
        dvcm.push_back(o.dvcm[i]), dvc.push_back(o.dvc[i]), dvm.push_back(o.dvm[i]);
        length.push_back(o.length[i]), front.push_back(o.front[i]), geom.push_back(o.geom[i]);
        uv.push_back(o.uv[i]), path.push_back(o.path[i]), medium.push_back(o.medium[i]);
    }
};

}  // namespace foton
