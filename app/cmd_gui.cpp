// fird gui [SCENE] [--script FILE] [--stats] [--frames N] [--offscreen WxH]: the interactive
// workbench
// (built with FIRD_BUILD_UI).
#include "commands.hpp"
#include "parse.hpp"

#ifdef FIRD_HAVE_UI
#include "workbench.hpp"
#endif

namespace fird::app {

void register_gui(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("gui", "Open the interactive workbench window");
    struct Args {
        std::string scene, script, offscreen;
        std::uint32_t frames = 0;
        bool stats = false;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("SCENE", a->scene, "Scene file to open");
    cmd->add_option("--script", a->script, "Run a scripted session (one action a line)");
    cmd->add_flag("--stats", a->stats, "Print frame-time statistics as JSON at exit");
    cmd->add_option("--offscreen", a->offscreen,
                    "Run the workbench with no window, its frames drawn into a WxH image "
                    "(frame times on a machine without a display)");
    cmd->add_option("--frames", a->frames, "Close after this many frames (0: run until closed)")
        ->check(CLI::NonNegativeNumber);
    cmd->callback([&global, &run, a] {
        run = [&global, a]() -> int {
#ifdef FIRD_HAVE_UI
            const auto [offscreen_w, offscreen_h] =
                a->offscreen.empty() ? std::pair<std::uint32_t, std::uint32_t>{0, 0}
                                     : parse_size("--offscreen", a->offscreen, 200, 16384);
            return ui::run_workbench({.device_name = global.device_name,
                                      .validation = global.validation,
                                      .max_batch_rays = global.max_batch_rays,
                                      .scene = a->scene,
                                      .script = a->script,
                                      .max_frames = a->frames,
                                      .stats = a->stats,
                                      .offscreen_w = offscreen_w,
                                      .offscreen_h = offscreen_h});
#else
            (void)global;
            (void)a;
            throw std::runtime_error(
                "this fird was built without the ui floor (FIRD_BUILD_UI=OFF)");
#endif
        };
    });
}

} // namespace fird::app
