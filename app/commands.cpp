#include "commands.hpp"

namespace fird::app {

void register_commands(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    register_info(app, global, run);
    register_trace(app, global, run);
    register_optimize(app, global, run);
    register_calibrate(app, global, run);
    register_export(app, global, run);
    register_screenshot(app, global, run);
    register_stress(app, global, run);
    register_bench(app, global, run);
    register_photometry(app, global, run);
    register_gui(app, global, run);
}

} // namespace fird::app
