#include "curve_intersector.h"

#include <tbb/parallel_invoke.h>

namespace foton {

CurveIntersector::CurveIntersector(const Scene& scene, std::unique_ptr<Intersector> inner)
    : scene_(scene), inner_(std::move(inner)) {
    std::vector<kern::CurveSegment> segments;
    std::vector<uint8_t> ribbon;
    for (uint32_t g = 0; g < scene.objects.size(); ++g) {
        const Object& o = scene.objects[g];
        if (o.kind != ObjectKind::Curves) continue;
        const CurveSet& set = scene.curves[o.index];
        for (uint32_t s = 0; s < set.size(); ++s) {
            segments.push_back(set.segments[s]);
            ribbon.push_back(set.form == CurveForm::Ribbon ? 1 : 0);
            refs_.push_back({g, s});
        }
    }
    bvh_ = kern::CurveBvh(segments, ribbon,
                          [](const std::function<void()>& a, const std::function<void()>& b) {
                              tbb::parallel_invoke(a, b);
                          });
}

std::size_t CurveIntersector::memory_bytes() const {
    return inner_->memory_bytes() + refs_.size() * sizeof(SegmentRef) + bvh_.memory_bytes();
}

bool CurveIntersector::closest_curve(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    kern::CurveHit ch;
    ch.t = hit.t;
    uint32_t id = 0;
    if (!bvh_.closest(ray, ch, id, c.curve_tests)) return false;
    hit = Hit1{ch.t, ch.u, ch.v, refs_[id].segment, refs_[id].geom};
    return true;
}

bool CurveIntersector::any_curve(const kern::Ray1& ray, TraceCounters& c) const {
    return bvh_.any(ray, c.curve_tests);
}

void CurveIntersector::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    inner_->intersect(rays, hits, c);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        Hit1 h{hits.t[i], hits.u[i], hits.v[i], hits.prim[i], hits.geom[i]};
        if (h.geom == kNoHit) h.t = kInfinity;
        if (!closest_curve(ray_at(rays, i), h, c)) continue;
        hits.t[i] = h.t;
        hits.u[i] = h.u;
        hits.v[i] = h.v;
        hits.prim[i] = h.prim;
        hits.geom[i] = h.geom;
    }
}

void CurveIntersector::occluded(const RayBatch& rays, std::vector<uint8_t>& occ,
                                TraceCounters& c) const {
    inner_->occluded(rays, occ, c);
    for (std::size_t i = 0; i < rays.size(); ++i)
        if (!occ[i]) occ[i] = any_curve(ray_at(rays, i), c) ? 1 : 0;
}

bool CurveIntersector::intersect1(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    const bool inner_hit = inner_->intersect1(ray, hit, c);
    if (!inner_hit) hit.t = kInfinity;
    return closest_curve(ray, hit, c) || inner_hit;
}

bool CurveIntersector::occluded1(const kern::Ray1& ray, TraceCounters& c) const {
    return inner_->occluded1(ray, c) || any_curve(ray, c);
}

}  // namespace foton
