#pragma once
// Packing a collapsed wide tree (bvh_build.h's WideTree) into WideNode rows: every node's
// child boxes padded (pad_box) into its SoA rows, empty slots given inverted infinite boxes, an
// inner child its node index; a leaf child's reference comes from the caller, which packs the
// leaf's primitives its own way (triangle blocks, curve parts), in the tree's order.
#include <cstdint>

#include "bvh_build.h"
#include "bvh_node.h"

namespace foton::kern {

// nodes must hold wide.nodes.size() nodes. leaf(child) packs a leaf and returns its reference.
template <std::size_t N, class Nodes, class Leaf>
void pack_wide_nodes(const WideTree& wide, Nodes& nodes, Leaf&& leaf) {
    for (std::size_t w = 0; w < wide.nodes.size(); ++w) {
        WideNode<N>& n = nodes[w];
        for (std::size_t c = 0; c < N; ++c) {
            for (int a = 0; a < 3; ++a) {
                n.bounds[2 * a][c] = kInf;
                n.bounds[2 * a + 1][c] = -kInf;
            }
            n.child[c] = 0;
        }
        const auto& kids = wide.nodes[w];
        for (std::size_t c = 0; c < kids.size(); ++c) {
            const WideChild& k = kids[c];
            float lo[3] = {k.lo[0], k.lo[1], k.lo[2]}, hi[3] = {k.hi[0], k.hi[1], k.hi[2]};
            pad_box(lo, hi);
            for (int a = 0; a < 3; ++a) {
                n.bounds[2 * a][c] = lo[a];
                n.bounds[2 * a + 1][c] = hi[a];
            }
            n.child[c] = k.leaf ? leaf(k) : k.index;
        }
    }
}

}  // namespace foton::kern
