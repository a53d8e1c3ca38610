// fird export SCENE: the scene traced on the fast path, written as VTK XML files for
// ParaView (scene.pvd opens them all).
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "export/scene_export.hpp"
#include "io/scene_file.hpp"
#include "parse.hpp"
#include "vk/context.hpp"

namespace fird::app {

void register_export(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("export", "Write the scene's reflector, quadtree, ray paths "
                                             "and far fields as VTK files for ParaView");
    struct Args {
        std::string scene, parameters, rays, out = "export";
        std::uint32_t paths = 1000, levels = 0;
    };
    auto a = std::make_shared<Args>();
    cmd->add_option("SCENE", a->scene, "Scene file (TOML)")->required();
    cmd->add_option("--parameters", a->parameters, "Reflector values, e.g. fx=15,fy=10");
    cmd->add_option("--rays", a->rays, "Rays to trace (default: the scene's)");
    cmd->add_option("--paths", a->paths, "Sample ray paths to write (rays.vtp)")
        ->check(CLI::Range(0.0, double(kMaxPaths)));
    cmd->add_option("--levels", a->levels,
                    "Coarsest quadtree levels to write (default: under a million boxes)")
        ->check(CLI::Range(0.0, 64.0));
    cmd->add_option("--out", a->out, "Output directory (default: export)");
    cmd->callback([&global, &run, a] {
        run = [&global, a] {
            ExportOptions o{.paths = a->paths, .levels = a->levels};
            if (!a->parameters.empty())
                o.parameters = parse_assignments("--parameters", a->parameters);
            if (!a->rays.empty()) o.rays = parse_count("--rays", a->rays, 4e9);
            const Scene scene = load_scene(a->scene);
            const auto ctx = vk::Context::create(context_options(global));
            const ExportReport report = export_scene(ctx, scene, o, a->out);
            if (ctx.validation_errors() > 0)
                throw std::runtime_error("Vulkan validation errors were reported (see above)");
            for (const std::string& note : report.notes)
                std::fprintf(stderr, "fird: note: %s\n", note.c_str());
            std::uint64_t total = 0;
            for (const ExportedFile& f : report.files) {
                std::printf(
                    "%s", fmt::format("{}/{}: {:.2f} MB\n", a->out, f.name, double(f.bytes) * 1e-6)
                              .c_str());
                total += f.bytes;
            }
            std::printf("%s", fmt::format("{:.2f} MB in all; open {}/scene.pvd in ParaView\n",
                                          double(total) * 1e-6, a->out)
                                  .c_str());
            return 0;
        };
    });
}

} // namespace fird::app
