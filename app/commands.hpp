// Subcommand registration: each subcommand's options and the function it runs.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "vk/context.hpp"

namespace fird::distributed {
class Job;
}

namespace fird::app {

struct GlobalOptions {
    std::string device_name;
    bool validation = false;
    double max_device_memory_mb = 0;  // 0: as the device allows
    std::uint64_t max_batch_rays = 0; // 0: as the device allows (gui: its own bound)
    // The MPI job this process is a rank of (fird optimize under mpirun or srun): null in a
    // build without MPI or when no launcher started it.
    const distributed::Job* job = nullptr;
    // This rank's place on its node, when one of several ranks: the device it opens.
    std::optional<std::uint32_t> local_rank;
};

// The Vulkan context options the global options ask for.
vk::ContextOptions context_options(const GlobalOptions& global);

// Adds every subcommand to `app`; the parsed one sets `run`.
void register_commands(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);

void register_info(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_gui(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_trace(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_tolerance(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_photometry(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_optimize(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_follow(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_calibrate(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_export(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_screenshot(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_stress(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_bench(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);

} // namespace fird::app
