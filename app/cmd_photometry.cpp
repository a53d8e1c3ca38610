// fird photometry info|convert: IES LM-63 and EULUMDAT files.
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "parse.hpp"
#include "photometry/photometry_commands.hpp"
#include "photometry/photometry_file.hpp"

namespace fird::app {

void register_photometry(CLI::App& app, const GlobalOptions&, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("photometry", "IES LM-63 and EULUMDAT files");
    cmd->require_subcommand(1);

    struct InfoArgs {
        std::string file;
        bool json = false;
    };
    auto info_args = std::make_shared<InfoArgs>();
    auto* info = cmd->add_subcommand("info", "What a photometric file holds, and its flux");
    info->add_option("FILE", info_args->file, "An .ies or .ldt file")->required();
    info->add_flag("--json", info_args->json, "Print one JSON object");
    info->callback([&run, info_args] {
        run = [info_args] {
            const auto j = photometry_info_json(read_photometry(info_args->file));
            if (info_args->json) {
                std::printf(
                    "%s\n",
                    j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
                return 0;
            }
            for (const auto& [key, value] : j.items())
                std::printf(
                    "%-20s %s\n", key.c_str(),
                    value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
            return 0;
        };
    });

    struct ConvertArgs {
        std::string in, out;
        ConvertOptions options;
    };
    auto conv = std::make_shared<ConvertArgs>();
    auto* convert = cmd->add_subcommand(
        "convert", "IES <-> LDT, or to a far field (.npy) or a polar plot (.png); a far-field "
                   ".npy in gives IES or LDT");
    convert->add_option("IN", conv->in, ".ies, .ldt or far-field .npy")->required();
    convert->add_option("OUT", conv->out, ".ies, .ldt, .npy or .png")->required();
    convert
        ->add_option("--c-step", conv->options.c_step_deg,
                     "C-plane step (deg) of a table made from a far field")
        ->check(finite_range(0.01, 180.0));
    convert
        ->add_option("--gamma-step", conv->options.gamma_step_deg,
                     "gamma step (deg) of a table made from a far field")
        ->check(finite_range(0.01, 90.0));
    convert->callback([&run, conv] {
        run = [conv] {
            convert_photometry(conv->in, conv->out, conv->options);
            return 0;
        };
    });
}

} // namespace fird::app
