// The light BVH's descent for one shading point: the reference pick_lights (light_tree_pick.cpp)
// is held to, and what the engine's scalar paths and MIS weights call.
#include <algorithm>
#include <array>
#include <cmath>

#include "light_tree.h"

namespace foton::kern {

namespace {
constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
}

float light_importance(const LightTree& tree, uint32_t node, const float p[3], const float n[3]) {
    using F = LightTree;
    const float* b = tree.node(node);
    const float tx = p[0] - b[F::kCx], ty = p[1] - b[F::kCy], tz = p[2] - b[F::kCz];
    const float dist2 = tx * tx + ty * ty + tz * tz;
    const float inv_dist = dist2 > 0.f ? 1.f / std::sqrt(dist2) : 0.f;
    // The half-angle the bounding sphere subtends at p; from inside it, everything.
    float cos_b = -1.f, sin_b = 0.f;
    if (dist2 > b[F::kRadius2]) {
        sin_b = std::min(1.f, b[F::kRadius] * inv_dist);
        cos_b = std::sqrt(std::max(0.f, 1.f - sin_b * sin_b));
    }
    // The smallest angle between an emitting direction and the way to p: past the cone
    // (theta_o), less what the sphere subtends (theta_b), clamped at 0.
    float cos_w = dist2 > 0.f ? (b[F::kAx] * tx + b[F::kAy] * ty + b[F::kAz] * tz) * inv_dist : 1.f;
    if (b[F::kTwoSided] != 0.f) cos_w = std::fabs(cos_w);
    const float cos_o = b[F::kCosO], sin_o = b[F::kSinO];
    float cos_t = 1.f;
    if (cos_w < cos_o) {
        const float sin_w = std::sqrt(std::max(0.f, 1.f - cos_w * cos_w));
        const float cos_wo = cos_w * cos_o + sin_w * sin_o;
        if (cos_wo < cos_b) {
            const float sin_wo = sin_w * cos_o - cos_w * sin_o;
            cos_t = cos_wo * cos_b + sin_wo * sin_b;
        }
    }
    // Strictly outside: a spot's cos_e is 1, and p inside its cone has cos_t = 1.
    if (cos_t < b[F::kCosE]) return 0.f;
    // Not below a quarter of the bound's radius, squared: a point at a node's centre must not
    // take every sample from its sibling. A clamp at the radius itself (our first version)
    // flattens the nodes of a large scene's upper levels over their whole extent: on the
    // many-lights plaza that starved the lamps over a point of ~13x the probability they
    // deserve (docs/shading.md).
    const float d2 = std::max(std::max(dist2, b[F::kRadius2] * (1.f / 16.f)), 1e-12f);
    float imp = b[F::kPhi] * cos_t / d2;
    if (n[0] != 0.f || n[1] != 0.f || n[2] != 0.f) {
        // The receiver's cosine, less theta_b.
        const float cos_i =
            dist2 > 0.f ? std::fabs(tx * n[0] + ty * n[1] + tz * n[2]) * inv_dist : 1.f;
        if (cos_i < cos_b) {
            const float sin_i = std::sqrt(std::max(0.f, 1.f - cos_i * cos_i));
            imp = imp * (cos_i * cos_b + sin_i * sin_b);
        }
    }
    return std::max(0.f, imp);
}

bool pick_light(const LightTree& tree, float u, const float p[3], const float n[3], uint32_t& light,
                float& pmf) {
    using F = LightTree;
    if (tree.empty()) return false;
    uint32_t node = 0;
    pmf = 1.f;
    // A lone light is its own root: its importance decides alone. Below, the child taken
    // always has importance > 0 (a child of importance 0 has probability 0).
    if (tree.node(0)[F::kLeaf] != 0.f && light_importance(tree, 0, p, n) == 0.f) return false;
    while (tree.node(node)[F::kLeaf] == 0.f) {
        const uint32_t a = node + 1, b = uint32_t(tree.node(node)[F::kNext]);
        const float ia = light_importance(tree, a, p, n);
        const float ib = light_importance(tree, b, p, n);
        if (ia == 0.f && ib == 0.f) return false;
        const float pa = ia / (ia + ib);
        const float pb = 1.f - pa;
        // The remaining bits of u choose below.
        if (u < pa) {
            u = std::min(u / pa, kOneMinusEpsilon);
            pmf = pmf * pa;
            node = a;
        } else {
            u = std::min((u - pa) / pb, kOneMinusEpsilon);
            pmf = pmf * pb;
            node = b;
        }
    }
    light = uint32_t(tree.node(node)[F::kNext]);
    return pmf > 0.f;
}

float light_pmf(const LightTree& tree, uint32_t leaf, const float p[3], const float n[3]) {
    using F = LightTree;
    if (light_importance(tree, leaf, p, n) == 0.f) return 0.f;
    // The trail from the root, multiplied in the descent's order. The build bounds the depth
    // (engine/scene/light_bvh.cpp); a deeper tree is not made.
    std::array<uint32_t, 128> trail;
    std::size_t depth = 0;
    for (uint32_t node = leaf; node != 0; node = uint32_t(tree.node(node)[F::kParent])) {
        if (depth == trail.size()) return 0.f;
        trail[depth++] = node;
    }
    float pmf = 1.f;
    while (depth > 0) {
        const uint32_t node = trail[--depth];
        const uint32_t parent = uint32_t(tree.node(node)[F::kParent]);
        const uint32_t a = parent + 1, b = uint32_t(tree.node(parent)[F::kNext]);
        const float ia = light_importance(tree, a, p, n);
        const float ib = light_importance(tree, b, p, n);
        if (ia == 0.f && ib == 0.f) return 0.f;
        const float pa = ia / (ia + ib);
        pmf = pmf * (node == a ? pa : 1.f - pa);
    }
    return pmf;
}

void pick_lights_scalar(const LightTree& tree, const LightQueries& q, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
        const float p[3] = {q.px[i], q.py[i], q.pz[i]}, n[3] = {q.nx[i], q.ny[i], q.nz[i]};
        uint32_t light = 0;
        float pmf = 0.f;
        if (!pick_light(tree, q.u[i], p, n, light, pmf)) {
            light = 0;
            pmf = 0.f;
        }
        q.light[i] = light;
        q.pmf[i] = pmf;
    }
}

}  // namespace foton::kern
