// fird gui: the interactive workbench (built with FIRD_BUILD_UI).
#include "commands.hpp"

#ifdef FIRD_HAVE_UI
#include "workbench.hpp"
#endif

namespace fird::app {

void register_gui(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("gui", "Open the interactive workbench window");
    auto frames = std::make_shared<std::uint32_t>(0);
    cmd->add_option("--frames", *frames, "Close after this many frames (0: run until closed)")
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&global, &run, frames] {
        run = [&global, frames]() -> int {
#ifdef FIRD_HAVE_UI
            return ui::run_workbench({.device_name = global.device_name,
                                      .validation = global.validation,
                                      .max_frames = *frames});
#else
            (void)global;
            (void)frames;
            throw std::runtime_error(
                "this fird was built without the ui floor (FIRD_BUILD_UI=OFF)");
#endif
        };
    });
}

} // namespace fird::app
