// fird export SCENE: the scene traced on the fast path, written as VTK XML files for
// ParaView (scene.pvd opens them all); with --cad, the reflector as CAD (STEP and STL).
#include <cstdio>

#include <cmath>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "export/cad_option_error.hpp"
#include "export/export_modules.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "optimize/parameter_space.hpp"
#include "parse.hpp"
#include "report/manufacturability.hpp"
#include "vk/context.hpp"

namespace fird::app {

namespace {

void print_cad_report(const std::string& dir, const CadReport& r) {
    const std::string surface =
        r.revolved ? fmt::format("the profile's B-spline meridian ({} heights) revolved, exact, "
                                 "trimmed to the holder (edges within {:.2g} mm)",
                                 r.fit_nx, r.trim_tolerance_mm)
        : r.exact  ? fmt::format("the family's B-spline, exact ({} x {} control heights)", r.fit_nx,
                                 r.fit_ny)
                   : fmt::format("B-spline fitted to {} x {} heights", r.fit_nx, r.fit_ny);
    std::printf("%s", fmt::format("CAD surface: {}{}; largest deviation {:.2g} mm at ({:.2f}, "
                                  "{:.2f}) mm on {} x {} points\n",
                                  r.creased ? "the family without its clamp, " : "", surface,
                                  r.max_deviation_mm, r.worst_xy_mm.x, r.worst_xy_mm.y, r.check_nx,
                                  r.check_ny)
                          .c_str());
    if (r.creased)
        std::printf("%s", fmt::format("trimmed where the holder's z range clamps it, flat "
                                      "beyond; crease edges within {:.2g} mm\n",
                                      r.edge_tolerance_mm)
                              .c_str());
    if (r.stl_nx > 0) { // a grid's STL: the surface sampled, its back radius measured
        std::printf("%s",
                    fmt::format("smallest radius of curvature towards the back: {:.4g} mm "
                                "at ({:.2f}, {:.2f}) mm (a sheet must be thinner)\n",
                                r.back_radius_mm, r.back_radius_xy_mm.x, r.back_radius_xy_mm.y)
                        .c_str());
        std::printf("%s", fmt::format("STL: {} x {} samples, facets within {:.2g} mm of the CAD "
                                      "surface\n",
                                      r.stl_nx, r.stl_ny, r.stl_chord_mm)
                              .c_str());
    } else {
        std::printf("%s", fmt::format("STL: OpenCASCADE's tessellation, facets within {:.2g} mm "
                                      "of the faces\n",
                                      r.stl_chord_mm)
                              .c_str());
    }
    if (r.bend)
        std::printf("%s", fmt::format("sheet: {} crease edge(s), {:.1f} mm, bent with radius {:g} "
                                      "mm; the bends leave the family by up to {:.3g} mm at "
                                      "({:.2f}, {:.2f}) mm\n",
                                      r.bend->creases, r.bend->crease_length_mm, r.bend->radius_mm,
                                      r.bend->max_deviation_mm, r.bend->worst_xy_mm.x,
                                      r.bend->worst_xy_mm.y)
                              .c_str());
    if (r.bend && r.bend->unformed_flats > 0)
        std::printf("%s", fmt::format("sheet: {} clamped flat(s) smaller than the bend's disc not "
                                      "formed: the sheet follows the family there, up to {:.3g} "
                                      "mm past the holder\n",
                                      r.bend->unformed_flats, r.bend->unformed_depth_mm)
                              .c_str());
    for (const ExportedFile& f : r.files)
        std::printf("%s",
                    fmt::format("{}/{}: {:.2f} MB\n", dir, f.name, double(f.bytes) * 1e-6).c_str());
}

nlohmann::json cad_json(const CadReport& r) {
    nlohmann::json files = nlohmann::json::array();
    for (const ExportedFile& f : r.files)
        files.push_back({{"name", f.name}, {"bytes", f.bytes}});
    return {{"exact", r.exact},
            {"form", r.revolved ? "revolved" : "height_field"},
            {"trim_edge_tolerance_mm", r.trim_tolerance_mm},
            {"creased", r.creased},
            {"crease_edge_tolerance_mm", r.edge_tolerance_mm},
            {"max_deviation_mm", r.max_deviation_mm},
            {"worst_at_mm", {r.worst_xy_mm.x, r.worst_xy_mm.y}},
            {"fit_grid", {r.fit_nx, r.fit_ny}},
            {"check_grid", {r.check_nx, r.check_ny}},
            {"back_radius_mm",
             std::isfinite(r.back_radius_mm) ? nlohmann::json(r.back_radius_mm) : nullptr},
            {"stl_chord_mm", r.stl_chord_mm},
            {"bend", r.bend ? nlohmann::json{{"radius_mm", r.bend->radius_mm},
                                             {"creases", r.bend->creases},
                                             {"crease_length_mm", r.bend->crease_length_mm},
                                             {"max_deviation_mm", r.bend->max_deviation_mm},
                                             {"worst_at_mm",
                                              {r.bend->worst_xy_mm.x, r.bend->worst_xy_mm.y}},
                                             {"unformed_flats", r.bend->unformed_flats},
                                             {"unformed_depth_mm", r.bend->unformed_depth_mm}}
                            : nlohmann::json(nullptr)},
            {"files", files}};
}

void print_manufacturability(const std::string& dir, const nlohmann::json& j) {
    const auto at = [](const nlohmann::json& p) {
        return p.is_null()
                   ? std::string("-")
                   : fmt::format("({:.2f}, {:.2f}) mm", p[0].get<double>(), p[1].get<double>());
    };
    std::string text = fmt::format(
        "press: steepest slope {:.2f} deg at {}; smallest radius {}; depth {:.3f} mm; "
        "area {:.1f} mm2; {} rim wall(s)\n",
        j["max_slope_deg"].get<double>(), at(j["max_slope_at_mm"]),
        j["min_radius_mm"].is_null()
            ? std::string("none (no curvature)")
            : fmt::format("{:.4g} mm at {}{}", j["min_radius_mm"].get<double>(),
                          at(j["min_radius_at_mm"]),
                          j["min_radius_is_kink"].get<bool>() ? " (a kink)" : ""),
        j["depth_mm"].get<double>(), j["area_mm2"].get<double>(), j["rim_walls"].size());
    for (const auto& [name, c] : j["constraints"].items())
        text += fmt::format("constraint {}: {} (limit {:g})\n", name,
                            c["met"].get<bool>() ? "met" : "BROKEN", c["limit"].get<double>());
    text += fmt::format("{}/manufacturability.json, {}/manufacturability.png\n", dir, dir);
    std::printf("%s", text.c_str());
}

} // namespace

void register_export(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("export", "Write the scene's reflector, quadtree, ray paths "
                                             "and far fields as VTK files for ParaView");
    struct Args {
        std::string scene, parameters, rays, out = "export", cad, press;
        bool json = false;
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
    cmd->add_option("--bend-radius", a->cad_options.bend_radius_mm,
                    "With --thickness on a reflector the holder clamps: the radius its creases "
                    "are bent to, mm (default: twice the thickness)");
    cmd->add_option("--manufacturability", a->press,
                    "Write the press's report here: manufacturability.json and .png (slope, "
                    "radius of curvature, depth, area, rim walls, [reflector.constraints]); "
                    "--cad writes it too, beside reflector.step");
    cmd->add_flag("--json", a->json,
                  "Print one JSON object (cad, manufacturability, vtk_files) instead of lines");
    cmd->callback([&global, &run, a, out] {
        const bool vtk = (a->cad.empty() && a->press.empty()) || out->count() > 0;
        run = [&global, a, vtk] {
            ExportOptions o{.paths = a->paths, .levels = a->levels};
            if (!a->parameters.empty())
                o.parameters = parse_assignments("--parameters", a->parameters);
            if (!a->rays.empty()) o.rays = parse_count("--rays", a->rays, 4e9);
            nlohmann::json j{
                {"cad", nullptr}, {"manufacturability", nullptr}, {"vtk_files", nullptr}};
            // The modules this export loads, after the options' usage errors and before the
            // scene, the device or a file.
            if (!a->cad.empty()) (void)cad_exports();
            if (vtk) (void)vtk_exports();
            if (!a->cad.empty() || !a->press.empty()) {
                const Scene scene = load_scene(a->scene);
                const ReflectorDesc reflector = overridden(scene, o.parameters);
                const Surface surface = Surface::make(reflector, scene.holder);
                if (!a->cad.empty()) {
                    CadReport r;
                    try {
                        r = cad_exports().cad(surface, a->cad_options, a->cad);
                    } catch (const CadOptionError& e) {
                        throw UsageError(e.what());
                    }
                    j["cad"] = cad_json(r);
                    if (!a->json) print_cad_report(a->cad, r);
                }
                // Beside the CAD files, and where --manufacturability asks (once if the same).
                std::vector<std::string> dirs;
                if (!a->cad.empty()) dirs.push_back(a->cad);
                if (!a->press.empty() && a->press != a->cad) dirs.push_back(a->press);
                for (const std::string& dir : dirs) {
                    create_output_directory(dir);
                    j["manufacturability"] =
                        write_manufacturability(dir, surface, reflector.constraints);
                    if (!a->json) print_manufacturability(dir, j["manufacturability"]);
                }
                if (!vtk) {
                    if (a->json) std::printf("%s\n", j.dump(2).c_str());
                    return 0;
                }
            }
            const Scene scene = load_scene(a->scene);
            const auto ctx = vk::Context::create(context_options(global));
            const ExportReport report = vtk_exports().scene(ctx, scene, o, a->out);
            if (ctx.validation_errors() > 0)
                throw std::runtime_error("Vulkan validation errors were reported (see above)");
            for (const std::string& note : report.notes)
                std::fprintf(stderr, "fird: note: %s\n", note.c_str());
            std::uint64_t total = 0;
            j["vtk_files"] = nlohmann::json::array();
            for (const ExportedFile& f : report.files) {
                j["vtk_files"].push_back({{"name", f.name}, {"bytes", f.bytes}});
                if (!a->json)
                    std::printf("%s", fmt::format("{}/{}: {:.2f} MB\n", a->out, f.name,
                                                  double(f.bytes) * 1e-6)
                                          .c_str());
                total += f.bytes;
            }
            if (a->json)
                std::printf("%s\n", j.dump(2).c_str());
            else
                std::printf("%s", fmt::format("{:.2f} MB in all; open {}/scene.pvd in ParaView\n",
                                              double(total) * 1e-6, a->out)
                                      .c_str());
            return 0;
        };
    });
}

} // namespace fird::app
