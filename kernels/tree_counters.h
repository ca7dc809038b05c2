#pragma once
// What a walk through a spatial subdivision of triangles (octree, kd-tree) did: the nodes it
// entered and the SIMD triangle blocks it tested, for the benchmark tables' per-ray columns.
#include <cstdint>

namespace foton::kern {

struct TreeCounters {
    uint64_t nodes = 0;   // nodes entered
    uint64_t blocks = 0;  // triangle blocks tested (each W ray/triangle tests)
};

}  // namespace foton::kern
