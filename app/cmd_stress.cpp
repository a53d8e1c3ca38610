// fird stress [--json] [--out DIR]: the numerical stability suite on this device.
#include <cstdio>
#include <filesystem>

#include <unistd.h>

#include <fmt/format.h>

#include "commands.hpp"
#include "io/atomic_file.hpp"
#include "progress.hpp"
#include "stress/stress.hpp"
#include "vk/context.hpp"

namespace fird::app {

void register_stress(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("stress", "Stress the fast path against the CPU reference: "
                                             "grazing rays, corners, steep walls, extreme scenes");
    struct Args {
        std::string out, only;
        bool json = false;
    };
    auto a = std::make_shared<Args>();
    cmd->add_flag("--json", a->json, "Print one JSON object");
    cmd->add_option("--out", a->out, "Write stress.json and stress.txt here");
    cmd->add_option("--case", a->only, "Only the cases whose name contains this text");
    cmd->callback([&global, &run, a] {
        run = [&global, a] {
            const auto ctx = vk::Context::create(context_options(global));
            const std::string scratch =
                (std::filesystem::temp_directory_path() / fmt::format("fird_stress_{}", ::getpid()))
                    .string();
            std::vector<StressResult> results;
            ProgressLine progress;
            for (const StressCase& c : stress_cases(ctx, scratch)) {
                if (!a->only.empty() && c.name.find(a->only) == std::string::npos) continue;
                progress.show("stress: " + c.name);
                results.push_back(run_stress_case(ctx, c));
            }
            progress.finish();
            std::filesystem::remove_all(scratch);
            if (results.empty())
                throw std::invalid_argument("--case " + a->only + ": no such case");
            const auto j = stress_json(results);
            if (!a->out.empty()) {
                create_output_directory(a->out);
                write_text_file((std::filesystem::path(a->out) / "stress.json").string(),
                                j.dump(2) + "\n");
                write_text_file((std::filesystem::path(a->out) / "stress.txt").string(),
                                stress_table(results));
            }
            if (a->json)
                std::printf("%s\n", j.dump(2).c_str());
            else
                std::printf("%s", stress_table(results).c_str());
            if (ctx.validation_errors() > 0)
                throw std::runtime_error("Vulkan validation errors were reported (see above)");
            return j["ok"].get<bool>() ? 0 : 1;
        };
    });
}

} // namespace fird::app
