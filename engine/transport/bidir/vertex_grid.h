#pragma once
// A hashed uniform grid over the light vertices of an iteration, for vertex merging: cells of
// edge 2r, so the vertices within r of a point lie in the 2 x 2 x 2 cells nearest it. Built
// by a counting sort of the vertices by cell hash (the vertices' order inside a bucket is
// their order in the store, so queries are deterministic). Colliding cells share a bucket;
// a query visits each bucket once and checks the distance. The vertices' coordinates are
// copied in bucket order, so a bucket's check is one SIMD scan of sequential loads
// (kern::radius_scan; `simd` false: its scalar twin, which visits the same vertices).
#include <cstdint>
#include <vector>

#include "engine/core/math.h"
#include "kernels/radius_scan.h"
#include "light_vertices.h"

namespace foton {

class VertexGrid {
  public:
    void build(const LightVertices& v, float radius, bool simd = true);

    // Calls visit(i) for every vertex i within the radius of p.
    template <class Visit>
    void query(const Vec3& p, Visit&& visit) const {
        if (start_.empty()) return;
        const float gx = (p.x - lo_.x) * inv_cell_ - 0.5f, gy = (p.y - lo_.y) * inv_cell_ - 0.5f,
                    gz = (p.z - lo_.z) * inv_cell_ - 0.5f;
        const int x0 = int(std::floor(gx)), y0 = int(std::floor(gy)), z0 = int(std::floor(gz));
        uint32_t buckets[8];
        int n = 0;
        for (int dz = 0; dz < 2; ++dz)
            for (int dy = 0; dy < 2; ++dy)
                for (int dx = 0; dx < 2; ++dx) {
                    const uint32_t b = bucket(x0 + dx, y0 + dy, z0 + dz);
                    bool seen = false;
                    for (int k = 0; k < n; ++k) seen |= buckets[k] == b;
                    if (!seen) buckets[n++] = b;
                }
        const float q[3] = {p.x, p.y, p.z};
        auto hit = [&](uint32_t j) { visit(index_[j]); };
        for (int k = 0; k < n; ++k) {
            const uint32_t begin = start_[buckets[k]], end = start_[buckets[k] + 1];
            if (simd_)
                kern::radius_scan(x_.data(), y_.data(), z_.data(), begin, end, q, r2_, hit);
            else
                kern::radius_scan_scalar(x_.data(), y_.data(), z_.data(), begin, end, q, r2_, hit);
        }
    }

  private:
    uint32_t bucket(int x, int y, int z) const {
        const uint32_t h =
            (uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u);
        return h % uint32_t(start_.size() - 1);
    }
    Vec3 lo_;
    float inv_cell_ = 1.f, r2_ = 0.f;
    std::vector<uint32_t> start_, index_;
    // Bucket order: vertex index_[j]'s coordinates at j, padded by the SIMD width.
    std::vector<float> x_, y_, z_;
    bool simd_ = true;
};

}  // namespace foton
