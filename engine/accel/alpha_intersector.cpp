#include "alpha_intersector.h"

#include <bit>
#include <cmath>

#include "engine/core/rng.h"

namespace foton {

namespace {

// Cut-out layers one ray may pass before the rest are taken as transparent too (a ray through
// a forest of leaves); far above what a scene needs, it only bounds the loop.
constexpr int kMaxLayers = 256;

// The next float above a cut-out hit's t: where the search goes on (Embree takes hits at
// t = tmin, the other backends only beyond it).
float alpha_search_start(float t) {
    return std::nextafter(t, kInfinity);
}

// The texture coordinates of a hit in uv set `set` (surface_at's parametrisation, without
// its normals).
Point2 alpha_hit_uv(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                    const Vec3& o, const Vec3& d, int set) {
    const Object& obj = scene.objects[geom];
    if (obj.kind == ObjectKind::Sphere) {
        const Sphere& s = scene.spheres[obj.index];
        Vec3 p = o + d * t;
        if (const Instance* in = scene.instance_of(geom)) p = in->to_object.point(p);
        return sphere_uv(normalize(p - s.center));
    }
    Point2 t0, t1, t2;
    scene.meshes[obj.index].corner_uvs(prim, t0, t1, t2, set);
    const float w = 1.f - u - v;
    return {t0.x * w + t1.x * u + t2.x * v, t0.y * w + t1.y * u + t2.y * v};
}

// A uniform number of the ray, the primitive it met and how many cut-out points it passed
// before: the same in every backend and run. The count decorrelates the two sides of one
// primitive (a sphere's entry and exit): pbrt-v4 tests each from a new ray, independently.
float alpha_hash(const Vec3& o, const Vec3& d, uint32_t geom, uint32_t prim, uint32_t passed) {
    auto bits = [](float a, float b) {
        return (uint64_t(std::bit_cast<uint32_t>(a)) << 32) | std::bit_cast<uint32_t>(b);
    };
    uint64_t h = rng::mix64((uint64_t(geom) << 32) | prim) ^ rng::mix64(uint64_t(passed) + 1);
    h = rng::mix64(h ^ bits(d.y, d.z));
    h = rng::mix64(h ^ bits(o.z, d.x));
    h = rng::mix64(h ^ bits(o.x, o.y));
    return rng::to_unit_float(h);
}

}  // namespace

bool alpha_hit_counts(const Scene& scene, uint32_t geom, uint32_t prim, float t, float u, float v,
                      const Vec3& o, const Vec3& d, uint32_t passed) {
    const Material& m = scene.material_of(geom);
    if (!m.cuts_out()) return true;
    float a = m.alpha;
    if (m.alpha_texture >= 0) {
        const Texture& tx = scene.textures[std::size_t(m.alpha_texture)];
        // The hit point for textures mapped by position; the surface normal is not computed
        // here, so a directionmix alpha reads the ray's direction instead. (Its uv2 is its uv:
        // the coordinates are already the texture's set.)
        a *= tx.eval_float(
            scene.texture_images,
            TexPoint{alpha_hit_uv(scene, geom, prim, t, u, v, o, d, tx.uv.set), o + d * t, -d});
    }
    if (m.alpha_cutoff >= 0.f) return a >= m.alpha_cutoff;
    if (a >= 1.f) return true;
    if (!(a > 0.f)) return false;
    return alpha_hash(o, d, geom, prim, passed) < a;
}

void AlphaIntersector::resolve(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    auto cut = [&](std::size_t i, uint32_t passed) {
        return hits.geom[i] != kNoHit &&
               !alpha_hit_counts(scene_, hits.geom[i], hits.prim[i], hits.t[i], hits.u[i],
                                 hits.v[i], rays.origin(i), rays.direction(i), passed);
    };
    RayBatch again;
    HitBatch found;
    std::vector<uint32_t> which;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (cut(i, 0)) which.push_back(uint32_t(i));
    for (int layer = 0; !which.empty(); ++layer) {
        if (layer == kMaxLayers) {
            for (const uint32_t i : which) hits.geom[i] = hits.prim[i] = kNoHit;
            break;
        }
        // From just past the cut-out hit, same origin and direction: the hash and the t
        // values stay those of the original ray.
        again.clear();
        for (const uint32_t i : which)
            again.push(rays.origin(i), rays.direction(i), alpha_search_start(hits.t[i]),
                       rays.tmax[i], i);
        inner_->intersect(again, found, c);
        std::vector<uint32_t> next;
        for (std::size_t k = 0; k < again.size(); ++k) {
            const uint32_t i = again.id[k];
            hits.t[i] = found.t[k];
            hits.u[i] = found.u[k];
            hits.v[i] = found.v[k];
            hits.prim[i] = found.prim[k];
            hits.geom[i] = found.geom[k];
            if (cut(i, uint32_t(layer) + 1)) next.push_back(i);
        }
        which.swap(next);
    }
}

void AlphaIntersector::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    inner_->intersect(rays, hits, c);
    resolve(rays, hits, c);
}

void AlphaIntersector::occluded(const RayBatch& rays, std::vector<uint8_t>& occ,
                                TraceCounters& c) const {
    inner_->occluded(rays, occ, c);
    // What the backend found in the way may be cut out: the closest-hit walk decides.
    RayBatch blocked;
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (occ[i])
            blocked.push(rays.origin(i), rays.direction(i), rays.tmin[i], rays.tmax[i],
                         uint32_t(i));
    if (blocked.empty()) return;
    HitBatch hits;
    intersect(blocked, hits, c);
    for (std::size_t k = 0; k < blocked.size(); ++k) occ[blocked.id[k]] = hits.geom[k] != kNoHit;
}

bool AlphaIntersector::intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    kern::Ray1 r = ray;
    const Vec3 o{ray.ox, ray.oy, ray.oz}, d{ray.dx, ray.dy, ray.dz};
    for (int layer = 0; layer < kMaxLayers; ++layer) {
        hit = Hit1{};
        if (!inner_->intersect1(r, hit, c)) return false;
        if (alpha_hit_counts(scene_, hit.geom, hit.prim, hit.t, hit.u, hit.v, o, d,
                             uint32_t(layer)))
            return true;
        r.tmin = alpha_search_start(hit.t);
    }
    hit = Hit1{};
    return false;
}

bool AlphaIntersector::occluded1(const kern::Ray1& ray, TraceCounters& c) const {
    if (!inner_->occluded1(ray, c)) return false;
    Hit1 hit;
    return intersect1(ray, hit, c);
}

}  // namespace foton
