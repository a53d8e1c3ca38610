// fird info [--json]: the devices found, the chosen one, its driver and limits.
#include <cstdio>

#include "commands.hpp"
#include "report/device_report.hpp"
#include "vk/context.hpp"

namespace fird::app {

void register_info(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("info", "List Vulkan devices and the limits that matter");
    auto json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *json, "Print one JSON object");
    cmd->callback([&global, &run, json] {
        run = [&global, json] {
            const auto ctx = vk::Context::create(context_options(global));
            const auto report = device_report(ctx);
            if (*json)
                std::printf("%s\n", report.dump(2).c_str());
            else
                std::printf("%s", device_report_text(report).c_str());
            return 0;
        };
    });
}

} // namespace fird::app
