#pragma once
// A bounding volume hierarchy over the light sources, for choosing one light for next event
// estimation in a scene with many: Conty Estevez and Kulla, "Importance Sampling of Many
// Lights with Adaptive Tree Splitting" (2018), as pbrt-v4's BVHLightSampler uses it. Each
// node bounds its lights' positions (a box), the directions they emit along (a cone around
// an axis, widened by the angle past the normal they still emit at) and their power. From a
// shading point a descent picks one child at each node in proportion to an importance that
// no light under the node can exceed by much: power over squared distance, times the cosine
// of the smallest angle between the cone and the direction to the point, times the cosine
// at the receiver. A light's probability is the product of its trail's choices, which `pmf`
// recomputes by walking from the light's leaf up to the root.
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "kernels/light_tree.h"

namespace foton {

// What a subtree of lights can send towards a point.
struct LightBounds {
    Bounds3 box;         // the positions of its lights
    Vec3 axis{0, 0, 1};  // the centre of the cone of their normals (or spot axes)
    float cos_o = 1.f;   // cosine of the cone's half-angle (-1: every direction)
    float cos_e = 0.f;   // cosine of the angle past a normal that light still leaves at
    float phi = 0.f;     // power (luminance); 0 for an empty bound
    bool two_sided = false;
};

// The bound of both.
LightBounds light_bounds_union(const LightBounds& a, const LightBounds& b);

class LightBvh {
  public:
    // Builds over `bounds`; primitive i of the tree is bounds[i]. Bounds of zero power are
    // left out: such lights are never picked (pmf 0).
    void build(const std::vector<LightBounds>& bounds);
    bool empty() const { return tree_.empty(); }
    std::size_t node_count() const { return tree_.size(); }

    // Picks a primitive with probability proportional to the importances along the descent;
    // false when every light's importance at p is 0.
    bool sample(float u, const Vec3& p, const Vec3& n, uint32_t& prim, float& pmf) const;
    // The probability that sample(., p, n) returns prim.
    float pmf(uint32_t prim, const Vec3& p, const Vec3& n) const;

    // The tree as the descent kernels read it (kernels/light_tree.h).
    const kern::LightTree& tree() const { return tree_; }

  private:
    struct Build;  // the lights' centres, cone sines and bucket numbers while building
    // Builds the subtree of [first, last) at node `self`; returns its bound.
    LightBounds build_range(Build& b, uint32_t* first, uint32_t* last, uint32_t parent, int depth,
                            uint32_t self);
    void put(uint32_t node, const LightBounds& b, uint32_t next, bool leaf, uint32_t parent);

    kern::LightTree tree_;
    std::vector<uint32_t> leaf_of_;  // primitive -> its leaf, kNoLeaf when left out
};

}  // namespace foton
