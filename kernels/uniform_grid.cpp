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
    blocks_.clear();
    cell_begin_.clear();
    mailbox_ = params.mailbox;
    references_ = 0;
    float lo[3] = {kInf, kInf, kInf}, hi[3] = {-kInf, -kInf, -kInf};
    for (std::size_t t = 0; t < n; ++t)
        for (int k = 0; k < 3; ++k) {
            const float* p = positions + 3 * indices[3 * t + k];
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], p[a]);
                hi[a] = std::max(hi[a], p[a]);
            }
        }
    if (n == 0) {
        for (int a = 0; a < 3; ++a) lo[a] = hi[a] = 0.f;
    }
    frame_ = GridFrame::fit(lo, hi, double(params.cells_per_triangle) * double(n), params.max_res);
    const uint32_t ncells = frame_.num_cells();

    // Each triangle goes into every cell its (slightly widened) bounding box overlaps.
    std::vector<CellRange> ranges(n);
    std::vector<uint32_t> count(ncells + 1, 0);
    for (std::size_t t = 0; t < n; ++t) {
        float tlo[3] = {kInf, kInf, kInf}, thi[3] = {-kInf, -kInf, -kInf};
        for (int k = 0; k < 3; ++k) {
            const float* p = positions + 3 * indices[3 * t + k];
            for (int a = 0; a < 3; ++a) {
                tlo[a] = std::min(tlo[a], p[a]);
                thi[a] = std::max(thi[a], p[a]);
            }
        }
        CellRange& cr = ranges[t];
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
    for (std::size_t t = 0; t < n; ++t) {
        const CellRange& cr = ranges[t];
        for (int z = cr.lo[2]; z <= cr.hi[2]; ++z)
            for (int y = cr.lo[1]; y <= cr.hi[1]; ++y)
                for (int x = cr.lo[0]; x <= cr.hi[0]; ++x)
                    refs[fill[frame_.index(x, y, z)]++] = uint32_t(t);
    }
    // Re-pack each cell's triangles into SIMD blocks.
    cell_begin_.resize(ncells + 1);
    std::size_t total_blocks = 0;
    for (uint32_t c = 0; c < ncells; ++c)
        total_blocks += (count[c + 1] - count[c] + kBlockWidth - 1) / kBlockWidth;
    blocks_.reserve(total_blocks);
    for (uint32_t c = 0; c < ncells; ++c) {
        cell_begin_[c] = uint32_t(blocks_.size());
        pack_triangle_blocks(positions, indices, refs.data() + count[c], count[c + 1] - count[c],
                             blocks_);
    }
    cell_begin_[ncells] = uint32_t(blocks_.size());
}

bool UniformGrid::intersect(const Ray1& r, TriHit& hit, GridCounters* counters) const {
    if (blocks_.empty()) return false;
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
    if (blocks_.empty()) return false;
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
