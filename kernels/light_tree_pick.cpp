// pick_lights: W shading points descend the light BVH together, each lane at its own node.
// Every level gathers both children's records for the live lanes and evaluates their
// importances at once; lanes that reached a leaf (or found no light) stay masked until the
// deepest lane is down. The operations are light_tree_scalar.cpp's, in its order: each branch
// of the scalar code is computed for all lanes and selected, which changes no lane's result.
#include "light_tree.h"
#include "simd.h"

namespace foton::kern {

namespace {

using simd::FloatV;
using simd::MaskV;
using IntV = xsimd::batch<int32_t, simd::Arch>;
constexpr std::size_t W = simd::kWidth;

struct Receivers {
    FloatV px, py, pz, nx, ny, nz;
    MaskV has_n;
};

// light_importance for W nodes (node indices as exact floats).
FloatV importance(const LightTree& tree, const FloatV& node, const Receivers& q) {
    using F = LightTree;
    const IntV rec = simd::to_int(node) * IntV(int32_t(F::kFields));
    auto f = [&](uint32_t field) { return simd::gather(tree.nodes.data() + field, rec); };
    const FloatV zero(0.f), one(1.f);
    const FloatV tx = q.px - f(F::kCx), ty = q.py - f(F::kCy), tz = q.pz - f(F::kCz);
    const FloatV dist2 = tx * tx + ty * ty + tz * tz;
    const MaskV pos = dist2 > zero;
    const FloatV inv_dist = xsimd::select(pos, one / simd::vsqrt(dist2), zero);
    const FloatV r2 = f(F::kRadius2);
    const MaskV outside = dist2 > r2;
    const FloatV sin_b = xsimd::select(outside, simd::vmin(f(F::kRadius) * inv_dist, one), zero);
    const FloatV cos_b =
        xsimd::select(outside, simd::vsqrt(simd::vmax(one - sin_b * sin_b, zero)), FloatV(-1.f));
    FloatV cos_w =
        xsimd::select(pos, (f(F::kAx) * tx + f(F::kAy) * ty + f(F::kAz) * tz) * inv_dist, one);
    cos_w = xsimd::select(f(F::kTwoSided) != zero, xsimd::abs(cos_w), cos_w);
    const FloatV cos_o = f(F::kCosO), sin_o = f(F::kSinO);
    const FloatV sin_w = simd::vsqrt(simd::vmax(one - cos_w * cos_w, zero));
    const FloatV cos_wo = cos_w * cos_o + sin_w * sin_o;
    const FloatV sin_wo = sin_w * cos_o - cos_w * sin_o;
    const FloatV cos_t =
        xsimd::select((cos_w < cos_o) & (cos_wo < cos_b), cos_wo * cos_b + sin_wo * sin_b, one);
    const MaskV outside_cone = cos_t < f(F::kCosE);
    const FloatV d2 = simd::vmax(simd::vmax(dist2, r2 * FloatV(1.f / 16.f)), FloatV(1e-12f));
    FloatV imp = f(F::kPhi) * cos_t / d2;
    const FloatV cos_i =
        xsimd::select(pos, xsimd::abs(tx * q.nx + ty * q.ny + tz * q.nz) * inv_dist, one);
    const FloatV sin_i = simd::vsqrt(simd::vmax(one - cos_i * cos_i, zero));
    imp = xsimd::select(q.has_n & (cos_i < cos_b), imp * (cos_i * cos_b + sin_i * sin_b), imp);
    return xsimd::select(outside_cone, zero, simd::vmax(imp, zero));
}

}  // namespace

void pick_lights(const LightTree& tree, const LightQueries& q, std::size_t count) {
    using F = LightTree;
    // A lone light, or a tree past the float indices' range: the twin.
    if (tree.empty() || tree.node(0)[F::kLeaf] != 0.f || tree.size() >= F::kMaxNodes) {
        pick_lights_scalar(tree, q, count);
        return;
    }
    const FloatV zero(0.f), one(1.f), one_minus_epsilon(0x1.fffffep-1f);
    for (std::size_t i = 0; i < count; i += W) {
        Receivers r;
        r.px = FloatV::load_unaligned(q.px + i);
        r.py = FloatV::load_unaligned(q.py + i);
        r.pz = FloatV::load_unaligned(q.pz + i);
        r.nx = FloatV::load_unaligned(q.nx + i);
        r.ny = FloatV::load_unaligned(q.ny + i);
        r.nz = FloatV::load_unaligned(q.nz + i);
        r.has_n = (r.nx != zero) | (r.ny != zero) | (r.nz != zero);
        FloatV u = FloatV::load_unaligned(q.u + i);
        FloatV node = zero, pmf = one;
        MaskV alive(true), failed(false);
        while (xsimd::any(alive)) {
            // Lanes done sit at the root, whose children are nodes, so every gather reads
            // inside the tree.
            const FloatV at = xsimd::select(alive, node, zero);
            const IntV rec = simd::to_int(at) * IntV(int32_t(F::kFields));
            const FloatV a = at + one;
            const FloatV b = simd::gather(tree.nodes.data() + F::kNext, rec);
            const FloatV ia = importance(tree, a, r);
            const FloatV ib = importance(tree, b, r);
            const MaskV dead = (ia == zero) & (ib == zero);
            const FloatV pa = ia / (ia + ib);
            const FloatV pb = one - pa;
            const MaskV go_a = u < pa;
            const MaskV step = alive & !dead;
            u = xsimd::select(step,
                              xsimd::select(go_a, simd::vmin(u / pa, one_minus_epsilon),
                                            simd::vmin((u - pa) / pb, one_minus_epsilon)),
                              u);
            pmf = xsimd::select(step, xsimd::select(go_a, pmf * pa, pmf * pb), pmf);
            node = xsimd::select(step, xsimd::select(go_a, a, b), node);
            failed = failed | (alive & dead);
            const IntV next = simd::to_int(node) * IntV(int32_t(F::kFields));
            const FloatV leaf = simd::gather(tree.nodes.data() + F::kLeaf, next);
            alive = step & (leaf == zero);
        }
        const IntV rec = simd::to_int(node) * IntV(int32_t(F::kFields));
        const FloatV light = simd::gather(tree.nodes.data() + F::kNext, rec);
        pmf = xsimd::select(failed | !(pmf > zero), zero, pmf);
        pmf.store_unaligned(q.pmf + i);
        alignas(64) float lights[W];
        light.store_aligned(lights);
        for (std::size_t k = 0; k < W; ++k)
            q.light[i + k] = q.pmf[i + k] > 0.f ? uint32_t(lights[k]) : 0u;
    }
}

}  // namespace foton::kern
