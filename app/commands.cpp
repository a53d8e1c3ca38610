#include "commands.hpp"

namespace fird::app {

vk::ContextOptions context_options(const GlobalOptions& g) {
    return {.validation = g.validation,
            .device_name = g.device_name,
            .local_rank = g.local_rank,
            .max_device_memory_bytes = std::uint64_t(g.max_device_memory_mb * 1048576.0),
            .max_batch_rays = g.max_batch_rays};
}

void register_commands(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    register_info(app, global, run);
    register_trace(app, global, run);
    register_optimize(app, global, run);
    register_follow(app, global, run);
    register_calibrate(app, global, run);
    register_export(app, global, run);
    register_screenshot(app, global, run);
    register_stress(app, global, run);
    register_tolerance(app, global, run);
    register_bench(app, global, run);
    register_photometry(app, global, run);
    register_gui(app, global, run);
}

} // namespace fird::app
