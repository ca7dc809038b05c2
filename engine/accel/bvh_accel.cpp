#include "bvh_accel.h"

#include "engine/core/thread_pinning.h"
#include "object_box.h"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

namespace foton {

namespace {

kern::BvhBuildParams::ParallelInvoke tbb_invoke() {
    return [](const std::function<void()>& a, const std::function<void()>& b) {
        tbb::parallel_invoke(a, b);
    };
}

// Trace counters from the kernel's (a block of M triangles is M ray/triangle tests).
void add_counts(TraceCounters& c, const kern::BvhCounters& bc) {
    c.bvh_nodes += bc.nodes;
    c.triangle_tests += bc.blocks * kern::TriangleBvh::kLeafWidth;
}

}  // namespace

BvhAccel::BvhAccel(const Scene& scene, int threads, std::size_t stream_min_bytes)
    : scene_(scene),
      instances_(scene, AccelType::Bvh, threads),
      stream_min_bytes_(stream_min_bytes) {
    std::vector<kern::TriangleSource> sources;
    std::vector<kern::PrimRef> sphere_refs;
    uint32_t next = 0;
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.instance >= 0) continue;  // in the instance layer
        if (o.kind == ObjectKind::Mesh) {
            const TriangleMesh& m = scene.meshes[o.index];
            sources.push_back({m.positions.data(), m.indices.data(), m.num_triangles()});
            first_id_.push_back(next);
            mesh_geom_.push_back(g);
            next += uint32_t(m.num_triangles());
            continue;
        }
        if (!traced_by_backend(o.kind)) continue;  // the wrappers'
        sphere_refs.push_back(padded_object_ref(scene, g));
    }
    auto build = [&] {
        auto p = kern::TriangleBvh::default_params();
        p.parallel = tbb_invoke();
        tris_.build(sources.data(), sources.size(), p);
        kern::BvhBuildParams sp;
        sp.leaf_block = 1;
        sp.max_leaf = 4;
        spheres_ = kern::build_binary_bvh(sphere_refs, sp);
    };
    if (threads > 0) {
        PinnedArena arena(threads);
        arena.execute(build);
    } else {
        build();
    }
}

std::size_t BvhAccel::memory_bytes() const {
    return tris_.memory_bytes() + spheres_.used * sizeof(kern::BinaryNode) +
           spheres_.prims.size() * sizeof(uint32_t) + instances_.memory_bytes();
}

void BvhAccel::closest_sphere(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    kern::walk_binary_bvh(
        spheres_, ray, [&] { return hit.geom == kNoHit ? hit.t : hit.t * kern::kBvhCullScale; },
        [&](uint32_t g) {
            // A tie with a sphere of a larger id is won; with a triangle, lost.
            const bool tie_wins =
                hit.geom == kNoHit ||
                (scene_.objects[hit.geom].kind == ObjectKind::Sphere && g < hit.geom);
            const float bound =
                tie_wins && hit.geom != kNoHit ? std::nextafter(hit.t, kInfinity) : hit.t;
            float t;
            ++c.sphere_tests;
            if (intersect_sphere(scene_.spheres[scene_.objects[g].index], org, dir, ray.tmin, bound,
                                 t) &&
                (t < hit.t || tie_wins))
                hit = Hit1{t, 0.f, 0.f, 0, g};
            return false;
        });
}

bool BvhAccel::any_sphere(const kern::Ray1& ray, TraceCounters& c) const {
    const Vec3 org{ray.ox, ray.oy, ray.oz}, dir{ray.dx, ray.dy, ray.dz};
    bool hit = false;
    kern::walk_binary_bvh(
        spheres_, ray, [&] { return ray.tmax; },
        [&](uint32_t g) {
            float t;
            ++c.sphere_tests;
            hit = intersect_sphere(scene_.spheres[scene_.objects[g].index], org, dir, ray.tmin,
                                   ray.tmax, t);
            return hit;
        });
    return hit;
}

Hit1 BvhAccel::mesh_hit(const kern::TriHit& th) const {
    const std::size_t m = std::size_t(std::upper_bound(first_id_.begin(), first_id_.end(), th.id) -
                                      first_id_.begin()) -
                          1;
    return Hit1{th.t, th.u, th.v, th.id - first_id_[m], mesh_geom_[m]};
}

bool BvhAccel::closest(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    hit.t = std::min(ray.tmax, hit.t);
    kern::TriHit th;
    th.t = hit.t;
    kern::BvhCounters bc;
    if (tris_.intersect(ray, th, &bc)) hit = mesh_hit(th);
    add_counts(c, bc);
    closest_sphere(ray, hit, c);
    if (!instances_.empty()) instances_.closest(ray, hit, c);
    return hit.geom != kNoHit;
}

bool BvhAccel::any(const kern::Ray1& ray, TraceCounters& c) const {
    kern::BvhCounters bc;
    const bool hit = tris_.occluded(ray, &bc);
    add_counts(c, bc);
    return hit || any_sphere(ray, c) || (!instances_.empty() && instances_.any(ray, c));
}

namespace {

constexpr std::size_t kW = kern::kBlockWidth;

// Rays [first, first + count) of the batch as one packet; lanes past count are inactive.
uint32_t load_packet(const RayBatch& rays, std::size_t first, std::size_t count, kern::RayPacket& p,
                     float* tmax) {
    for (std::size_t l = 0; l < kW; ++l) {
        const std::size_t i = first + std::min(l, count - 1);
        p.ox[l] = rays.ox[i], p.oy[l] = rays.oy[i], p.oz[l] = rays.oz[i];
        p.dx[l] = rays.dx[i], p.dy[l] = rays.dy[i], p.dz[l] = rays.dz[i];
        p.tmin[l] = rays.tmin[i];
        tmax[l] = rays.tmax[i];
    }
    return count >= 32 ? ~0u : (1u << count) - 1u;
}

}  // namespace

namespace {

kern::RayStream stream_of(const RayBatch& rays) {
    return {rays.ox.data(), rays.oy.data(),   rays.oz.data(),   rays.dx.data(), rays.dy.data(),
            rays.dz.data(), rays.tmin.data(), rays.tmax.data(), rays.size()};
}

}  // namespace

void BvhAccel::finish_hit(const RayBatch& rays, std::size_t i, const kern::TriHit& th,
                          HitBatch& hits, TraceCounters& c) const {
    Hit1 h;
    h.t = std::min(rays.tmax[i], h.t);
    if (th.valid()) h = mesh_hit(th);
    closest_sphere(ray_at(rays, i), h, c);
    if (!instances_.empty()) instances_.closest(ray_at(rays, i), h, c);
    hits.t[i] = h.t;
    hits.u[i] = h.u;
    hits.v[i] = h.v;
    hits.prim[i] = h.prim;
    hits.geom[i] = h.geom;
}

bool BvhAccel::use_stream(const RayBatch& rays) const {
    return !rays.coherent && tris_.memory_bytes() >= stream_min_bytes_;
}

void BvhAccel::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    if (use_stream(rays)) {
        // The stream writes each ray's triangle hit (t, u, v, id) into the hit columns; then
        // every ray finishes as closest() does: mesh hit, spheres, instances.
        hits.resize(rays.size());
        kern::BvhCounters bc;
        tris_.intersect_stream(
            stream_of(rays), {hits.t.data(), hits.u.data(), hits.v.data(), hits.prim.data()}, &bc);
        add_counts(c, bc);
        for (std::size_t i = 0; i < rays.size(); ++i)
            finish_hit(rays, i, {hits.t[i], hits.u[i], hits.v[i], hits.prim[i]}, hits, c);
        return;
    }
    if (!rays.coherent) return PerRayIntersector<BvhAccel>::intersect(rays, hits, c);
    hits.resize(rays.size());
    kern::BvhCounters bc;
    for (std::size_t first = 0; first < rays.size(); first += kW) {
        const std::size_t count = std::min(kW, rays.size() - first);
        kern::RayPacket p;
        kern::PacketHits ph;
        const uint32_t active = load_packet(rays, first, count, p, ph.t);
        for (std::size_t l = 0; l < kW; ++l) ph.u[l] = ph.v[l] = 0.f, ph.id[l] = kern::kInvalidId;
        tris_.intersect_packet(p, active, ph, &bc);
        for (std::size_t l = 0; l < count; ++l)
            finish_hit(rays, first + l, {ph.t[l], ph.u[l], ph.v[l], ph.id[l]}, hits, c);
    }
    add_counts(c, bc);
}

void BvhAccel::occluded(const RayBatch& rays, std::vector<uint8_t>& occ, TraceCounters& c) const {
    if (use_stream(rays)) {
        occ.resize(rays.size());
        kern::BvhCounters bc;
        tris_.occluded_stream(stream_of(rays), occ.data(), &bc, kern::StreamMode::SortedPackets);
        add_counts(c, bc);
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (!occ[i])
                occ[i] = any_sphere(ray_at(rays, i), c) ||
                         (!instances_.empty() && instances_.any(ray_at(rays, i), c));
        return;
    }
    if (!rays.coherent) return PerRayIntersector<BvhAccel>::occluded(rays, occ, c);
    occ.resize(rays.size());
    kern::BvhCounters bc;
    for (std::size_t first = 0; first < rays.size(); first += kW) {
        const std::size_t count = std::min(kW, rays.size() - first);
        kern::RayPacket p;
        alignas(64) float tmax[kW];
        const uint32_t active = load_packet(rays, first, count, p, tmax);
        const uint32_t blocked = tris_.occluded_packet(p, tmax, active, &bc);
        for (std::size_t l = 0; l < count; ++l)
            occ[first + l] = ((blocked >> l) & 1u) || any_sphere(ray_at(rays, first + l), c) ||
                             (!instances_.empty() && instances_.any(ray_at(rays, first + l), c));
    }
    add_counts(c, bc);
}

}  // namespace foton
