#pragma once
// The triangles a BVH is built over: one or more meshes, each xyz vertex positions and three
// indices per triangle. A triangle's id is its index in the concatenation of the sources.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace foton::kern {

struct TriangleSource {
    const float* positions = nullptr;
    const uint32_t* indices = nullptr;
    std::size_t count = 0;
};

// From a triangle id to its source, its indices and its corners.
class SourceIds {
  public:
    SourceIds(const TriangleSource* sources, std::size_t num_sources)
        : sources_(sources), first_(num_sources + 1, 0) {
        for (std::size_t s = 0; s < num_sources; ++s) first_[s + 1] = first_[s] + sources[s].count;
    }
    std::size_t total() const { return first_.back(); }
    std::size_t first_of(std::size_t source) const { return first_[source]; }
    // The three vertex indices of triangle `id`.
    const uint32_t* indices(uint32_t id) const {
        const std::size_t s = source_of(id);
        return sources_[s].indices + 3 * (id - first_[s]);
    }
    void corners(uint32_t id, const float* p[3]) const {
        const std::size_t s = source_of(id);
        const uint32_t* ix = sources_[s].indices + 3 * (id - first_[s]);
        for (int k = 0; k < 3; ++k) p[k] = sources_[s].positions + 3 * std::size_t(ix[k]);
    }

  private:
    std::size_t source_of(uint32_t id) const {
        return std::size_t(std::upper_bound(first_.begin(), first_.end(), std::size_t(id)) -
                           first_.begin()) -
               1;
    }
    const TriangleSource* sources_;
    std::vector<std::size_t> first_;  // first_[s]: the first id of source s; then the total
};

}  // namespace foton::kern
