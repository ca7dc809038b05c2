#include "uniform_grid.h"

#include <algorithm>
#include <cmath>

#include "mailbox.h"

namespace foton::kern {

namespace {
struct CellRange {
    int lo[3], hi[3];
};
}  // namespace

void UniformGrid::build(const float* positions, const uint32_t* indices, std::size_t n,
                        const GridParams& params) {
    std::vector<uint32_t> all(n);
    for (std::size_t t = 0; t < n; ++t) all[t] = uint32_t(t);
    build_subset(positions, indices, all.data(), n, params, 0);
}

std::size_t UniformGrid::memory_bytes() const {
    std::size_t bytes = blocks_.size() * sizeof(TriangleBlock) +
                        cell_begin_.size() * sizeof(uint32_t) + cell_child_.size() * 4;
    for (const UniformGrid& c : children_) bytes += c.memory_bytes();
    return bytes;
}

std::size_t UniformGrid::num_blocks() const {
    std::size_t n = blocks_.size();
    for (const UniformGrid& c : children_) n += c.num_blocks();
    return n;
}

std::size_t UniformGrid::num_child_grids() const {
    std::size_t n = children_.size();
    for (const UniformGrid& c : children_) n += c.num_child_grids();
    return n;
}

void UniformGrid::build_subset(const float* positions, const uint32_t* indices,
                               const uint32_t* tris, std::size_t n, const GridParams& params,
                               int depth, const float* clip_lo, const float* clip_hi) {
    blocks_.clear();
    cell_begin_.clear();
    cell_child_.clear();
    children_.clear();
    mailbox_ = params.mailbox;
    references_ = 0;
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) {
            const float* p = positions + 3 * indices[3 * tris[i] + k];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
        }
    if (n == 0) {
        for (int a = 0; a < 3; ++a) lo[a] = hi[a] = 0.f;
    } else if (clip_lo && clip_hi) {
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::max(lo[a], clip_lo[a]);
            hi[a] = std::min(hi[a], clip_hi[a]);
        }
    }
    frame_ = GridFrame::fit(lo, hi, double(params.cells_per_triangle) * double(n), params.max_res);
    const uint32_t ncells = frame_.num_cells();

    // Each triangle goes into every cell its (slightly widened) bounding box overlaps.
    std::vector<CellRange> ranges(n);
    std::vector<uint32_t> count(ncells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t t = tris[i];
        float tlo[3] = {kInf, kInf, kInf}, thi[3] = {-kInf, -kInf, -kInf};
        for (int k = 0; k < 3; ++k) {
            const float* p = positions + 3 * indices[3 * t + k];
            for (int a = 0; a < 3; ++a) {
                tlo[a] = std::min(tlo[a], p[a]);
                thi[a] = std::max(thi[a], p[a]);
            }
        }
        CellRange& cr = ranges[i];
        for (int a = 0; a < 3; ++a) {
            const float eps = 1e-6f * frame_.cell[a];
            cr.lo[a] = frame_.cell_of(a, tlo[a] - eps);
            cr.hi[a] = frame_.cell_of(a, thi[a] + eps);
        }
        for (int z = cr.lo[2]; z <= cr.hi[2]; ++z)
            for (int y = cr.lo[1]; y <= cr.hi[1]; ++y)
                for (int x = cr.lo[0]; x <= cr.hi[0]; ++x) ++count[frame_.index(x, y, z) + 1];
    }
    // CSR of triangle references, triangles in index order within each cell.
    for (uint32_t c = 0; c < ncells; ++c) count[c + 1] += count[c];
    references_ = count[ncells];
    std::vector<uint32_t> refs(references_);
    std::vector<uint32_t> fill(count.begin(), count.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        const CellRange& cr = ranges[i];
        for (int z = cr.lo[2]; z <= cr.hi[2]; ++z)
            for (int y = cr.lo[1]; y <= cr.hi[1]; ++y)
                for (int x = cr.lo[0]; x <= cr.hi[0]; ++x)
                    refs[fill[frame_.index(x, y, z)]++] = tris[i];
    }
    // Overfull cells become nested grids over their own triangles.
    if (depth < params.nest_depth && ncells > 1) {
        uint32_t nonempty = 0;
        for (uint32_t c = 0; c < ncells; ++c) nonempty += count[c + 1] > count[c];
        const double mean = double(references_) / std::max(1u, nonempty);
        const double limit = std::max(double(params.nest_min_refs), params.nest_factor * mean);
        for (uint32_t c = 0; c < ncells; ++c) {
            const uint32_t m = count[c + 1] - count[c];
            if (double(m) <= limit) continue;
            if (cell_child_.empty()) cell_child_.assign(ncells, -1);
            cell_child_[c] = int32_t(children_.size());
            const int x = int(c % uint32_t(frame_.res[0]));
            const int y = int((c / uint32_t(frame_.res[0])) % uint32_t(frame_.res[1]));
            const int z = int(c / (uint32_t(frame_.res[0]) * uint32_t(frame_.res[1])));
            const int xyz[3] = {x, y, z};
            float cell_lo[3], cell_hi[3];
            for (int a = 0; a < 3; ++a) {
                cell_lo[a] = frame_.lo[a] + float(xyz[a]) * frame_.cell[a];
                cell_hi[a] = frame_.lo[a] + float(xyz[a] + 1) * frame_.cell[a];
            }
            children_.emplace_back();
            children_.back().build_subset(positions, indices, refs.data() + count[c], m, params,
                                          depth + 1, cell_lo, cell_hi);
        }
    }
    auto own = [&](uint32_t c) { return child_of(c) >= 0 ? 0u : count[c + 1] - count[c]; };
    // Re-pack each cell's triangles into SIMD blocks.
    cell_begin_.resize(ncells + 1);
    std::size_t total_blocks = 0;
    for (uint32_t c = 0; c < ncells; ++c) total_blocks += (own(c) + kBlockWidth - 1) / kBlockWidth;
    blocks_.reserve(total_blocks);
    for (uint32_t c = 0; c < ncells; ++c) {
        cell_begin_[c] = uint32_t(blocks_.size());
        pack_triangle_blocks(positions, indices, refs.data() + count[c], own(c), blocks_);
    }
    cell_begin_[ncells] = uint32_t(blocks_.size());
}

bool UniformGrid::intersect(const Ray1& r, TriHit& hit, GridCounters* counters) const {
    if (empty()) return false;
    if (r.tmax < hit.t) hit.t = r.tmax;
    bool found = false;
    if (frame_.num_cells() == 1) {
        // A one-cell grid (a quad, a small mesh) is just its block list: skip the DDA set-up.
        for (const TriangleBlock& b : blocks_) found |= intersect_block(r, b, hit);
        if (counters) counters->blocks += blocks_.size();
        return found;
    }
    if (mailbox_) return intersect_mailboxed(r, hit, counters);
    uint64_t cells = 0, tests = 0;
    dda_walk(frame_, r, hit.t, [&](uint32_t cell, float t_exit) {
        ++cells;
        if (const int32_t child = child_of(cell); child >= 0)
            found |= children_[child].intersect(r, hit, counters);
        const uint32_t b0 = cell_begin_[cell], b1 = cell_begin_[cell + 1];
        for (uint32_t b = b0; b < b1; ++b) found |= intersect_block(r, blocks_[b], hit);
        tests += b1 - b0;
        // A hit inside this cell cannot be beaten by a later cell.
        return found && hit.t <= t_exit;
    });
    if (counters) {
        counters->cells += cells;
        counters->blocks += tests;
    }
    return found;
}

bool UniformGrid::intersect_mailboxed(const Ray1& r, TriHit& hit, GridCounters* counters) const {
    // Skipping a triangle seen before is safe for the closest hit: if it was a hit, `hit`
    // already holds it or something closer, and hit.t only decreases.
    Mailbox<7> mailbox;
    bool found = false;
    uint64_t cells = 0, tests = 0, skips = 0;
    dda_walk(frame_, r, hit.t, [&](uint32_t cell, float t_exit) {
        ++cells;
        if (const int32_t child = child_of(cell); child >= 0)
            found |= children_[child].intersect(r, hit, counters);
        for (uint32_t b = cell_begin_[cell]; b < cell_begin_[cell + 1]; ++b) {
            const TriangleBlock& blk = blocks_[b];
            uint32_t lanes = 0;
            for (uint32_t l = 0; l < kBlockWidth && blk.id[l] != kInvalidId; ++l)
                if (!mailbox.seen(blk.id[l])) lanes |= 1u << l;
            if (lanes == 0) {
                ++skips;
                continue;
            }
            ++tests;
            found |= intersect_block(r, blk, hit, lanes);
        }
        return found && hit.t <= t_exit;
    });
    if (counters) {
        counters->cells += cells;
        counters->blocks += tests;
        counters->mailbox_skips += skips;
    }
    return found;
}

bool UniformGrid::occluded(const Ray1& r, GridCounters* counters) const {
    if (empty()) return false;
    bool hit = false;
    if (frame_.num_cells() == 1) {
        std::size_t tests = 0;
        for (std::size_t b = 0; b < blocks_.size() && !hit; ++b, ++tests)
            hit = occluded_block(r, blocks_[b]);
        if (counters) counters->blocks += tests;
        return hit;
    }
    uint64_t cells = 0, tests = 0;
    dda_walk(frame_, r, r.tmax, [&](uint32_t cell, float) {
        ++cells;
        if (const int32_t child = child_of(cell); child >= 0)
            hit = children_[child].occluded(r, counters);
        const uint32_t b0 = cell_begin_[cell], b1 = cell_begin_[cell + 1];
        for (uint32_t b = b0; b < b1 && !hit; ++b) {
            ++tests;
            hit = occluded_block(r, blocks_[b]);
        }
        return hit;
    });
    if (counters) {
        counters->cells += cells;
        counters->blocks += tests;
    }
    return hit;
}

}  // namespace foton::kern
