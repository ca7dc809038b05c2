#pragma once
// Which MPI rank renders which pixel, and the gather of per-pixel values to rank 0. A
// pixel's value is computed whole on the rank that owns it (all its samples, in the single
// process's order), so gathering copies it and the image equals one process's bit for bit.
#include <cstdint>
#include <vector>

#include "engine/core/cluster.h"

namespace foton {

// owner[pixel] = the rank that renders it; every rank computes the same table.
using PixelOwners = std::vector<int32_t>;

// Image rows dealt out in turn (row y to rank y mod N, cluster.h's dealt_to).
inline PixelOwners owners_by_row(int width, int height, int ranks) {
    PixelOwners o(std::size_t(width) * std::size_t(height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            o[std::size_t(y) * std::size_t(width) + x] = dealt_to(uint64_t(y), ranks);
    return o;
}

// Runs of `run` pixels in image order dealt out in turn (pixel p to rank (p / run) mod N).
inline PixelOwners owners_by_run(std::size_t pixels, std::size_t run, int ranks) {
    PixelOwners o(pixels);
    for (std::size_t p = 0; p < pixels; ++p) o[p] = dealt_to(uint64_t(p / run), ranks);
    return o;
}

// After this, rank 0's `values` holds every pixel's value from its owner (its own pixels
// untouched); the other ranks' are unchanged. T is trivially copyable. Collective.
template <class T>
void gather_to_root(const Cluster& cluster, const PixelOwners& owner, std::vector<T>& values) {
    if (!cluster.distributed()) return;
    Bytes mine;
    for (std::size_t p = 0; p < owner.size(); ++p)
        if (owner[p] == cluster.rank()) pack(mine, &values[p], 1);
    const std::vector<Bytes> parts = cluster.gather(mine);
    if (!cluster.root()) return;
    std::vector<Unpacker> from;
    for (const Bytes& b : parts) from.emplace_back(b);
    for (std::size_t p = 0; p < owner.size(); ++p)
        if (owner[p] != 0) from[std::size_t(owner[p])].read(&values[p], 1);
}

}  // namespace foton
