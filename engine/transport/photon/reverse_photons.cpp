#include "reverse_photons.h"

#include <algorithm>

namespace foton {

namespace {
// Up to this k each hit keeps a heap of its own; above it (the whole radius) pairs are listed.
constexpr uint32_t kHeapLimit = 256;

// Inserts (id, d2) into the max-heap (idx, dist) of count entries, at most k.
void heap_insert(uint32_t* idx, float* dist, uint32_t& count, uint32_t k, uint32_t id, float d2) {
    uint32_t i;
    if (count < k) {
        i = count++;
        while (i > 0 && dist[(i - 1) / 2] < d2) {  // sift up
            idx[i] = idx[(i - 1) / 2];
            dist[i] = dist[(i - 1) / 2];
            i = (i - 1) / 2;
        }
    } else {
        if (!(d2 < dist[0])) return;
        i = 0;  // replace the farthest, sift down
        for (;;) {
            const uint32_t l = 2 * i + 1, r = l + 1;
            uint32_t m = i;
            float md = d2;
            if (l < count && dist[l] > md) m = l, md = dist[l];
            if (r < count && dist[r] > md) m = r;
            if (m == i) break;
            idx[i] = idx[m];
            dist[i] = dist[m];
            i = m;
        }
    }
    idx[i] = id;
    dist[i] = d2;
}
}  // namespace

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
    // Every photon in that box, against the hits within the radius: found(hit, photon, d2).
    uint64_t visited = 0;
    const auto each_pair = [&](auto&& found) {
        for (std::size_t j = 0; j < map.size(); ++j) {
            const Vec3 p = map.position(j);
            if (p.x < lo[0] || p.x > hi[0] || p.y < lo[1] || p.y > hi[1] || p.z < lo[2] ||
                p.z > hi[2])
                continue;
            ++visited;
            const float pq[3] = {p.x, p.y, p.z};
            ws.hits.for_each_in_radius(pq, r2,
                                       [&](uint32_t q, float d2) { found(q, uint32_t(j), d2); });
        }
    };
    const uint32_t k = std::min(params.k, PhotonMap::kMaxEstimate);
    if (k <= kHeapLimit) {
        // Each hit keeps its k nearest photons so far in a max-heap of its own (the farthest
        // at [0], as the forward search leaves them): no list of every pair, no sort.
        ws.heap_idx.resize(n * k);
        ws.heap_d2.resize(n * k);
        ws.heap_count.assign(n, 0);
        each_pair([&](uint32_t q, uint32_t j, float d2) {
            heap_insert(ws.heap_idx.data() + std::size_t(q) * k,
                        ws.heap_d2.data() + std::size_t(q) * k, ws.heap_count[q], k, j, d2);
        });
        for (std::size_t q = 0; q < n; ++q)
            if (ws.heap_count[q] > 0)
                estimate(q, ws.heap_count[q], ws.heap_idx.data() + q * k,
                         ws.heap_d2.data() + q * k);
        return visited;
    }
    ws.pairs.clear();
    each_pair([&](uint32_t q, uint32_t j, float d2) { ws.pairs.push_back({q, j, d2}); });
    // Grouped by query, each group's photons in map order (a stable sort).
    std::stable_sort(ws.pairs.begin(), ws.pairs.end(),
                     [](const ReversePhotons::Pair& a, const ReversePhotons::Pair& b) {
                         return a.query < b.query;
                     });
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
