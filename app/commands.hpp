// Subcommand registration: each subcommand's options and the function it runs.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>

#include "vk/context.hpp"

namespace fird::app {

struct GlobalOptions {
    std::string device_name;
    bool validation = false;
    double max_device_memory_mb = 0;  // 0: as the device allows
    std::uint64_t max_batch_rays = 0; // 0: as the device allows (gui: its own bound)
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
void register_calibrate(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_export(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_screenshot(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_stress(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);
void register_bench(CLI::App& app, const GlobalOptions& global, std::function<int()>& run);

} // namespace fird::app
