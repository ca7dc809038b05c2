// Christensen's precomputed irradiance in the photon map: estimated at every n-th photon,
// kept in a kd-tree of its own, looked up by position and normal.
#include <cmath>

#include "engine/core/cluster.h"
#include "photon_direction.h"
#include "photon_map.h"

namespace foton {

void PhotonMap::precompute_irradiance(uint32_t stride, const EstimateParams& params,
                                      const ParallelFor& parallel_for, const Cluster* cluster) {
    const std::size_t m = stride == 0 ? 0 : (size() + stride - 1) / stride;
    irr_x_.resize(m);
    irr_y_.resize(m);
    irr_z_.resize(m);
    irr_n_.resize(m);
    irr_e_.resize(m);
    for (std::size_t j = 0; j < m; ++j) {
        const std::size_t i = j * stride;
        irr_x_[j] = x_[i];
        irr_y_[j] = y_[i];
        irr_z_[j] = z_[i];
        irr_n_[j] = normal_[i];
    }
    // The estimates run in Morton order of their points, each parallel chunk as one batched
    // kNN: a chunk's queries are then neighbours and share the tree's nodes in cache. Every
    // estimate still lands at its own point, so the order changes nothing but the speed.
    const std::vector<uint32_t> order =
        kern::morton_order(irr_x_.data(), irr_y_.data(), irr_z_.data(), m);
    const uint32_t k = std::min(params.k, kMaxEstimate);
    auto body = [&](std::size_t begin, std::size_t end) {
        const std::size_t count = end - begin;
        std::vector<float> qx(count), qy(count), qz(count),
            max_d2(count, params.max_radius * params.max_radius);
        for (std::size_t t = 0; t < count; ++t) {
            const uint32_t j = order[begin + t];
            qx[t] = irr_x_[j];
            qy[t] = irr_y_[j];
            qz[t] = irr_z_[j];
        }
        kern::KnnBatchResult res;
        tree_.knn_batch(qx.data(), qy.data(), qz.data(), max_d2.data(), count, k, res);
        for (std::size_t t = 0; t < count; ++t) {
            const uint32_t j = order[begin + t];
            const std::size_t i = std::size_t(j) * stride;
            uint32_t* idx = res.index.data() + t * k;
            float* d2 = res.dist2.data() + t * k;
            float r = 0.f;
            const Vec3 n = normal(i);
            const uint32_t kept = accept(position(i), n, params, k, res.count[t], idx, d2, r);
            irr_e_[j] = irradiance_of(n, params, kept, idx, d2, r);
        }
    };
    // Across MPI ranks each estimates a share of the points; all get every estimate.
    const Cluster& ranks = cluster_or_solo(cluster);
    const Share mine = share_of(m, ranks);
    if (parallel_for)
        parallel_for(mine.size(),
                     [&](std::size_t b, std::size_t e) { body(mine.begin + b, mine.begin + e); });
    else
        body(mine.begin, mine.end);
    if (ranks.distributed()) {
        Bytes part;
        for (std::size_t t = mine.begin; t < mine.end; ++t) foton::pack(part, &irr_e_[order[t]], 1);
        std::size_t t = 0;
        for (const Bytes& b : ranks.all_gather(part))
            for (Unpacker in(b); !in.done(); ++t) in.read(&irr_e_[order[t]], 1);
    }
    irr_tree_.build(irr_x_.data(), irr_y_.data(), irr_z_.data(), m);
    if (compact_) {
        irr_rgbe_.resize(m);
        for (std::size_t j = 0; j < m; ++j) irr_rgbe_[j] = encode_rgbe(irr_e_[j]);
        std::vector<RGB>().swap(irr_e_);
    }
}

int PhotonMap::best_irradiance(const uint32_t* idx, const float* d2, uint32_t found,
                               const Vec3& n) const {
    int best = -1;
    float best_d2 = kInfinity;
    for (uint32_t i = 0; i < found; ++i) {
        // Normals agree within ~25 degrees (two-byte normals are good to about a degree).
        if (dot(decode_direction(irr_n_[idx[i]]), n) < 0.9f) continue;
        if (d2[i] < best_d2) {
            best_d2 = d2[i];
            best = int(idx[i]);
        }
    }
    return best;
}

bool PhotonMap::lookup_irradiance(const Vec3& p, const Vec3& n, float max_radius, RGB& e) const {
    uint32_t idx[kIrradianceCandidates];
    float d2[kIrradianceCandidates];
    const float q[3] = {p.x, p.y, p.z};
    const uint32_t found =
        irr_tree_.knn(q, max_radius * max_radius, kIrradianceCandidates, idx, d2);
    const int best = best_irradiance(idx, d2, found, n);
    if (best < 0) return false;
    e = irr(std::size_t(best));
    return true;
}

void PhotonMap::lookup_irradiance_batch(IrradianceQueries& q, std::vector<RGB>& e,
                                        std::vector<uint8_t>& found) const {
    const std::size_t n = q.size();
    irr_tree_.knn_batch(q.x.data(), q.y.data(), q.z.data(), q.max_d2.data(), n,
                        kIrradianceCandidates, q.knn);
    e.resize(n);
    found.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t row = i * kIrradianceCandidates;
        const int best = best_irradiance(q.knn.index.data() + row, q.knn.dist2.data() + row,
                                         q.knn.count[i], q.n[i]);
        found[i] = best >= 0;
        if (best >= 0) e[i] = irr(std::size_t(best));
    }
}

}  // namespace foton
