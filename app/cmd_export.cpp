// fird export SCENE: the scene traced on the fast path, written as VTK XML files for
// ParaView (scene.pvd opens them all); with --cad, the reflector as CAD (STEP and STL).
#include <cstdio>

#include <fmt/format.h>

#include "commands.hpp"
#include "export/cad_export.hpp"
#include "export/cad_option_error.hpp"
#include "export/scene_export.hpp"
#include "io/scene_file.hpp"
#include "parse.hpp"
#include "vk/context.hpp"

namespace fird::app {

namespace {

void print_cad_report(const std::string& dir, const CadReport& r) {
    const std::string surface =
        r.exact ? fmt::format("the family's B-spline, exact ({} x {} control heights)", r.fit_nx,
                              r.fit_ny)
                : fmt::format("B-spline fitted to {} x {} heights", r.fit_nx, r.fit_ny);
    std::printf("%s", fmt::format("CAD surface: {}{}; largest deviation {:.2g} mm at ({:.2f}, "
                                  "{:.2f}) mm on {} x {} points\n",
                                  r.creased ? "the family without its clamp, " : "", surface,
                                  r.max_deviation_mm, r.worst_xy_mm.x, r.worst_xy_mm.y, r.check_nx,
                                  r.check_ny)
                          .c_str());
    if (r.creased) {
        std::printf("%s", fmt::format("trimmed where the holder's z range clamps it, flat "
                                      "beyond; crease edges within {:.2g} mm\n",
                                      r.edge_tolerance_mm)
                              .c_str());
        std::printf("%s", fmt::format("STL: OpenCASCADE's tessellation, facets within {:.2g} mm "
                                      "of the faces\n",
                                      r.stl_chord_mm)
                              .c_str());
    } else {
        std::printf("%s",
                    fmt::format("smallest radius of curvature towards the back: {:.4g} mm "
                                "at ({:.2f}, {:.2f}) mm (a sheet must be thinner)\n",
                                r.back_radius_mm, r.back_radius_xy_mm.x, r.back_radius_xy_mm.y)
                        .c_str());
        std::printf("%s", fmt::format("STL: {} x {} samples, facets within {:.2g} mm of the CAD "
                                      "surface\n",
                                      r.stl_nx, r.stl_ny, r.stl_chord_mm)
                              .c_str());
    }
    for (const ExportedFile& f : r.files)
        std::printf("%s",
                    fmt::format("{}/{}: {:.2f} MB\n", dir, f.name, double(f.bytes) * 1e-6).c_str());
}

} // namespace

void register_export(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("export", "Write the scene's reflector, quadtree, ray paths "
                                             "and far fields as VTK files for ParaView");
    struct Args {
        std::string scene, parameters, rays, out = "export", cad;
        std::uint32_t paths = 1000, levels = 0;
        CadOptions cad_options;
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
    auto* out = cmd->add_option("--out", a->out, "Output directory (default: export)");
    cmd->add_option("--cad", a->cad,
                    "Write the reflector as CAD here: reflector.step (B-spline surface, mm) and "
                    "reflector.stl (binary); the VTK files then only with --out");
    cmd->add_option("--cad-tolerance", a->cad_options.tolerance_mm,
                    "Largest height deviation of a fitted CAD surface, mm (default 0.01)");
    cmd->add_option("--thickness", a->cad_options.thickness_mm,
                    "Thicken the CAD reflector into a solid sheet this thick, mm, its back face "
                    "offset along the normal (default: the surface alone)");
    cmd->callback([&global, &run, a, out] {
        const bool vtk = a->cad.empty() || out->count() > 0;
        run = [&global, a, vtk] {
            ExportOptions o{.paths = a->paths, .levels = a->levels};
            if (!a->parameters.empty())
                o.parameters = parse_assignments("--parameters", a->parameters);
            if (!a->cad.empty()) {
                const Scene scene = load_scene(a->scene);
                const Surface surface =
                    Surface::make(overridden(scene, o.parameters), scene.holder);
                CadReport r;
                try {
                    r = export_cad(surface, a->cad_options, a->cad);
                } catch (const CadOptionError& e) {
                    throw UsageError(e.what());
                }
                print_cad_report(a->cad, r);
                if (!vtk) return 0;
            }
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
