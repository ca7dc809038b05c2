#pragma once
// The light BVH (engine/scene/light_bvh.h builds it) as its descent kernel reads it, and the
// descent: from a shading point, one child per level in proportion to an importance that no
// light under the child can much exceed (Conty Estevez and Kulla 2018), down to one light.
//
// Each node is one 64-byte record of 16 floats (a cache line; indices are floats too, exact
// below 2^24, so the SIMD descent gathers every field alike). pick_lights runs W shading
// points at a time; pick_light is its scalar twin for one point, and the two do the same IEEE
// operations in the same order, so their picks and probabilities agree bit for bit.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace foton::kern {

struct LightTree {
    enum Field : uint32_t {
        kCx,  // centre of the box's bounding sphere
        kCy,
        kCz,
        kRadius2,  // its radius, squared and as is
        kRadius,
        kAx,  // the emission cone's axis
        kAy,
        kAz,
        kCosO,  // its half-angle's cosine and sine (-1, 0: every direction)
        kSinO,
        kCosE,      // cosine of the angle past the cone light still leaves at
        kPhi,       // power
        kTwoSided,  // 1: emits on both sides of its normals
        kNext,      // inner node: its second child (the first follows it); leaf: the light
        kLeaf,      // 1 at a leaf
        kParent,    // the root's is itself
        kFields
    };
    // Node indices are stored as floats: exact to here.
    static constexpr uint32_t kMaxNodes = 1u << 24;
    std::vector<float> nodes;  // kFields per node, the root first

    std::size_t size() const { return nodes.size() / kFields; }
    bool empty() const { return nodes.empty(); }
    const float* node(uint32_t i) const { return nodes.data() + std::size_t(i) * kFields; }
    float* node(uint32_t i) { return nodes.data() + std::size_t(i) * kFields; }
};

// What the light under `node` can send to point p with normal n (n = 0: a point with no
// surface, no receiver cosine): power over squared distance, times the cosine of the
// smallest angle between the emission cone and the way to p, times the receiver's cosine,
// both angles reduced by what the node's bounding sphere subtends. 0 only where no light
// under the node can reach p.
float light_importance(const LightTree& tree, uint32_t node, const float p[3], const float n[3]);

// One shading point: a light (the leaf's kNext) with probability pmf, the product of the
// descent's choices; u (in [0, 1)) steers the descent and is reused at each level. False when
// the descent meets a node whose children both have importance 0.
bool pick_light(const LightTree& tree, float u, const float p[3], const float n[3], uint32_t& light,
                float& pmf);

// The probability that pick_light(., p, n) ends at `leaf` (a node index), multiplied in the
// order the descent multiplies it, so the two are the same float.
float light_pmf(const LightTree& tree, uint32_t leaf, const float p[3], const float n[3]);

// Many shading points, structure of arrays (count of them; the arrays are read and written
// up to count rounded up to the SIMD width): pmf[i] = 0 where no light was picked.
struct LightQueries {
    const float *px, *py, *pz, *nx, *ny, *nz, *u;
    uint32_t* light;
    float* pmf;
};
void pick_lights(const LightTree& tree, const LightQueries& q, std::size_t count);
void pick_lights_scalar(const LightTree& tree, const LightQueries& q, std::size_t count);

}  // namespace foton::kern
