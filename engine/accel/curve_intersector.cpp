#include "curve_intersector.h"

#include <tbb/parallel_invoke.h>

namespace foton {

CurveIntersector::CurveIntersector(const Scene& scene, std::unique_ptr<Intersector> inner)
    : LayeredIntersector(std::move(inner)) {
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

bool CurveIntersector::closest_own(const kern::Ray1& ray, Hit1& hit, TraceCounters& c) const {
    kern::CurveHit ch;
    ch.t = hit.t;
    uint32_t id = 0;
    if (!bvh_.closest(ray, ch, id, c.curve_tests)) return false;
    hit = Hit1{ch.t, ch.u, ch.v, refs_[id].segment, refs_[id].geom};
    return true;
}

void CurveIntersector::intersect(const RayBatch& rays, HitBatch& hits, TraceCounters& c) const {
    inner_->intersect(rays, hits, c);
    if (bvh_.empty()) return;
    thread_local Stream s;
    const std::size_t n = rays.size();
    s.rays.resize(n);
    s.hits.assign(n, kern::CurveHit{});
    s.ids.resize(n);
    s.found.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        s.rays[i] = ray_at(rays, i);
        // Closer than the backend's hit, as closest_own() asks.
        if (hits.geom[i] != kNoHit) s.hits[i].t = hits.t[i];
    }
    bvh_.closest_stream(s.rays.data(), n, s.hits.data(), s.ids.data(), s.found.data(),
                        c.curve_tests);
    for (std::size_t i = 0; i < n; ++i)
        if (s.found[i]) {
            const kern::CurveHit& h = s.hits[i];
            store_hit(hits, i, Hit1{h.t, h.u, h.v, refs_[s.ids[i]].segment, refs_[s.ids[i]].geom});
        }
}

bool CurveIntersector::any_own(const kern::Ray1& ray, TraceCounters& c) const {
    return bvh_.any(ray, c.curve_tests);
}

}  // namespace foton
