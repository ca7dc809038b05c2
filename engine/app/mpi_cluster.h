#pragma once
// MPI for `mpirun -np N foton render ...` (issue 16): the process's MPI runtime and the
// cluster of its ranks. foton starts MPI only when a launcher started it (or --mpi asks),
// so a plain `foton render` never touches MPI, and a build without MPI still works.
#include <memory>
#include <stdexcept>
#include <string>

#include "engine/core/cluster.h"

namespace foton::app {

// Whether this build has MPI (libopenmpi-dev found at configure time).
bool mpi_available();
// Whether an MPI launcher (mpirun, mpiexec, srun) started this process: its environment
// says so.
bool launched_by_mpi();

// MPI from construction to destruction. Threads are serialised: a collective may run on any
// worker thread (inside a graph node), one at a time. Throws InputError in a build without
// MPI.
class MpiRuntime {
  public:
    MpiRuntime();
    ~MpiRuntime();
    MpiRuntime(const MpiRuntime&) = delete;
    MpiRuntime& operator=(const MpiRuntime&) = delete;
    const Cluster& cluster() const { return *cluster_; }
    // Ends every rank at once with this exit code (an error only this rank saw, mid-render,
    // while the others wait in a collective).
    [[noreturn]] void abort(int code) const;

  private:
    std::unique_ptr<Cluster> cluster_;
};

// What an error must do depends on where the ranks are:
// - Setup (loading, checking): ranks fail alone (a file one node cannot read). Every rank
//   checks in before the first collective of the render (Cluster::first_error): the ones
//   that failed with their message, the others with none; rank 0 shows the first, and all
//   exit with its code.
// - Collective (rendering): bad input found here (a renderer's own checks) is found by every
//   rank alike, which all check in as above. Anything else ends every rank (MPI_Abort).
// - Local (rank 0 writing its files): only that rank is concerned.
enum class RankPhase { Setup, Collective, Local };
void set_rank_phase(RankPhase phase);

// Thrown on the ranks that did not fail when another one did during the setup: they stop
// too, and rank 0 shows the message.
class OtherRankFailed : public std::runtime_error {
  public:
    explicit OtherRankFailed(const std::string& message) : std::runtime_error(message) {}
};

// Every rank checks in (collective); throws OtherRankFailed when any rank failed.
void check_in(const Cluster& cluster);

// main()'s error handler: shows `message` (once across ranks) and gives the exit code, or
// ends every rank. `mpi` is null in a process without MPI.
int report_error(const std::string& message, int code, bool bad_input, const MpiRuntime* mpi);

}  // namespace foton::app
