#include "light_bvh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include <tbb/parallel_invoke.h>

namespace foton {

namespace {

constexpr uint32_t kNoLeaf = 0xffffffffu;
// Deeper than this a node splits at the middle of its count, not by cost: keeps the depth
// bounded however the cost buckets fall.
constexpr int kMaxCostDepth = 48;
constexpr int kBuckets = 12;
// Subtrees of more lights than this build in parallel.
constexpr std::ptrdiff_t kParallelLights = 16384;

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

namespace {

// A bucket of lights as the split cost sees it: box, power, cos_e and sidedness exactly, the
// cone around the sum of the lights' axes, each light's own cone inside it. A bounding cone,
// not the smallest one: a few multiplies per light where cone_union's inverse trigonometry
// made the build of an emissive mesh of 871,000 triangles take 9 s.
struct Bucket {
    Bounds3 box;
    Vec3 axis_sum;
    float phi = 0.f, cos_e = 1.f, cos_o = 1.f;
    bool two_sided = false;
    uint32_t count = 0;
    LightBounds bounds() const {
        LightBounds b;
        if (count == 0) return b;
        b.box = box;
        const float len = length(axis_sum);
        b.axis = len > 0.f ? axis_sum / len : Vec3{0.f, 0.f, 1.f};
        b.cos_o = len > 0.f ? cos_o : -1.f;
        b.cos_e = cos_e;
        b.phi = phi;
        b.two_sided = two_sided;
        return b;
    }
};

// cos(angle between unit a and b + theta) for theta's cosine and sine, -1 past pi.
float cos_angle_plus(const Vec3& a, const Vec3& b, float cos_t, float sin_t) {
    const float d = std::clamp(dot(a, b), -1.f, 1.f);
    const float sd = std::sqrt(std::max(0.f, 1.f - d * d));
    if (sd * cos_t + d * sin_t < 0.f) return -1.f;  // the sum passed pi
    return d * cos_t - sd * sin_t;
}

}  // namespace

struct LightBvh::Build {
    const std::vector<LightBounds>& bounds;
    std::vector<Vec3> centre;
    std::vector<float> sin_o;
    std::vector<uint8_t> bucket_of;
};

void LightBvh::build(const std::vector<LightBounds>& bounds) {
    tree_.nodes.clear();
    leaf_of_.assign(bounds.size(), kNoLeaf);
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < bounds.size(); ++i)
        if (bounds[i].phi > 0.f) order.push_back(i);
    if (order.empty()) return;
    Build b{bounds, {}, {}, {}};
    b.centre.resize(bounds.size());
    b.sin_o.resize(bounds.size());
    b.bucket_of.resize(bounds.size());
    for (std::size_t i = 0; i < bounds.size(); ++i) {
        b.centre[i] = bounds[i].box.center();
        b.sin_o[i] = std::sqrt(std::max(0.f, 1.f - bounds[i].cos_o * bounds[i].cos_o));
    }
    // 2 n - 1 nodes, each subtree at a range of its own (the left child follows its parent,
    // the right one after the left subtree's 2 n_left - 1 nodes): large subtrees build in
    // parallel and the tree is the same on any number of threads.
    tree_.nodes.assign((2 * order.size() - 1) * kern::LightTree::kFields, 0.f);
    build_range(b, order.data(), order.data() + order.size(), 0, 0, 0);
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

LightBounds LightBvh::build_range(Build& b, uint32_t* first, uint32_t* last, uint32_t parent,
                                  int depth, uint32_t self) {
    const std::vector<LightBounds>& bounds = b.bounds;
    if (last - first == 1) {
        put(self, bounds[*first], *first, true, parent);
        leaf_of_[*first] = self;
        return bounds[*first];
    }
    Bounds3 box, centres;
    for (const uint32_t* i = first; i != last; ++i) {
        box.extend(bounds[*i].box);
        centres.extend(b.centre[*i]);
    }
    // The cheapest of the bucket boundaries on the three axes.
    float best_cost = std::numeric_limits<float>::infinity();
    int best_axis = -1, best_bucket = 0;
    const Vec3 diag = box.diagonal();
    const float longest = std::max({diag.x, diag.y, diag.z});
    const Vec3 extent = centres.diagonal();
    const Vec3 scale{float(kBuckets) / extent.x, float(kBuckets) / extent.y,
                     float(kBuckets) / extent.z};
    auto bucket_index = [&](uint32_t i, int axis) {
        return std::min(kBuckets - 1, int((b.centre[i][axis] - centres.lo[axis]) * scale[axis]));
    };
    if (depth < kMaxCostDepth) {
        for (int axis = 0; axis < 3; ++axis) {
            if (!(extent[axis] > 0.f)) continue;
            std::array<Bucket, kBuckets> bucket{};
            for (const uint32_t* i = first; i != last; ++i) {
                const int k = bucket_index(*i, axis);
                b.bucket_of[*i] = uint8_t(k);
                Bucket& bk = bucket[std::size_t(k)];
                const LightBounds& l = bounds[*i];
                bk.box.extend(l.box);
                bk.axis_sum = bk.axis_sum + l.axis;
                bk.phi += l.phi;
                bk.cos_e = std::min(bk.cos_e, l.cos_e);
                bk.two_sided = bk.two_sided || l.two_sided;
                ++bk.count;
            }
            // Each light's cone inside its bucket's: the widest angle to the bucket's axis.
            std::array<Vec3, kBuckets> axis_of;
            for (int k = 0; k < kBuckets; ++k)
                axis_of[std::size_t(k)] = bucket[std::size_t(k)].bounds().axis;
            for (const uint32_t* i = first; i != last; ++i) {
                Bucket& bk = bucket[b.bucket_of[*i]];
                bk.cos_o =
                    std::min(bk.cos_o, cos_angle_plus(axis_of[b.bucket_of[*i]], bounds[*i].axis,
                                                      bounds[*i].cos_o, b.sin_o[*i]));
            }
            // Costs of every boundary from the running unions below and above it.
            std::array<LightBounds, kBuckets> below, above;
            LightBounds acc;
            for (int k = 0; k < kBuckets; ++k)
                below[std::size_t(k)] = acc =
                    light_bounds_union(acc, bucket[std::size_t(k)].bounds());
            acc = LightBounds{};
            for (int k = kBuckets - 1; k >= 0; --k)
                above[std::size_t(k)] = acc =
                    light_bounds_union(acc, bucket[std::size_t(k)].bounds());
            const float regular = diag[axis] > 0.f ? longest / diag[axis] : 1.f;
            for (int split = 0; split < kBuckets - 1; ++split) {
                // Past an empty bucket the boundary parts the lights as the one before it.
                if (bucket[std::size_t(split)].count == 0) continue;
                const LightBounds& lo = below[std::size_t(split)];
                const LightBounds& hi = above[std::size_t(split + 1)];
                if (lo.phi == 0.f || hi.phi == 0.f) continue;
                const float cost = split_cost(lo, regular) + split_cost(hi, regular);
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
        middle = std::partition(first, last,
                                [&](uint32_t i) { return bucket_index(i, axis) <= best_bucket; });
    }
    if (middle == nullptr || middle == first || middle == last) {
        // No boundary parts them (one centre, or too deep): halve the count along the
        // centres' longest axis.
        const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                         : extent.y >= extent.z                       ? 1
                                                                      : 2;
        middle = first + (last - first) / 2;
        std::nth_element(first, middle, last, [&](uint32_t x, uint32_t y) {
            return b.centre[x][axis] < b.centre[y][axis];
        });
    }
    // The node's bound is its children's, exactly (cone_union once per node, bottom-up).
    const uint32_t left = self + 1, right = self + 2 * uint32_t(middle - first);
    LightBounds lb, rb;
    auto build_left = [&] { lb = build_range(b, first, middle, self, depth + 1, left); };
    auto build_right = [&] { rb = build_range(b, middle, last, self, depth + 1, right); };
    if (last - first > kParallelLights) {
        tbb::parallel_invoke(build_left, build_right);
    } else {
        build_left();
        build_right();
    }
    const LightBounds all = light_bounds_union(lb, rb);
    put(self, all, right, false, parent);
    return all;
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
