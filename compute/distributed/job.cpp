#include "job.hpp"

#include <cstdlib>
#include <string>

#include <mpi.h>

namespace fird::distributed {

namespace {

bool launched_by_mpi() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(v)) return true;
    return false;
}

} // namespace

Job::Job(int& argc, char**& argv) {
    if (!launched_by_mpi()) return;
    // Only the main thread calls MPI (the workbench is not run under mpirun).
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    initialised_ = true;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
    for (const char* v : {"OMPI_COMM_WORLD_LOCAL_RANK", "SLURM_LOCALID"})
        if (const char* s = std::getenv(v)) {
            local_rank_ = std::uint32_t(std::strtoul(s, nullptr, 10));
            return;
        }
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
    int local = 0;
    MPI_Comm_rank(node, &local);
    MPI_Comm_free(&node);
    local_rank_ = std::uint32_t(local);
}

Job::~Job() {
    if (!initialised_) return;
    if (exit_code_ != 0 && size_ > 1) MPI_Abort(MPI_COMM_WORLD, exit_code_); // does not return
    MPI_Finalize();
}

} // namespace fird::distributed
