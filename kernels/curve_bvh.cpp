#include "curve_bvh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "bvh_box_ray.h"
#include "bvh_pack.h"

namespace foton::kern {

CurveBvh::CurveBvh(const std::vector<CurveSegment>& segments, const std::vector<uint8_t>& ribbon,
                   const BvhBuildParams::ParallelInvoke& parallel, int split) {
    const uint32_t parts = 1u << std::clamp(split, 0, 6);
    part_du_ = 1.f / float(parts);
    std::vector<CurveSegment> all;
    std::vector<uint32_t> owner;
    std::vector<float> u0;
    all.reserve(segments.size() * parts);
    for (std::size_t i = 0; i < segments.size(); ++i)
        for (uint32_t k = 0; k < parts; ++k) {
            const float a = float(k) / float(parts), b = float(k + 1) / float(parts);
            all.push_back(parts == 1 ? segments[i] : curve_part(segments[i], a, b));
            owner.push_back(uint32_t(i));
            u0.push_back(a);
        }
    if (all.empty()) return;
    std::vector<PrimRef> boxes(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        curve_bounds(all[i], boxes[i].lo, boxes[i].hi);
        boxes[i].id = uint32_t(i);
        boxes[i].pad = 0;
    }
    BvhBuildParams p;
    p.leaf_block = 1;
    p.max_leaf = 4;
    p.parallel = parallel;
    const BinaryBvh bin = build_binary_bvh(boxes, p);
    const WideTree wide = collapse_bvh(bin, uint32_t(kWidth));
    // Parts in leaf order, so a leaf's tests read consecutive memory; nodes in the wide
    // tree's order, a leaf a run of parts.
    parts_.reserve(all.size());
    nodes_.resize(wide.nodes.size());
    pack_wide_nodes<kWidth>(wide, nodes_, [&](const WideChild& k) {
        const uint32_t first = uint32_t(parts_.size());
        if (k.count > kBvhMaxLeafBlocks || first + k.count > kBvhMaxFirstBlock)
            throw std::length_error("curve BVH: too many parts");
        for (uint32_t j = 0; j < k.count; ++j) {
            const uint32_t part = bin.prims[k.index + j];
            const CurveSegment& s = all[part];
            Part& q = parts_.emplace_back();
            std::copy(&s.cp[0][0], &s.cp[0][0] + 12, &q.cp[0][0]);
            q.w0 = s.w0;
            q.w1 = s.w1;
            q.ribbon = ribbon[owner[part]];
            q.index = uint32_t(ids_.size());
            normals_.insert(normals_.end(), s.n0, s.n0 + 3);
            normals_.insert(normals_.end(), s.n1, s.n1 + 3);
            ids_.push_back(owner[part]);
            u0_.push_back(u0[part]);
        }
        return bvh_make_leaf(first, k.count);
    });
    root_ = (wide.nodes[0].size() == 1 && wide.nodes[0][0].leaf) ? nodes_[0].child[0] : 0;
}

CurveSegment CurveBvh::Part::segment(const std::vector<float>& normals) const {
    CurveSegment s;
    std::copy(&cp[0][0], &cp[0][0] + 12, &s.cp[0][0]);
    s.w0 = w0;
    s.w1 = w1;
    if (ribbon) {
        // Only a ribbon's test reads its normals.
        const float* n = &normals[6 * std::size_t(index)];
        std::copy(n, n + 3, s.n0);
        std::copy(n + 3, n + 6, s.n1);
    }
    return s;
}

namespace {

// Rays with NaN, an empty interval or no direction find nothing (as the kernel's own checks).
bool unusable_ray(const Ray1& r) {
    return std::isnan(r.ox + r.oy + r.oz + r.dx + r.dy + r.dz) || !(r.tmin <= r.tmax) ||
           (r.dx == 0.f && r.dy == 0.f && r.dz == 0.f);
}

}  // namespace

// Every child the ray enters will likely be visited: start their loads now (the tree and its
// parts, tens of megabytes, are read at random by incoherent rays).
[[gnu::always_inline]] inline void CurveBvh::prefetch_children(const Node& node,
                                                               uint32_t mask) const {
    for (uint32_t m = mask; m; m &= m - 1) {
        const uint32_t c = node.child[__builtin_ctz(m)];
        if (bvh_is_leaf(c)) {
            const Part* part = &parts_[bvh_leaf_first(c)];
            for (uint32_t b = 0; b < bvh_leaf_blocks(c); ++b) __builtin_prefetch(part + b);
        } else {
            const char* n = reinterpret_cast<const char*>(&nodes_[c]);
            for (uint32_t b = 0; b < sizeof(Node); b += 64) __builtin_prefetch(n + b);
        }
    }
}

// The walk: the nearest child box first, the others stacked far to near with their entry
// distances; a leaf's parts tested in order, each closer hit shrinking the cull distance;
// `leaf(first, count)` returns true to stop (any-hit).
template <class Leaf>
void CurveBvh::walk(const Ray1& ray, const float& tcull, Leaf&& leaf) const {
    using namespace bvh_detail;
    using V = simd::FloatW<kWidth>;
    const BoxRay<kWidth> br(ray);
    StackEntry stack[kStackSize];
    uint32_t sp = 0;
    uint32_t ref = root_;
    for (;;) {
        while (!bvh_is_leaf(ref)) {
            const Node& node = nodes_[ref];
            V tnv;
            const uint32_t mask = br.test(node, tcull, tnv);
            if (mask == 0) goto pop;
            alignas(64) float tn[kWidth];
            tnv.store_aligned(tn);
            prefetch_children(node, mask);
            ref = order_children(node, mask, tn, stack, sp);
        }
        if (leaf(bvh_leaf_first(ref), bvh_leaf_blocks(ref))) return;
    pop:
        for (;;) {
            if (sp == 0) return;
            const StackEntry& e = stack[--sp];
            if (e.t <= tcull) {
                ref = e.ref;
                break;
            }
        }
    }
}

bool CurveBvh::closest(const Ray1& ray, CurveHit& hit, uint32_t& id, uint64_t& tests) const {
    if (parts_.empty() || unusable_ray(ray)) return false;
    uint32_t best = UINT32_MAX;
    hit.t = std::min(hit.t, ray.tmax);
    float tcull = hit.t < kInf ? hit.t * kBvhCullScale : hit.t;
    const CurveRay cr(ray);
    walk(ray, tcull, [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count; ++i) {
            ++tests;
            if (test_part(cr, i, hit)) {
                best = i;
                tcull = hit.t * kBvhCullScale;
            }
        }
        return false;
    });
    if (best == UINT32_MAX) return false;
    const uint32_t k = parts_[best].index;
    hit.u = u0_[k] + part_du_ * hit.u;
    id = ids_[k];
    return true;
}

bool CurveBvh::any(const Ray1& ray, uint64_t& tests) const {
    if (parts_.empty() || unusable_ray(ray)) return false;
    bool found = false;
    const float tcull = ray.tmax;
    const CurveRay cr(ray);
    walk(ray, tcull, [&](uint32_t first, uint32_t count) {
        for (uint32_t i = first; i < first + count && !found; ++i) {
            ++tests;
            const Part& q = parts_[i];
            found = occluded_curve(cr, q.segment(normals_), q.ribbon != 0);
        }
        return found;
    });
    return found;
}

void CurveBvh::closest_stream(const Ray1* rays, std::size_t n, CurveHit* hits, uint32_t* ids,
                              uint8_t* found, uint64_t& tests) const {
    using namespace bvh_detail;
    using V = simd::FloatW<kWidth>;
    constexpr uint32_t kLanes = 8, kDone = kBvhEmpty;
    // A ray in flight: closest()'s walk state. Its stack is deep enough for the build's depth
    // bound (bvh_build.cpp) times the node width.
    struct Lane {
        BoxRay<kWidth> br;
        CurveRay cr;
        std::size_t ray;
        uint32_t ref, sp, best;
        float tcull;
        StackEntry stack[kStackSize];
    };
    std::vector<Lane> lanes(kLanes);
    std::size_t next = 0;
    uint32_t live = 0;
    // Starts the next usable ray in lane l; false when none is left.
    auto start = [&](Lane& l) {
        while (next < n) {
            const std::size_t i = next++;
            found[i] = 0;
            if (parts_.empty() || unusable_ray(rays[i])) continue;
            hits[i].t = std::min(hits[i].t, rays[i].tmax);
            l.br = BoxRay<kWidth>(rays[i]);
            l.cr = CurveRay(rays[i]);
            l.ray = i;
            l.ref = root_;
            l.sp = 0;
            l.best = UINT32_MAX;
            l.tcull = hits[i].t < kInf ? hits[i].t * kBvhCullScale : hits[i].t;
            return true;
        }
        return false;
    };
    auto finish = [&](Lane& l) {
        if (l.best == UINT32_MAX) return;
        const uint32_t k = parts_[l.best].index;
        CurveHit& h = hits[l.ray];
        h.u = u0_[k] + part_du_ * h.u;
        ids[l.ray] = ids_[k];
        found[l.ray] = 1;
    };
    auto pop = [](Lane& l) {
        while (l.sp) {
            const StackEntry& e = l.stack[--l.sp];
            if (e.t <= l.tcull) return e.ref;
        }
        return kDone;
    };
    bool active[kLanes];
    for (uint32_t k = 0; k < kLanes; ++k) {
        active[k] = start(lanes[k]);
        if (active[k]) ++live;
    }
    // One step of each live lane in turn: a node's box test (its entered children prefetched)
    // or a leaf's parts, then the lane's next reference.
    while (live) {
        for (uint32_t k = 0; k < kLanes; ++k) {
            if (!active[k]) continue;
            Lane& l = lanes[k];
            if (!bvh_is_leaf(l.ref)) {
                const Node& node = nodes_[l.ref];
                V tnv;
                const uint32_t mask = l.br.test(node, l.tcull, tnv);
                if (mask) {
                    alignas(64) float tn[kWidth];
                    tnv.store_aligned(tn);
                    prefetch_children(node, mask);
                    l.ref = order_children(node, mask, tn, l.stack, l.sp);
                    continue;
                }
            } else {
                const uint32_t first = bvh_leaf_first(l.ref), count = bvh_leaf_blocks(l.ref);
                CurveHit& h = hits[l.ray];
                for (uint32_t i = first; i < first + count; ++i) {
                    ++tests;
                    if (test_part(l.cr, i, h)) {
                        l.best = i;
                        l.tcull = h.t * kBvhCullScale;
                    }
                }
            }
            l.ref = pop(l);
            if (l.ref != kDone) continue;
            finish(l);
            if (!start(l)) {
                active[k] = false;
                --live;
            }
        }
    }
}

std::size_t CurveBvh::memory_bytes() const {
    return nodes_.size() * sizeof(Node) + parts_.size() * sizeof(Part) +
           (normals_.size() + u0_.size()) * sizeof(float) + ids_.size() * sizeof(uint32_t);
}

}  // namespace foton::kern
