#include "light_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace foton {

namespace {

constexpr uint32_t kNoLeaf = 0xffffffffu;
// Deeper than this a node splits at the middle of its count, not by cost: keeps the depth
// bounded however the cost buckets fall.
constexpr int kMaxCostDepth = 48;
constexpr int kBuckets = 12;

float safe_acos(float c) {
    return std::acos(std::clamp(c, -1.f, 1.f));
}

// The angle between unit vectors, accurate near 0 and pi (acos is not).
float angle_between(const Vec3& a, const Vec3& b) {
    if (dot(a, b) < 0.f) return kPi - 2.f * std::asin(std::min(1.f, 0.5f * length(a + b)));
    return 2.f * std::asin(std::min(1.f, 0.5f * length(b - a)));
}

// v turned by `angle` about the unit axis k, k perpendicular to v (Rodrigues).
Vec3 rotate_perpendicular(const Vec3& v, const Vec3& k, float angle) {
    return v * std::cos(angle) + cross(k, v) * std::sin(angle);
}

// The smallest cone holding cones (a, cos_a) and (b, cos_b).
void cone_union(const Vec3& a, float cos_a, const Vec3& b, float cos_b, Vec3& axis, float& cos_o) {
    const float theta_a = safe_acos(cos_a), theta_b = safe_acos(cos_b);
    const float theta_d = angle_between(a, b);
    if (std::min(theta_d + theta_b, kPi) <= theta_a) {
        axis = a;
        cos_o = cos_a;
        return;
    }
    if (std::min(theta_d + theta_a, kPi) <= theta_b) {
        axis = b;
        cos_o = cos_b;
        return;
    }
    const float theta_o = 0.5f * (theta_a + theta_d + theta_b);
    const Vec3 k = cross(a, b);
    if (theta_o >= kPi || length_squared(k) == 0.f) {
        axis = a;
        cos_o = -1.f;
        return;
    }
    axis = normalize(rotate_perpendicular(a, normalize(k), theta_o - theta_a));
    cos_o = std::cos(theta_o);
}

// The orientation measure of a bound's cones (the solid angle its normals and emission
// spread over, weighted by the cosine): what a split's cost charges besides power and area.
float orientation_measure(const LightBounds& b) {
    const float theta_o = safe_acos(b.cos_o), theta_e = safe_acos(b.cos_e);
    const float theta_w = std::min(theta_o + theta_e, kPi);
    const float sin_o = std::sin(theta_o);
    return 2.f * kPi * (1.f - b.cos_o) +
           0.5f * kPi *
               (2.f * theta_w * sin_o - std::cos(theta_o - 2.f * theta_w) - 2.f * theta_o * sin_o +
                b.cos_o);
}

float surface_area(const Bounds3& b) {
    const Vec3 d = b.diagonal();
    return 2.f * (d.x * d.y + d.y * d.z + d.z * d.x);
}

// A split's cost (Conty Estevez and Kulla, sec. 4.4): power times orientation measure times
// area; `regular` stretches thin nodes' costs so they split across their long side.
float split_cost(const LightBounds& b, float regular) {
    if (b.phi == 0.f) return 0.f;
    return b.phi * orientation_measure(b) * surface_area(b.box) * regular;
}

}  // namespace

LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b) {
    if (a.phi == 0.f) return b;
    if (b.phi == 0.f) return a;
    LightBounds u;
    u.box = a.box;
    u.box.extend(b.box);
    cone_union(a.axis, a.cos_o, b.axis, b.cos_o, u.axis, u.cos_o);
    u.cos_e = std::min(a.cos_e, b.cos_e);
    u.phi = a.phi + b.phi;
    u.two_sided = a.two_sided || b.two_sided;
    return u;
}

void LightBvh::build(const std::vector<LightBounds>& bounds) {
    tree_.nodes.clear();
    leaf_of_.assign(bounds.size(), kNoLeaf);
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < bounds.size(); ++i)
        if (bounds[i].phi > 0.f) order.push_back(i);
    if (order.empty()) return;
    tree_.nodes.reserve(2 * order.size() * kern::LightTree::kFields);
    build_range(bounds, order.data(), order.data() + order.size(), 0, 0);
}

void LightBvh::put(uint32_t node, const LightBounds& b, uint32_t next, bool leaf, uint32_t parent) {
    using F = kern::LightTree;
    float* r = tree_.node(node);
    const Vec3 c = b.box.center();
    r[F::kCx] = c.x;
    r[F::kCy] = c.y;
    r[F::kCz] = c.z;
    r[F::kRadius2] = 0.25f * length_squared(b.box.diagonal());
    r[F::kRadius] = std::sqrt(r[F::kRadius2]);
    r[F::kAx] = b.axis.x;
    r[F::kAy] = b.axis.y;
    r[F::kAz] = b.axis.z;
    r[F::kCosO] = b.cos_o;
    r[F::kSinO] = std::sqrt(std::max(0.f, 1.f - b.cos_o * b.cos_o));
    r[F::kCosE] = b.cos_e;
    r[F::kPhi] = b.phi;
    r[F::kTwoSided] = b.two_sided ? 1.f : 0.f;
    r[F::kNext] = float(next);
    r[F::kLeaf] = leaf ? 1.f : 0.f;
    r[F::kParent] = float(parent);
}

uint32_t LightBvh::build_range(const std::vector<LightBounds>& bounds, uint32_t* first,
                               uint32_t* last, uint32_t parent, int depth) {
    const uint32_t self = uint32_t(tree_.size());
    tree_.nodes.resize(tree_.nodes.size() + kern::LightTree::kFields);
    if (self == 0) parent = 0;
    if (last - first == 1) {
        put(self, bounds[*first], *first, true, parent);
        leaf_of_[*first] = self;
        return self;
    }
    LightBounds all;
    Bounds3 centres;
    for (const uint32_t* i = first; i != last; ++i) {
        all = light_bounds_union(all, bounds[*i]);
        centres.extend(bounds[*i].box.center());
    }
    // The cheapest of the bucket boundaries on the three axes.
    float best_cost = std::numeric_limits<float>::infinity();
    int best_axis = -1, best_bucket = 0;
    const Vec3 diag = all.box.diagonal();
    const float longest = std::max({diag.x, diag.y, diag.z});
    const Vec3 extent = centres.diagonal();
    if (depth < kMaxCostDepth) {
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0.f)) continue;
            std::array<LightBounds, kBuckets> bucket{};
            auto bucket_of = [&](uint32_t i) {
                const float t = (bounds[i].box.center()[axis] - centres.lo[axis]) / extent[axis];
                return std::min(kBuckets - 1, int(t * kBuckets));
            };
            for (const uint32_t* i = first; i != last; ++i)
                bucket[std::size_t(bucket_of(*i))] =
                    light_bounds_union(bucket[std::size_t(bucket_of(*i))], bounds[*i]);
            const float regular = diag[axis] > 0.f ? longest / diag[axis] : 1.f;
            for (int split = 0; split < kBuckets - 1; ++split) {
                LightBounds below, above;
                for (int k = 0; k <= split; ++k) below = light_bounds_union(below, bucket[k]);
                for (int k = split + 1; k < kBuckets; ++k)
                    above = light_bounds_union(above, bucket[k]);
                if (below.phi == 0.f || above.phi == 0.f) continue;
                const float cost = split_cost(below, regular) + split_cost(above, regular);
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_bucket = split;
                }
            }
        }
    }
    uint32_t* middle = nullptr;
    if (best_axis >= 0) {
        const int axis = best_axis;
        middle = std::partition(first, last, [&](uint32_t i) {
            const float t = (bounds[i].box.center()[axis] - centres.lo[axis]) / extent[axis];
            return std::min(kBuckets - 1, int(t * kBuckets)) <= best_bucket;
        });
    }
    if (middle == nullptr || middle == first || middle == last) {
        // No boundary parts them (one centre, or too deep): halve the count along the
        // centres' longest axis.
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        middle = first + (last - first) / 2;
        std::nth_element(first, middle, last, [&](uint32_t a, uint32_t b) {
            return bounds[a].box.center()[axis] < bounds[b].box.center()[axis];
        });
    }
    build_range(bounds, first, middle, self, depth + 1);
    const uint32_t second = build_range(bounds, middle, last, self, depth + 1);
    put(self, all, second, false, parent);
    return self;
}

bool LightBvh::sample(float u, const Vec3& p, const Vec3& n, uint32_t& prim, float& pmf) const {
    const float pp[3] = {p.x, p.y, p.z}, nn[3] = {n.x, n.y, n.z};
    return kern::pick_light(tree_, u, pp, nn, prim, pmf);
}

float LightBvh::pmf(uint32_t prim, const Vec3& p, const Vec3& n) const {
    if (prim >= leaf_of_.size() || leaf_of_[prim] == kNoLeaf) return 0.f;
    const float pp[3] = {p.x, p.y, p.z}, nn[3] = {n.x, n.y, n.z};
    return kern::light_pmf(tree_, leaf_of_[prim], pp, nn);
}

}  // namespace foton
