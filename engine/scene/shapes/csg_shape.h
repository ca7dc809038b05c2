#pragma once
// A scene object made of analytic shapes: one shape, or a constructive solid geometry tree
// (the photon thesis' B.2) of solids combined by union, intersection and difference. A ray
// meets a CSG tree by classifying its line: each solid's spans along it (inside stretches),
// combined node by node as sets, the result's span ends being the surface crossings.
#include <cstdint>
#include <string>
#include <vector>

#include "analytic_shape.h"

namespace foton {

enum class CsgOp : uint8_t { Leaf, Union, Intersection, Difference };

// The largest CSG tree: its solids (each gives at most two spans, so a tree's span lists hold
// at most 2 x this many).
inline constexpr std::size_t kMaxCsgSolids = 32;

struct CsgNode {
    CsgOp op = CsgOp::Leaf;
    uint32_t a = 0, b = 0;  // a leaf: a = the shape; otherwise the two operand nodes
};

// Hits on an AnalyticShape name their primitive as (shape << 3) | part.
inline uint32_t shape_prim(uint32_t shape, uint32_t part) {
    return (shape << 3) | part;
}
inline uint32_t prim_shape(uint32_t prim) {
    return prim >> 3;
}
inline uint8_t prim_part(uint32_t prim) {
    return uint8_t(prim & 7u);
}

class AnalyticShape {
  public:
    // One shape on its own.
    explicit AnalyticShape(const ShapePrimitive& s);
    // An empty CSG tree, filled bottom-up by leaf() and combine(); the last node made is the
    // root. finish() must be called before use.
    AnalyticShape() = default;
    uint32_t leaf(const ShapePrimitive& s);  // a solid; returns its node
    uint32_t combine(CsgOp op, uint32_t a, uint32_t b);
    void finish();
    // Places the whole shape by xf after its current placement (an object instance); false,
    // unchanged, when xf is singular.
    bool place(const Affine& xf);

    // The closest surface crossing with tmin < t < tmax: t and the primitive (shape << 3 |
    // part).
    bool closest(const Vec3& o, const Vec3& d, float tmin, float tmax, float& t,
                 uint32_t& prim) const;
    bool any(const Vec3& o, const Vec3& d, float tmin, float tmax) const;

    const std::vector<ShapePrimitive>& shapes() const { return shapes_; }
    // Whether shape i's outside faces into the result's inside (it is subtracted an odd
    // number of times): its normal is turned over.
    bool inverted(uint32_t i) const { return inverted_[i] != 0; }
    bool csg() const { return !nodes_.empty(); }
    bool solid() const { return csg() || shapes_[0].solid(); }
    const Bounds3& bounds() const { return bounds_; }
    std::string name;

  private:
    std::vector<ShapePrimitive> shapes_;
    std::vector<CsgNode> nodes_;  // empty for a single shape
    std::vector<uint8_t> inverted_;
    Bounds3 bounds_;
};

}  // namespace foton
