#pragma once
// The processes one render runs across (MPI ranks, issue 16), and the few collective
// operations the renderers need to split their work and still make the image of one process
// bit for bit: every rank traces a fixed share of the work (tiles, photon chunks, light-path
// chunks, cache-fill chunks); results that feed further work are exchanged in rank order,
// which is the single process's chunk order, and the image is gathered to rank 0.
//
// The engine sees only this interface; the app starts MPI and provides the implementation
// (app/mpi_cluster.cpp). A single process is a cluster of one, whose collectives copy.
// Every collective must be called by every rank in the same order, one at a time.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

namespace foton {

using Bytes = std::vector<std::byte>;

class Cluster {
  public:
    virtual ~Cluster() = default;
    virtual int rank() const = 0;
    virtual int size() const = 0;
    bool root() const { return rank() == 0; }
    bool distributed() const { return size() > 1; }
    // Every rank's size, in rank order, on every rank (MPI_Allgather).
    virtual std::vector<uint64_t> all_sizes(uint64_t mine) const = 0;
    // Every rank's bytes (`sizes` from all_sizes) concatenated in rank order into `out`, on
    // every rank (MPI_Allgatherv): straight into their destination, no copy on the way.
    virtual void all_gather_into(const void* mine, const std::vector<uint64_t>& sizes,
                                 void* out) const = 0;
    // The same for small messages: one entry per rank.
    std::vector<Bytes> all_gather(const Bytes& mine) const;
    // Replaces v, on every rank, by every rank's v concatenated in rank order.
    template <class T, class A>
    void all_gather_concat(std::vector<T, A>& v) const {
        static_assert(std::is_trivially_copyable_v<T>);
        if (!distributed()) return;
        const std::vector<uint64_t> sizes = all_sizes(v.size() * sizeof(T));
        uint64_t total = 0;
        for (uint64_t s : sizes) total += s;
        std::vector<T, A> all(total / sizeof(T));
        all_gather_into(v.data(), sizes, all.data());
        v.swap(all);
    }
    // The same on rank 0 only; the other ranks get an empty list (MPI_Gatherv).
    virtual std::vector<Bytes> gather(const Bytes& mine) const = 0;
    // Rank 0's bytes on every rank (MPI_Bcast); `data` has the same size everywhere.
    virtual void broadcast(Bytes& data) const = 0;
    // Bytes this process has sent and received in collectives so far (the communication
    // model's measurements).
    virtual uint64_t bytes_moved() const = 0;
    // Wall seconds this process has spent inside collectives (moving data, and waiting for
    // the ranks that came later).
    virtual double collective_seconds() const = 0;

    // The first of the ranks' errors ("" = none), on every rank: a failure on one rank
    // (a file only that node cannot read) ends every rank instead of leaving them waiting.
    std::string first_error(const std::string& mine) const;
    // Whether any rank says yes, on every rank (a Ctrl-C that reached one rank only).
    bool any(bool mine) const;
};

// The cluster of one: this process alone.
class SoloCluster final : public Cluster {
  public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::vector<uint64_t> all_sizes(uint64_t mine) const override { return {mine}; }
    void all_gather_into(const void* mine, const std::vector<uint64_t>& sizes,
                         void* out) const override {
        if (sizes[0]) std::memcpy(out, mine, sizes[0]);
    }
    std::vector<Bytes> gather(const Bytes& mine) const override { return {mine}; }
    void broadcast(Bytes&) const override {}
    uint64_t bytes_moved() const override { return 0; }
    double collective_seconds() const override { return 0.0; }
};

// The cluster a render runs on: the one given, else this process alone.
const Cluster& cluster_or_solo(const Cluster* c);

// Rank `rank`'s share of n items: the contiguous range [begin, end), ranks in order, sizes
// differing by at most one. Contiguous shares keep rank order equal to item order.
struct Share {
    uint64_t begin = 0, end = 0;
    uint64_t size() const { return end - begin; }
};
inline Share share_of(uint64_t n, int rank, int ranks) {
    return {n * uint64_t(rank) / uint64_t(ranks), n * uint64_t(rank + 1) / uint64_t(ranks)};
}
inline Share share_of(uint64_t n, const Cluster& c) {
    return share_of(n, c.rank(), c.size());
}

// The other split: items dealt out in turn, item i to rank i mod N (camera tiles, VCM's
// camera chunks, SPPM's image rows). Every rank gets some of every part of the image, so
// cheap and costly regions are shared alike; rank order is then not item order.
inline int dealt_to(uint64_t item, int ranks) {
    return int(item % uint64_t(ranks));
}
// The items of [0, n) dealt to this rank, in order.
inline std::vector<uint64_t> dealt_in_turn(uint64_t n, const Cluster& c) {
    std::vector<uint64_t> mine;
    for (uint64_t i = uint64_t(c.rank()); i < n; i += uint64_t(c.size())) mine.push_back(i);
    return mine;
}

// Packing trivially copyable values into the byte strings the collectives move.
template <class T>
void pack(Bytes& out, const T* data, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::size_t at = out.size();
    out.resize(at + n * sizeof(T));
    if (n) std::memcpy(out.data() + at, data, n * sizeof(T));
}
template <class T, class A>
void pack(Bytes& out, const std::vector<T, A>& v) {
    const uint64_t n = v.size();
    pack(out, &n, 1);
    pack(out, v.data(), v.size());
}
template <class T>
void pack_value(Bytes& out, const T& v) {
    pack(out, &v, 1);
}

// Reads back what pack() wrote, in the same order.
class Unpacker {
  public:
    explicit Unpacker(const Bytes& b) : b_(b) {}
    template <class T>
    void read(T* data, std::size_t n) {
        static_assert(std::is_trivially_copyable_v<T>);
        check(n * sizeof(T));
        if (n) std::memcpy(data, b_.data() + at_, n * sizeof(T));
        at_ += n * sizeof(T);
    }
    template <class T>
    T value() {
        T v;
        read(&v, 1);
        return v;
    }
    // Appends a packed vector to `v`.
    template <class T, class A>
    void append(std::vector<T, A>& v) {
        const uint64_t n = value<uint64_t>();
        check(n * sizeof(T));
        const std::size_t old = v.size();
        v.resize(old + n);
        read(v.data() + old, n);
    }
    bool done() const { return at_ == b_.size(); }

  private:
    void check(std::size_t n) const;
    const Bytes& b_;
    std::size_t at_ = 0;
};

}  // namespace foton
