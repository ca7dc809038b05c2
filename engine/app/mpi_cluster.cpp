#include "mpi_cluster.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "engine/core/error.h"

#ifdef FOTON_HAVE_MPI
#include <mpi.h>
#endif

namespace foton::app {

bool mpi_available() {
#ifdef FOTON_HAVE_MPI
    return true;
#else
    return false;
#endif
}

bool launched_by_mpi() {
    // Open MPI's mpirun, then MPICH/Hydra and Slurm's PMI (srun --mpi=pmi2/pmix).
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (std::getenv(v)) return true;
    return false;
}

namespace {
std::atomic<RankPhase> phase{RankPhase::Setup};
}

void set_rank_phase(RankPhase p) {
    phase = p;
}

void check_in(const Cluster& cluster) {
    const std::string e = cluster.first_error("");
    if (!e.empty()) throw OtherRankFailed(e);
}

int report_error(const std::string& message, int code, bool bad_input, const MpiRuntime* mpi) {
    const Cluster* cluster = mpi ? &mpi->cluster() : nullptr;
    const RankPhase p = phase.load();
    if (!cluster || !cluster->distributed() || p == RankPhase::Local) {
        std::fprintf(stderr, "%s\n", message.c_str());
        return code;
    }
    if (p == RankPhase::Collective && !bad_input) {
        std::fprintf(stderr, "%s (on MPI rank %d: ending every rank)\n", message.c_str(),
                     cluster->rank());
        std::fflush(stderr);
        mpi->abort(code);
    }
    // Every rank checks in with its message; rank 0 shows the first.
    const std::string first = cluster->first_error(message);
    if (cluster->root()) std::fprintf(stderr, "%s\n", first.c_str());
    return code;
}

#ifdef FOTON_HAVE_MPI

namespace {

// Messages above this go in pieces: MPI counts and displacements are ints.
constexpr uint64_t kPiece = uint64_t(1) << 30;

void check(int rc, const char* what) {
    if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

class MpiCluster final : public Cluster {
  public:
    MpiCluster() {
        MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
        MPI_Comm_size(MPI_COMM_WORLD, &size_);
    }
    int rank() const override { return rank_; }
    int size() const override { return size_; }
    uint64_t bytes_moved() const override { return moved_.load(); }
    double collective_seconds() const override { return double(nanoseconds_.load()) * 1e-9; }

    std::vector<uint64_t> all_sizes(uint64_t mine) const override {
        const Timer timer(nanoseconds_);
        std::vector<uint64_t> sizes(static_cast<std::size_t>(size_));
        check(MPI_Allgather(&mine, 1, MPI_UINT64_T, sizes.data(), 1, MPI_UINT64_T, MPI_COMM_WORLD),
              "MPI_Allgather");
        return sizes;
    }

    void all_gather_into(const void* mine, const std::vector<uint64_t>& sizes,
                         void* out) const override {
        const Timer timer(nanoseconds_);
        std::byte* dst = static_cast<std::byte*>(out);
        uint64_t total = 0;
        std::vector<uint64_t> at(sizes.size());
        for (std::size_t r = 0; r < sizes.size(); ++r) {
            at[r] = total;
            total += sizes[r];
        }
        const uint64_t own = sizes[std::size_t(rank_)];
        if (total <= uint64_t(INT_MAX)) {
            std::vector<int> counts(sizes.size()), displs(sizes.size());
            for (std::size_t r = 0; r < sizes.size(); ++r) {
                counts[r] = int(sizes[r]);
                displs[r] = int(at[r]);
            }
            check(MPI_Allgatherv(mine, int(own), MPI_BYTE, dst, counts.data(), displs.data(),
                                 MPI_BYTE, MPI_COMM_WORLD),
                  "MPI_Allgatherv");
        } else {
            // Beyond 2 GB in all: each rank's part broadcast by it, in pieces.
            if (own) std::memcpy(dst + at[std::size_t(rank_)], mine, own);
            for (int r = 0; r < size_; ++r)
                bcast(dst + at[std::size_t(r)], sizes[std::size_t(r)], r);
        }
        moved_ += own * uint64_t(size_ - 1) + (total - own);
    }

    std::vector<Bytes> gather(const Bytes& mine) const override {
        const std::vector<uint64_t> sizes = all_sizes(mine.size());
        const Timer timer(nanoseconds_);
        std::vector<Bytes> all;
        if (rank_ == 0) {
            all.resize(static_cast<std::size_t>(size_));
            all[0] = mine;
            for (int r = 1; r < size_; ++r) {
                Bytes& b = all[std::size_t(r)];
                b.resize(sizes[std::size_t(r)]);
                for (uint64_t at = 0; at < b.size(); at += kPiece)
                    check(MPI_Recv(b.data() + at, int(std::min<uint64_t>(kPiece, b.size() - at)),
                                   MPI_BYTE, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                          "MPI_Recv");
                moved_ += b.size();
            }
        } else {
            for (uint64_t at = 0; at < mine.size(); at += kPiece)
                check(MPI_Send(mine.data() + at, int(std::min<uint64_t>(kPiece, mine.size() - at)),
                               MPI_BYTE, 0, 0, MPI_COMM_WORLD),
                      "MPI_Send");
            moved_ += mine.size();
        }
        return all;
    }

    void broadcast(Bytes& data) const override {
        const Timer timer(nanoseconds_);
        bcast(data.data(), data.size(), 0);
        moved_ += data.size() * (rank_ == 0 ? uint64_t(size_ - 1) : 1);
    }

  private:
    void bcast(std::byte* b, uint64_t n, int root) const {
        for (uint64_t at = 0; at < n; at += kPiece)
            check(MPI_Bcast(b + at, int(std::min<uint64_t>(kPiece, n - at)), MPI_BYTE, root,
                            MPI_COMM_WORLD),
                  "MPI_Bcast");
    }

    // Adds the wall time of its scope to a counter.
    struct Timer {
        std::atomic<uint64_t>& total;
        std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
        explicit Timer(std::atomic<uint64_t>& t) : total(t) {}
        ~Timer() {
            total += uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                  std::chrono::steady_clock::now() - start)
                                  .count());
        }
    };

    int rank_ = 0, size_ = 1;
    mutable std::atomic<uint64_t> moved_{0}, nanoseconds_{0};
};

}  // namespace

MpiRuntime::MpiRuntime() {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
    if (provided < MPI_THREAD_SERIALIZED) {
        MPI_Finalize();
        throw InputError("mpi", 0,
                         "this MPI library cannot take calls from several threads "
                         "(MPI_THREAD_SERIALIZED): rebuild foton against one that can");
    }
    cluster_ = std::make_unique<MpiCluster>();
}

MpiRuntime::~MpiRuntime() {
    cluster_.reset();
    MPI_Finalize();
}

void MpiRuntime::abort(int code) const {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}

#else

MpiRuntime::MpiRuntime() {
    throw InputError("mpi", 0,
                     "this foton was built without MPI: install libopenmpi-dev (scripts/bootstrap "
                     "does) and configure again");
}
MpiRuntime::~MpiRuntime() = default;
void MpiRuntime::abort(int code) const {
    std::_Exit(code);
}

#endif

}  // namespace foton::app
