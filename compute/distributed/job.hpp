// The MPI job this process is a rank of (mpirun or srun, one rank per device), or a job of
// one process when no launcher started it: MPI is then never initialised, and the
// commands run as they do without MPI. Only compute/distributed sees mpi.h.
#pragma once

#include <cstdint>

namespace fird::distributed {

class Job {
  public:
    // Joins the job when a launcher started this process (Open MPI's mpirun sets
    // OMPI_COMM_WORLD_SIZE; srun with PMIx sets PMIX_RANK); else a job of one.
    Job(int& argc, char**& argv);
    // Finalises MPI, or aborts the whole job when end() was given a failure (the other
    // ranks may be waiting on this one: finalising would hang).
    ~Job();
    Job(const Job&) = delete;
    Job& operator=(const Job&) = delete;

    int rank() const { return rank_; }
    int size() const { return size_; }
    // The rank among those on this node (OMPI_COMM_WORLD_LOCAL_RANK, SLURM_LOCALID, or
    // MPI's shared-memory split): which of the node's devices this rank opens.
    std::uint32_t local_rank() const { return local_rank_; }
    bool distributed() const { return size_ > 1; }
    // The process's exit code, so that the destructor knows whether to abort.
    void end(int exit_code) { exit_code_ = exit_code; }

  private:
    bool initialised_ = false;
    int rank_ = 0, size_ = 1;
    std::uint32_t local_rank_ = 0;
    int exit_code_ = 0;
};

} // namespace fird::distributed
