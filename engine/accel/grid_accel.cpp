#include "grid_accel.h"

#include <algorithm>
#include <array>

namespace foton {

namespace {
// Mailbox: which objects this thread has already tested for the current ray. An object's
// test covers the whole ray, so a second visit (from another cell) adds nothing.
struct Mailbox {
    std::vector<uint32_t> stamp;
    uint32_t ray = 0;
    void begin(std::size_t objects) {
        if (stamp.size() < objects) stamp.assign(objects, 0);
        if (++ray == 0) {
            std::fill(stamp.begin(), stamp.end(), 0);
            ray = 1;
        }
    }
    bool first_visit(uint32_t geom) {
        if (stamp[geom] == ray) return false;
        stamp[geom] = ray;
        return true;
    }
};
thread_local Mailbox t_mailbox;
}  // namespace

GridAccel::GridAccel(const Scene& scene, const kern::GridParams& mesh_params) : scene_(scene) {
    grids_.resize(scene.meshes.size());
    for (const Object& o : scene.objects) {
        if (o.kind != ObjectKind::Mesh) continue;
        const TriangleMesh& m = scene.meshes[o.index];
        grids_[o.index].build(m.positions.data(), m.indices.data(), m.num_triangles(), mesh_params);
    }
    // Top level: a coarse grid over object bounds.
    const std::size_t n = scene.objects.size();
    std::vector<Bounds3> ob(n);
    Bounds3 all;
    for (std::size_t g = 0; g < n; ++g) {
        ob[g] = scene.object_bounds(uint32_t(g));
        all.extend(ob[g]);
    }
    if (n == 0) all.extend(Vec3{0, 0, 0});
    const float lo[3] = {all.lo.x, all.lo.y, all.lo.z}, hi[3] = {all.hi.x, all.hi.y, all.hi.z};
    top_ = kern::GridFrame::fit(lo, hi, double(std::max<std::size_t>(1, 8 * n)), 64);
    const uint32_t ncells = top_.num_cells();
    std::vector<std::vector<uint32_t>> cells(ncells);
    for (uint32_t g = 0; g < n; ++g) {
        int clo[3], chi[3];
        for (int a = 0; a < 3; ++a) {
            clo[a] = top_.cell_of(a, ob[g].lo[a]);
            chi[a] = top_.cell_of(a, ob[g].hi[a]);
        }
        for (int z = clo[2]; z <= chi[2]; ++z)
            for (int y = clo[1]; y <= chi[1]; ++y)
                for (int x = clo[0]; x <= chi[0]; ++x) cells[top_.index(x, y, z)].push_back(g);
    }
    cell_begin_.assign(ncells + 1, 0);
    for (uint32_t c = 0; c < ncells; ++c) {
        cell_begin_[c + 1] = cell_begin_[c] + uint32_t(cells[c].size());
        cell_objects_.insert(cell_objects_.end(), cells[c].begin(), cells[c].end());
    }
}

std::size_t GridAccel::memory_bytes() const {
    std::size_t n = (cell_begin_.size() + cell_objects_.size()) * sizeof(uint32_t);
    for (const auto& g : grids_) n += g.memory_bytes();
    return n;
}

bool GridAccel::hit_object(uint32_t geom, const kern::Ray1& ray, Hit1& hit,
                           TraceCounters& c) const {
    const Object& o = scene_.objects[geom];
    if (o.kind == ObjectKind::Sphere) {
        float t;
        ++c.sphere_tests;
        if (!intersect_sphere(scene_.spheres[o.index], {ray.ox, ray.oy, ray.oz},
                              {ray.dx, ray.dy, ray.dz}, ray.tmin, hit.t, t))
            return false;
        hit = Hit1{t, 0.f, 0.f, 0, geom};
        return true;
    }
    kern::TriHit th;
    th.t = hit.t;
    kern::GridCounters gc;
    const bool found = grids_[o.index].intersect(ray, th, &gc);
    c.cells += gc.cells;
    c.triangle_tests += gc.blocks * kern::kBlockWidth;
    if (!found) return false;
    hit = Hit1{th.t, th.u, th.v, th.id, geom};
    return true;
}

bool GridAccel::occludes_object(uint32_t geom, const kern::Ray1& ray, TraceCounters& c) const {
    const Object& o = scene_.objects[geom];
    if (o.kind == ObjectKind::Sphere) {
        float t;
        ++c.sphere_tests;
        return intersect_sphere(scene_.spheres[o.index], {ray.ox, ray.oy, ray.oz},
                                {ray.dx, ray.dy, ray.dz}, ray.tmin, ray.tmax, t);
    }
    kern::GridCounters gc;
    const bool hit = grids_[o.index].occluded(ray, &gc);
    c.cells += gc.cells;
    c.triangle_tests += gc.blocks * kern::kBlockWidth;
    return hit;
}

bool GridAccel::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    Mailbox& mb = t_mailbox;
    mb.begin(scene_.objects.size());
    hit.t = std::min(hit.t, ray.tmax);
    kern::dda_walk(top_, ray, hit.t, [&](uint32_t cell, float t_exit) {
        for (uint32_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
            const uint32_t g = cell_objects_[k];
            if (mb.first_visit(g)) hit_object(g, ray, hit, c);
        }
        return hit.geom != kNoHit && hit.t <= t_exit;
    });
    return hit.geom != kNoHit;
}

bool GridAccel::any(const kern::Ray1& ray, TraceCounters& c) const {
    Mailbox& mb = t_mailbox;
    mb.begin(scene_.objects.size());
    bool hit = false;
    kern::dda_walk(top_, ray, ray.tmax, [&](uint32_t cell, float) {
        for (uint32_t k = cell_begin_[cell]; k < cell_begin_[cell + 1] && !hit; ++k) {
            const uint32_t g = cell_objects_[k];
            if (mb.first_visit(g)) hit = occludes_object(g, ray, c);
        }
        return hit;
    });
    return hit;
}

void GridAccel::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    if (!rays.coherent) return PerRayIntersector<GridAccel>::intersect(rays, hits, c);
    constexpr std::size_t W = kern::kBlockWidth;
    // Rays per bundle: 4 packets, e.g. 4 pixels x 4 samples x 4 on AVX-512.
    constexpr std::size_t kPackets = 4, B = kPackets * W;
    hits.resize(rays.size());
    const std::size_t n_obj = scene_.objects.size();
    // Per mesh object: the bundle's hits in that object alone (bound: each ray's tmax).
    thread_local std::vector<std::array<kern::PacketHits, kPackets>> per_object;
    thread_local std::vector<uint8_t> wanted;
    per_object.resize(n_obj);
    for (std::size_t first = 0; first < rays.size(); first += B) {
        const std::size_t count = std::min(B, rays.size() - first);
        const std::size_t np = (count + W - 1) / W;
        // The objects any of the rays' full walks would reach.
        wanted.assign(n_obj, 0);
        for (std::size_t l = 0; l < count; ++l) {
            const kern::Ray1 r = ray_at(rays, first + l);
            const float no_limit = r.tmax;
            kern::dda_walk(top_, r, no_limit, [&](uint32_t cell, float) {
                for (uint32_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k)
                    wanted[cell_objects_[k]] = 1;
                return false;
            });
        }
        kern::RayPacket p[kPackets];
        for (std::size_t l = 0; l < np * W; ++l) {
            const std::size_t i = first + std::min(l, count - 1);
            kern::RayPacket& k = p[l / W];
            const std::size_t j = l % W;
            k.ox[j] = rays.ox[i], k.oy[j] = rays.oy[i], k.oz[j] = rays.oz[i];
            k.dx[j] = rays.dx[i], k.dy[j] = rays.dy[i], k.dz[j] = rays.dz[i];
            k.tmin[j] = rays.tmin[i];
        }
        for (uint32_t g = 0; g < n_obj; ++g) {
            const Object& o = scene_.objects[g];
            if (!wanted[g] || o.kind != ObjectKind::Mesh) continue;
            auto& ph = per_object[g];
            for (std::size_t l = 0; l < np * W; ++l) {
                ph[l / W].t[l % W] = l < count ? rays.tmax[first + l] : -kInfinity;
                ph[l / W].id[l % W] = kern::kInvalidId;
            }
            kern::GridCounters gc;
            grids_[o.index].intersect_packets(p, np, ph.data(), &gc);
            c.cells += gc.cells;
            c.triangle_tests += (gc.blocks + gc.packet_tests) * W;
        }
        // Each ray's own walk, as closest() does it, reading its hits from the packets: an
        // object's hit counts when it is closer than the best so far, exactly as the object's
        // own traversal bounded by that best would have found it.
        for (std::size_t l = 0; l < count; ++l) {
            const std::size_t i = first + l;
            const kern::Ray1 r = ray_at(rays, i);
            Mailbox& mb = t_mailbox;
            mb.begin(n_obj);
            Hit1 hit;
            hit.t = std::min(hit.t, r.tmax);
            kern::dda_walk(top_, r, hit.t, [&](uint32_t cell, float t_exit) {
                for (uint32_t k = cell_begin_[cell]; k < cell_begin_[cell + 1]; ++k) {
                    const uint32_t g = cell_objects_[k];
                    if (!mb.first_visit(g)) continue;
                    const Object& o = scene_.objects[g];
                    if (o.kind != ObjectKind::Mesh) {
                        hit_object(g, r, hit, c);
                        continue;
                    }
                    const kern::PacketHits& ph = per_object[g][l / W];
                    const std::size_t j = l % W;
                    if (ph.id[j] != kern::kInvalidId && ph.t[j] < hit.t)
                        hit = Hit1{ph.t[j], ph.u[j], ph.v[j], ph.id[j], g};
                }
                return hit.geom != kNoHit && hit.t <= t_exit;
            });
            hits.t[i] = hit.t;
            hits.u[i] = hit.u;
            hits.v[i] = hit.v;
            hits.prim[i] = hit.prim;
            hits.geom[i] = hit.geom;
        }
    }
}

}  // namespace foton
