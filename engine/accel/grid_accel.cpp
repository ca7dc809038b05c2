#include "grid_accel.h"

#include <algorithm>

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

GridAccel::GridAccel(const Scene& scene, const kern::GridParams& mesh_params)
    : scene_(scene),
      mesh_params_(mesh_params),
      lazy_(scene.grid_lazy),
      instances_(scene, AccelType::Grid, 0) {
    grids_.resize(scene.meshes.size());
    once_ = std::make_unique<std::once_flag[]>(scene.meshes.size());
    built_ = std::make_unique<std::atomic<bool>[]>(scene.meshes.size());
    for (const Object& o : scene.objects) {
        if (o.kind != ObjectKind::Mesh || o.instance >= 0) continue;
        ++meshes_;
        if (!lazy_) build_once(o.index);
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
        if (scene.objects[g].instance >= 0) continue;             // in the instance layer
        if (!traced_by_backend(scene.objects[g].kind)) continue;  // the wrappers'
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

const kern::UniformGrid& GridAccel::build_once(uint32_t mesh) const {
    std::call_once(once_[mesh], [&] {
        const TriangleMesh& m = scene_.meshes[mesh];
        grids_[mesh].build(m.positions.data(), m.indices.data(), m.num_triangles(), mesh_params_);
        built_[mesh].store(true, std::memory_order_release);
    });
    return grids_[mesh];
}

std::size_t GridAccel::built_grids() const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < grids_.size(); ++i)
        n += built_[i].load(std::memory_order_acquire) ? 1 : 0;
    return n;
}

std::size_t GridAccel::memory_bytes() const {
    std::size_t n =
        (cell_begin_.size() + cell_objects_.size()) * sizeof(uint32_t) + instances_.memory_bytes();
    for (std::size_t i = 0; i < grids_.size(); ++i)
        if (built_[i].load(std::memory_order_acquire)) n += grids_[i].memory_bytes();
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
    const bool found = grid(o.index).intersect(ray, th, &gc);
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
    const bool hit = grid(o.index).occluded(ray, &gc);
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
    if (!instances_.empty()) instances_.closest(ray, hit, c);
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
    return hit || (!instances_.empty() && instances_.any(ray, c));
}

}  // namespace foton
