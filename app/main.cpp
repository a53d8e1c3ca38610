// The `fird` command: parses arguments and wires the floors; nothing else.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "parse.hpp"
#include "version.hpp"
#include "vk/check.hpp"

int main(int argc, char** argv) {
    CLI::App app{"FIRD: fast inverse reflector design workbench", "fird"};
    app.require_subcommand(1);
    app.set_version_flag("--version", fird::app::program_version(),
                         "Print the program's version (and the git commit built) and exit");
    fird::app::GlobalOptions global;
    app.add_option("--device", global.device_name,
                   "Vulkan device to use (case-insensitive substring of its name)");
    app.add_option("--max-device-memory", global.max_device_memory_mb,
                   "Refuse device allocations past this many MB in all")
        ->check(CLI::PositiveNumber);
    app.add_option("--max-batch-rays", global.max_batch_rays,
                   "Trace at most this many rays per submission (default: as the device "
                   "allows; the workbench: 131072)")
        ->check(CLI::PositiveNumber);
    app.add_flag("--validation", global.validation,
                 "Enable the Vulkan validation layers (also FIRD_VALIDATION=1)");
    std::function<int()> run;
    fird::app::register_commands(app, global, run);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e); // --help
        std::string message = e.what();
        // CLI11 reports an unknown first word as a missing subcommand; name the word.
        for (int i = 1; i < argc; ++i) {
            const std::string word = argv[i];
            if (word == "--device" || word == "--max-device-memory" || word == "--max-batch-rays") {
                ++i;
                continue;
            }
            const auto known =
                app.get_subcommands([&](const CLI::App* sub) { return sub->get_name() == word; });
            if (!word.empty() && word[0] != '-' && known.empty())
                message = "unknown subcommand '" + word + "'";
            break;
        }
        std::fprintf(stderr, "fird: error: %s\n", message.c_str());
        std::fprintf(stderr, "usage: fird [--device NAME] [--validation] SUBCOMMAND ... "
                             "(fird --help lists subcommands)\n");
        return 2;
    }
    if (const char* env = std::getenv("FIRD_VALIDATION"); env && std::string(env) == "1")
        global.validation = true;
    try {
        return run();
    } catch (const fird::app::UsageError& e) {
        std::fprintf(stderr, "fird: error: %s\n", e.what());
        std::fprintf(stderr, "usage: see fird %s --help\n",
                     app.get_subcommands().empty() ? ""
                                                   : app.get_subcommands()[0]->get_name().c_str());
        return 2;
    } catch (const fird::vk::NoDeviceError& e) {
        std::fprintf(stderr, "fird: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fird: error: %s\n", e.what());
        return 1;
    }
}
