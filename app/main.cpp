// The `fird` command: parses arguments and wires the floors; nothing else.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "parse.hpp"
#include "version.hpp"
#include "vk/cpu_driver_lanes.hpp"

#if FIRD_HAVE_MPI
#include "distributed/job.hpp"
#endif

namespace {

#if FIRD_HAVE_MPI
constexpr const char* kMpiNote = "";
#else
constexpr const char* kMpiNote = " (this fird was built without MPI: FIRD_BUILD_MPI)";
#endif

#if FIRD_HAVE_MPI
int rank(const fird::distributed::Job* job) {
    return job ? job->rank() : 0;
}
int ranks(const fird::distributed::Job* job) {
    return job ? job->size() : 1;
}
std::uint32_t local_rank(const fird::distributed::Job* job) {
    return job ? job->local_rank() : 0;
}
#else
int rank(const fird::distributed::Job*) {
    return 0;
}
int ranks(const fird::distributed::Job*) {
    return 1;
}
std::uint32_t local_rank(const fird::distributed::Job*) {
    return 0;
}
#endif

// srun started this process as one of several tasks of a step that no MPI launch joined
// (srun --mpi=none, or a fird without MPI: Open MPI, even mpirun -np 1, sets
// OMPI_COMM_WORLD_SIZE, and srun's pmix PMIX_RANK): every task would run the whole command
// and write the same files. The step's task count, or null.
const char* unjoined_srun_tasks() {
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
        if (std::getenv(v)) return nullptr;
    const char* n = std::getenv("SLURM_STEP_NUM_TASKS");
    return n && std::atoi(n) > 1 ? n : nullptr;
}

// The subcommands that run across the ranks of an MPI job; the others refuse more than one.
bool runs_distributed(const std::string& subcommand) {
    return subcommand == "optimize" || subcommand == "tolerance" || subcommand == "calibrate" ||
           subcommand == "bench";
}

// The global options, named once for fird_main's parser and for first_word.
constexpr const char* kDeviceOption = "--device";
constexpr const char* kMaxDeviceMemoryOption = "--max-device-memory";
constexpr const char* kMaxBatchRaysOption = "--max-batch-rays";
constexpr const char* kValidationFlag = "--validation";
constexpr const char* kVersionFlag = "--version";

// Whether `word` is `option`, alone (its value the next word) or as option=value.
bool is_option(const std::string& word, const char* option, bool* value_follows) {
    *value_follows = word == option;
    return *value_follows || word.rfind(std::string(option) + "=", 0) == 0;
}

// The first word of the command line that is neither a global option nor its value: the
// subcommand, if the line is well formed (read before CLI11 parses it, and before MPI); an
// unknown option if that comes first.
std::string first_word(int argc, char** argv) {
    for (int i = 1; i < argc; ++i) {
        const std::string word = argv[i];
        bool value_follows = false;
        if (is_option(word, kDeviceOption, &value_follows) ||
            is_option(word, kMaxDeviceMemoryOption, &value_follows) ||
            is_option(word, kMaxBatchRaysOption, &value_follows)) {
            i += value_follows ? 1 : 0;
            continue;
        }
        if (word != kValidationFlag && word != kVersionFlag && word != "--help" && word != "-h")
            return word;
    }
    return "";
}

// The subcommands that draw (fragment shaders) on the device they compute on.
fird::vk::DeviceWork device_work(const std::string& subcommand) {
    return subcommand == "gui" || subcommand == "screenshot" ? fird::vk::DeviceWork::ComputeAndDraw
                                                             : fird::vk::DeviceWork::Compute;
}

int fird_main(int argc, char** argv, const fird::distributed::Job* job) {
    CLI::App app{"FIRD: fast inverse reflector design workbench", "fird"};
    app.require_subcommand(1);
    app.set_version_flag(kVersionFlag, fird::app::program_version(),
                         "Print the program's version (and the git commit built) and exit");
    fird::app::GlobalOptions global;
    global.job = job;
    // Every rank parses the same command line: rank 0 alone reports what is wrong with it.
    const bool reports = rank(job) == 0;
    app.add_option(kDeviceOption, global.device_name,
                   "Vulkan device to use (case-insensitive substring of its name)");
    app.add_option(kMaxDeviceMemoryOption, global.max_device_memory_mb,
                   "Refuse device allocations past this many MB in all")
        ->check(fird::app::finite_range(1e-3, 1e9));
    app.add_option(kMaxBatchRaysOption, global.max_batch_rays,
                   "Trace at most this many rays per submission (default: as the device "
                   "allows; the workbench: 131072)")
        ->check(CLI::PositiveNumber);
    app.add_flag(kValidationFlag, global.validation,
                 "Enable the Vulkan validation layers (also FIRD_VALIDATION=1)");
    std::function<int()> run;
    fird::app::register_commands(app, global, run);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help
        std::string message = e.what();
        // CLI11 reports an unknown first word as a missing subcommand; name the word.
        const std::string word = first_word(argc, argv);
        const auto known =
            app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == word; });
        if (!word.empty() && word[0] != '-' && known.empty())
            message = "unknown subcommand '" + word + "'";
        if (!reports) return 2;
        std::fprintf(stderr, "fird: error: %s\n", message.c_str());
        std::fprintf(stderr, "usage: fird [--device NAME] [--validation] SUBCOMMAND ... "
                             "(fird --help lists subcommands)\n");
        return 2;
    }
    const std::string subcommand =
        app.get_subcommands().empty() ? "" : app.get_subcommands()[0]->get_name();
    // The commands that share work across ranks, started by srun as several tasks that no
    // MPI launch joined: each would run it all into the same files (measured: srun
    // --mpi=none on Slurm 22.05). Any other command runs in each task as the user asked.
    if (const char* n = unjoined_srun_tasks(); n && runs_distributed(subcommand)) {
        std::fprintf(stderr,
                     "fird: error: srun started %s tasks that did not join one MPI job (srun "
                     "--mpi=none?): each would run the whole fird %s; run srun --mpi=pmix%s\n",
                     n, subcommand.c_str(), kMpiNote);
        return 2;
    }
    if (ranks(job) > 1) {
        if (!runs_distributed(subcommand)) {
            if (reports)
                std::fprintf(
                    stderr,
                    "fird: error: fird %s runs in one process; under mpirun or srun "
                    "only fird optimize, calibrate, tolerance and bench share their work among "
                    "ranks: run it with -np 1\n",
                    subcommand.c_str());
            return 2;
        }
        if (global.device_name.empty()) global.local_rank = local_rank(job);
    }
    if (const char* env = std::getenv("FIRD_VALIDATION"); env && std::string(env) == "1")
        global.validation = true;
    try {
        return run();
    } catch (const fird::app::UsageError& e) {
        if (!reports) return 2;
        std::fprintf(stderr, "fird: error: %s\n", e.what());
        std::fprintf(stderr, "usage: see fird %s --help\n",
                     app.get_subcommands().empty() ? ""
                                                   : app.get_subcommands()[0]->get_name().c_str());
        return 2;
    } catch (const std::exception& e) {
        // A rank other than 0 names itself: its error ends the whole job.
        if (reports)
            std::fprintf(stderr, "fird: error: %s\n", e.what());
        else
            std::fprintf(stderr, "fird: error: rank %d: %s\n", rank(job), e.what());
        return 1;
    }
}

} // namespace

int main(int argc, char** argv) {
    // Before any thread starts (MPI's own read the environment): setenv is not safe beside a
    // getenv on another thread.
    fird::vk::choose_cpu_driver_width(device_work(first_word(argc, argv)));
#if FIRD_HAVE_MPI
    fird::distributed::Job job(argc, argv);
    const int code = fird_main(argc, argv, &job);
    job.end(code); // a failure aborts the job: the other ranks may be waiting on this one
    return code;
#else
    // Started as one of several ranks, a fird without MPI would run the whole search in
    // every rank, each writing the same files.
    for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* n = std::getenv(v); n && std::atoi(n) > 1) {
            std::fprintf(stderr,
                         "fird: error: started as one of %s ranks (%s), but this fird was built "
                         "without MPI (FIRD_BUILD_MPI): run it as one process\n",
                         n, v);
            return 2;
        }
    return fird_main(argc, argv, nullptr);
#endif
}
