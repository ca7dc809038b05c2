#include "reverse_photons.h"

#include <algorithm>

namespace foton {

uint64_t reverse_gather(
    const PhotonMap& map, const float* x, const float* y, const float* z, std::size_t n,
    const EstimateParams& params, ReversePhotons& ws,
    const std::function<void(std::size_t, uint32_t, uint32_t*, float*)>& estimate) {
    if (n == 0 || map.empty()) return 0;
    ws.hits.build(x, y, z, n);
    const float r = params.max_radius, r2 = r * r;
    // Only photons in the hits' box grown by the radius can reach one.
    float lo[3] = {kInfinity, kInfinity, kInfinity}, hi[3] = {-kInfinity, -kInfinity, -kInfinity};
    for (std::size_t q = 0; q < n; ++q) {
        const float p[3] = {x[q], y[q], z[q]};
        for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], p[a] - r), hi[a] = std::max(hi[a], p[a] + r);
    }
    ws.pairs.clear();
    uint64_t visited = 0;
    for (std::size_t j = 0; j < map.size(); ++j) {
        const Vec3 p = map.position(j);
        if (p.x < lo[0] || p.x > hi[0] || p.y < lo[1] || p.y > hi[1] || p.z < lo[2] || p.z > hi[2])
            continue;
        ++visited;
        const float pq[3] = {p.x, p.y, p.z};
        ws.hits.for_each_in_radius(pq, r2, [&](uint32_t q, float d2) {
            ws.pairs.push_back({q, uint32_t(j), d2});
        });
    }
    // Grouped by query, each group's photons in map order (a stable sort).
    std::stable_sort(ws.pairs.begin(), ws.pairs.end(),
                     [](const ReversePhotons::Pair& a, const ReversePhotons::Pair& b) {
                         return a.query < b.query;
                     });
    const uint32_t k = std::min(params.k, PhotonMap::kMaxEstimate);
    for (std::size_t begin = 0; begin < ws.pairs.size();) {
        std::size_t end = begin;
        while (end < ws.pairs.size() && ws.pairs[end].query == ws.pairs[begin].query) ++end;
        auto first = ws.pairs.begin() + std::ptrdiff_t(begin),
             last = ws.pairs.begin() + std::ptrdiff_t(end);
        auto nearer = [](const ReversePhotons::Pair& a, const ReversePhotons::Pair& b) {
            return a.d2 < b.d2 || (a.d2 == b.d2 && a.photon < b.photon);
        };
        if (end - begin > k) {
            std::nth_element(first, first + k, last, nearer);
            last = first + k;
        }
        // The farthest first (the forward search's max-heap order, which the disc reads).
        std::iter_swap(first, std::max_element(first, last, nearer));
        const auto count = uint32_t(last - first);
        ws.idx.resize(count);
        ws.d2.resize(count);
        for (uint32_t i = 0; i < count; ++i) {
            ws.idx[i] = first[i].photon;
            ws.d2[i] = first[i].d2;
        }
        estimate(ws.pairs[begin].query, count, ws.idx.data(), ws.d2.data());
        begin = end;
    }
    return visited;
}

}  // namespace foton
