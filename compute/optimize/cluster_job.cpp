#include "cluster_job.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <regex>
#include <stdexcept>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "optimize/search_folder.hpp"

namespace fird {

namespace {

namespace fs = std::filesystem;

// The launch arguments both scripts share: a search begun in the folder is continued
// (--resume takes no other option: the search keeps the settings it began with).
std::string fird_arguments(const ClusterJob& job, const std::string& here) {
    const auto words = [](const std::vector<std::string>& options) {
        std::string text;
        for (const std::string& o : options)
            text.append(1, ' ').append(shell_quoted(o)); // (not " " + ...: GCC 12's -Wrestrict)
        return text;
    };
    const std::string both = words(job.launch_options);
    // fird's own options go before the subcommand, on both branches.
    std::string global;
    for (const std::string& o : job.global_options)
        global.append(shell_quoted(o)).append(1, ' ');
    return fmt::format("if [[ -f \"{0}/options.json\" ]]; then\n"
                       "  args=({3}optimize \"{0}/scene.toml\" --resume \"{0}\"{2})\n"
                       "else\n"
                       "  args=({3}optimize \"{0}/scene.toml\" --out \"{0}\"{1}{2})\n"
                       "fi\n",
                       here, words(job.optimize_options), both, global);
}

std::string run_script(const ClusterJob& job) {
    return fmt::format(
        R"SH(#!/usr/bin/env bash
# {name}: fird optimize on the ranks of this machine under mpirun, one rank per device
# (docs/scale-out.md). Written by fird for the search in this folder.
#
#   bash run.sh [RANKS]      # default {ranks}; 1 runs fird alone, without mpirun
#
# Started again, it continues the search recorded here (--resume), on any number of ranks.
# $FIRD names another fird; $MPIRUN_ARGS adds mpirun options (--oversubscribe, --hostfile).
# Progress: fird follow "$(dirname "$0")" (or the workbench's optimize panel).
set -euo pipefail
here=$(CDPATH='' cd -- "$(dirname -- "${{BASH_SOURCE[0]}}")" && pwd)
fird=${{FIRD:-{fird}}}
ranks=${{1:-{ranks}}}
if [[ ! $ranks =~ ^[1-9][0-9]*$ ]]; then
  echo "run.sh: error: RANKS must be a whole number >= 1, not '$ranks'" >&2
  exit 2
fi
{args}if [[ $ranks == 1 ]]; then
  exec "$fird" "${{args[@]}}"
fi
launcher=(mpirun -np "$ranks")
# Open MPI refuses root unless told (a container's root).
if [[ $(id -u) == 0 ]]; then launcher+=(--allow-run-as-root); fi
# $MPIRUN_ARGS split into words as the shell splits them, never globbed. (Open MPI's
# mpirun; another MPI's launcher takes other options: edit the two lines above.)
read -ra extra <<< "${{MPIRUN_ARGS:-}}"
exec "${{launcher[@]}}" "${{extra[@]}}" "$fird" "${{args[@]}}"
)SH",
        fmt::arg("name", one_line(job.scene.name)), fmt::arg("ranks", job.shape.ranks),
        fmt::arg("fird", shell_quoted(job.fird)), fmt::arg("args", fird_arguments(job, "$here")));
}

// A job name Slurm shows: the scene's name in the characters every shell and queue takes.
std::string job_name(const std::string& scene_name) {
    std::string name = "fird-";
    for (char c : scene_name)
        name.push_back(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' ? c
                                                                                           : '-');
    name.resize(std::min<std::size_t>(name.size(), 64));
    return name;
}

std::string slurm_script(const ClusterJob& job, const std::string& dir) {
    const ClusterShape& s = job.shape;
    return fmt::format(
        R"SH(#!/usr/bin/env bash
# {name}: fird optimize on {nodes} node(s) of {gpus} GPU(s), one rank per GPU: rank 0 runs the
# search and writes every output into this folder, the others trace their shares of each
# batch (docs/scale-out.md). Written by fird for the search in this folder.
#
#   sbatch {script}
#
# A second submission continues the search recorded here (--resume), on any number of
# nodes: a job that ran out of time, lost a node or was preempted ends where an
# uninterrupted one would have. The scene, the files it names and this folder must be on a
# file system every node reads. $FIRD names another fird; $FIRD_SRUN_MPI the PMI
# (default pmix). Progress: fird follow {here}
#SBATCH --job-name={job}
#SBATCH --nodes={nodes}
#SBATCH --ntasks-per-node={gpus}
#SBATCH --gpus-per-node={gpus}
#SBATCH --cpus-per-task=2
#SBATCH --time={time}
{partition}{output}set -euo pipefail
# sbatch runs a copy of this script: the folder is named, not found beside it.
here={here}
fird=${{FIRD:-{fird}}}
{args}# Each rank opens the GPU of its rank on the node (SLURM_LOCALID) among those it sees.
exec srun --mpi="${{FIRD_SRUN_MPI:-pmix}}" "$fird" "${{args[@]}}"
)SH",
        fmt::arg("name", one_line(job.scene.name)), fmt::arg("nodes", s.nodes),
        fmt::arg("gpus", s.gpus_per_node), fmt::arg("job", job_name(job.scene.name)),
        fmt::arg("time", s.time_limit),
        fmt::arg("partition", s.partition.empty()
                                  ? std::string()
                                  : fmt::format("#SBATCH --partition={}\n", s.partition)),
        // (#SBATCH lines are not read by a shell, and Slurm expands % in them: a folder with
        // a space, a quote or a % gets Slurm's default log, slurm-JOB.out where it is
        // submitted.)
        fmt::arg("output", dir.find_first_of(" \t'\"\\$%") == std::string::npos
                               ? fmt::format("#SBATCH --output={}/slurm-%j.log\n", dir)
                               : std::string()),
        fmt::arg("script", shell_quoted((fs::path(dir) / "slurm.sh").string())),
        fmt::arg("here", shell_quoted(dir)), fmt::arg("fird", shell_quoted(job.fird)),
        fmt::arg("args", fird_arguments(job, "$here")));
}

void write_script(const std::string& path, const std::string& text) {
    write_text_file(path, text);
    std::error_code ec;
    fs::permissions(path, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                    fs::perm_options::add, ec);
    if (ec)
        throw std::runtime_error(
            fmt::format("{}: cannot make it executable: {}", path, ec.message()));
}

} // namespace

std::string shell_quoted(const std::string& word) {
    std::string q(1, '\'');
    for (char c : word) {
        if (c == '\'')
            q.append("'\\''");
        else
            q.push_back(c);
    }
    q.push_back('\'');
    return q;
}

std::optional<std::string> cluster_shape_error(const ClusterShape& s) {
    constexpr std::uint32_t most = 1u << 20;
    if (s.ranks < 1 || s.ranks > most)
        return fmt::format("--ranks: {} is not a rank count (1 to {})", s.ranks, most);
    if (s.nodes < 1 || s.nodes > most)
        return fmt::format("--nodes: {} is not a node count (1 to {})", s.nodes, most);
    if (s.gpus_per_node < 1 || s.gpus_per_node > 1024)
        return fmt::format("--gpus-per-node: {} is not a GPU count (1 to 1024)", s.gpus_per_node);
    // Slurm's time forms: minutes, minutes:seconds, hours:minutes:seconds, days-hours,
    // days-hours:minutes, days-hours:minutes:seconds.
    static const std::regex time(R"(\d{1,6}(:\d{1,2}){0,2}|\d{1,4}-\d{1,2}(:\d{1,2}){0,2})");
    if (!std::regex_match(s.time_limit, time))
        return fmt::format("--time-limit: '{}' is not a Slurm time (MINUTES, HH:MM:SS or "
                           "DAYS-HH:MM:SS)",
                           s.time_limit);
    static const std::regex partition(R"([A-Za-z0-9_.,-]{1,128})");
    if (!s.partition.empty() && !std::regex_match(s.partition, partition))
        return fmt::format("--partition: '{}' is not a partition name (letters, digits, '_', "
                           "'.', '-', ',')",
                           s.partition);
    return std::nullopt;
}

WrittenJob write_cluster_job(const ClusterJob& job) {
    if (const auto why = cluster_shape_error(job.shape)) throw std::invalid_argument(*why);
    const std::string dir = fs::absolute(job.dir).lexically_normal().string();
    if (search_began(dir))
        throw std::runtime_error(fmt::format(
            "{}: a search has begun here already (its options.json): its run.sh or slurm.sh "
            "continues it, or choose another folder",
            dir));
    create_output_directory(dir);
    const auto path = [&](const char* name) { return (fs::path(dir) / name).string(); };
    WrittenJob w{
        .scene = path("scene.toml"), .run_sh = path("run.sh"), .slurm_sh = path("slurm.sh")};
    write_text_file(w.scene,
                    fmt::format("# {}: the scene of a fird optimize job (run.sh, slurm.sh)\n",
                                one_line(job.scene.name)) +
                        scene_to_toml(with_absolute_files(job.scene)));
    write_script(w.run_sh, run_script(job));
    write_script(w.slurm_sh, slurm_script(job, dir));
    w.mpirun = fmt::format("bash {} {}", shell_quoted(w.run_sh), job.shape.ranks);
    w.sbatch = fmt::format("sbatch {}", shell_quoted(w.slurm_sh));
    return w;
}

} // namespace fird
