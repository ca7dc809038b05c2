#pragma once
// Reverse photon mapping (Havran, Herzog and Seidel 2005; the photon-mapping thesis' 6.7) for
// final gathering: instead of one kNN search among the photons per gather hit, the gather hits
// of a batch go into a kd-tree of their own (the "reverse photon map") and every photon near
// the batch looks up the hits within the estimate's radius. Each hit then holds the photons of
// a fixed-radius estimate, handed to the same radiance estimate as the forward search's
// (PhotonMap::radiance_from), so the two give the same image up to the summation order and
// photons at the radius' rounding edge; with k reached, the k nearest are kept, as forward.
// It pays when gather hits far outnumber the photons that reach them (many gather rays).
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/transport/photon/photon_map.h"
#include "kernels/point_kdtree.h"

namespace foton {

struct ReversePhotons {
    kern::PointKdTree hits;
    struct Pair {
        uint32_t query, photon;
        float d2;
    };
    std::vector<Pair> pairs;
    std::vector<uint32_t> idx;
    std::vector<float> d2;
    std::vector<uint32_t> heap_idx, heap_count;  // k nearest per hit (k <= 256)
    std::vector<float> heap_d2;
};

// For each query q < n at (x, y, z)[q]: the photons of `map` within params.max_radius (the k
// nearest of them when there are more), farthest first, as estimate(q, count, index, d2).
// Queries without photons are not reported. Returns the photons visited.
uint64_t reverse_gather(
    const PhotonMap& map, const float* x, const float* y, const float* z, std::size_t n,
    const EstimateParams& params, ReversePhotons& ws,
    const std::function<void(std::size_t, uint32_t, uint32_t*, float*)>& estimate);

}  // namespace foton
