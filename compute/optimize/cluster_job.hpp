// A search handed to a cluster: its folder gets the scene as searched (scene.toml), a script
// that runs it under mpirun on one machine (run.sh) and a Slurm batch script for N nodes of
// G GPUs (slurm.sh). Both run `fird optimize` with the folder as its --out, and continue the
// search recorded there (--resume) when started again; `fird follow` or the workbench
// follows its progress from the folder (docs/scale-out.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "model/scene.hpp"

namespace fird {

// What the job asks of the machines: ranks for mpirun on one machine; for Slurm, nodes,
// GPUs per node (one rank each), a time limit and a partition.
struct ClusterShape {
    std::uint32_t ranks = 4; // run.sh's mpirun -np (its first argument overrides it)
    std::uint32_t nodes = 1;
    std::uint32_t gpus_per_node = 4;     // and as many ranks on each node
    std::string time_limit = "04:00:00"; // Slurm's forms: M, H:M:S, D-H, D-H:M:S ...
    std::string partition;               // empty: the cluster's default
};

struct ClusterJob {
    std::string dir; // the search's --out folder; the job's files go in it
    Scene scene;     // the scene searched: written with its files' absolute paths
    // fird optimize's options besides the scene and --out ("--method", "grid", ...) for the
    // search's start, and those that go with --resume too (--rank-timeout).
    std::vector<std::string> optimize_options, launch_options;
    // fird's own options given with the job (--max-device-memory, --max-batch-rays,
    // --validation, --device), before the subcommand on every start of the search.
    std::vector<std::string> global_options;
    std::string fird; // the program the job runs (an absolute path; $FIRD overrides it)
    ClusterShape shape;
};

struct WrittenJob {
    std::string scene, run_sh, slurm_sh; // the files written
    std::string mpirun, sbatch;          // the command lines that start it
};

// One line naming the option ("--time-limit: ...") when the shape is not one a launcher
// takes; nothing when it is.
std::optional<std::string> cluster_shape_error(const ClusterShape& shape);

// Writes the job's files (each whole or not at all). Throws std::invalid_argument for a
// bad shape (cluster_shape_error), std::runtime_error naming the folder when a search has
// begun in it already or a file cannot be written.
WrittenJob write_cluster_job(const ClusterJob& job);

// `word` quoted for bash (single quotes; a quote inside as '\''), as the scripts hold it.
std::string shell_quoted(const std::string& word);

} // namespace fird
