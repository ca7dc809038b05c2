#include "cluster.h"

#include <stdexcept>

namespace foton {

std::string Cluster::first_error(const std::string& mine) const {
    if (!distributed()) return mine;
    Bytes b(mine.size());
    if (!mine.empty()) std::memcpy(b.data(), mine.data(), mine.size());
    const std::vector<Bytes> all = all_gather(b);
    for (std::size_t r = 0; r < all.size(); ++r)
        if (!all[r].empty()) {
            std::string e(reinterpret_cast<const char*>(all[r].data()), all[r].size());
            // Rank 0's own error is the one every rank would show; another rank's says where.
            return r == 0 ? e : e + " (on MPI rank " + std::to_string(r) + ")";
        }
    return {};
}

bool Cluster::any(bool mine) const {
    if (!distributed()) return mine;
    const std::vector<uint64_t> votes = all_sizes(mine ? 1 : 0);
    for (const uint64_t v : votes)
        if (v) return true;
    return false;
}

std::vector<Bytes> Cluster::all_gather(const Bytes& mine) const {
    const std::vector<uint64_t> sizes = all_sizes(mine.size());
    uint64_t total = 0;
    for (uint64_t n : sizes) total += n;
    Bytes flat(total);
    all_gather_into(mine.data(), sizes, flat.data());
    std::vector<Bytes> parts;
    uint64_t at = 0;
    for (uint64_t n : sizes) {
        parts.emplace_back(flat.begin() + std::ptrdiff_t(at),
                           flat.begin() + std::ptrdiff_t(at + n));
        at += n;
    }
    return parts;
}

const Cluster& cluster_or_solo(const Cluster* c) {
    static const SoloCluster solo;
    return c ? *c : solo;
}

void Unpacker::check(std::size_t n) const {
    // The ranks run the same binary on the same input: a short message is a bug, not input.
    if (n > b_.size() - at_) throw std::logic_error("cluster message shorter than its contents");
}

}  // namespace foton
