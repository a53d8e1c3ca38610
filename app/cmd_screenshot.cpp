// fird screenshot SCENE --out DIR: the views as PNG files, with no window and no display.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "io/atomic_file.hpp"
#include "io/scene_file.hpp"
#include "parse.hpp"
#include "traced_scene.hpp"
#include "vk/context.hpp"
#include "vk/graphics_pipeline.hpp"

#ifdef FIRD_HAVE_UI
#include "workbench.hpp"
#endif

namespace fird::app {

namespace {

struct ScreenshotArgs {
    std::string scene, out, size = "1280x800", view = "all", camera, parameters, rays;
    std::int64_t pick = -1, quadtree_level = -1;
    std::uint32_t paths = 300;
    double plane_distance_m = 3.0;
    bool height_colours = false, slope_colours = false, curvature_colours = false, log = false,
         json = false;
};

render::OrbitCamera parse_camera(const std::string& text, render::OrbitCamera c) {
    const auto parts = split_list(text);
    if (parts.size() != 3) throw UsageError(fmt::format("--camera {}: not AZ,EL,DIST", text));
    const auto number = [&](const std::string& s) {
        try {
            std::size_t used = 0;
            const double v = std::stod(s, &used);
            if (used == s.size() && std::isfinite(v)) return v;
        } catch (const std::exception&) {
        }
        throw UsageError(fmt::format("--camera {}: '{}' is not a number", text, s));
    };
    c.azimuth_deg = number(parts[0]);
    c.elevation_deg = number(parts[1]);
    c.distance_mm = number(parts[2]);
    if (!(c.elevation_deg >= -90 && c.elevation_deg <= 90) || !(c.distance_mm > 0))
        throw UsageError(
            fmt::format("--camera {}: elevation within -90..90 deg and a distance > 0 mm", text));
    return c;
}

int run_screenshot(const GlobalOptions& global, const ScreenshotArgs& a) {
    const auto [w, h] = parse_size("--size", a.size, 64, 8192);
    static const std::vector<std::string> views{
        "viewport", "farfield", "plots", "all", "workbench", "polar", "isocandela", "illuminance"};
    if (std::find(views.begin(), views.end(), a.view) == views.end())
        throw UsageError(fmt::format("--view {}: one of viewport, farfield, plots, all, "
                                     "workbench, polar, isocandela, illuminance",
                                     a.view));
    if (a.view == "workbench") {
#ifdef FIRD_HAVE_UI
        std::uint64_t errors = 0;
        const auto rgba = ui::render_workbench_offscreen(global.device_name, global.validation,
                                                         a.scene, w, h, &errors);
        create_output_directory(a.out);
        const std::string path = (std::filesystem::path(a.out) / "workbench.png").string();
        render::write_rgba_png(path, rgba, w, h);
        if (errors > 0)
            throw std::runtime_error("Vulkan validation errors were reported (see above)");
        if (a.json)
            std::printf("%s\n", nlohmann::json{{"files", {path}}}.dump(2).c_str());
        else
            std::printf("wrote %s\n", path.c_str());
        return 0;
#else
        throw std::runtime_error("this fird was built without the ui floor (FIRD_BUILD_UI=OFF)");
#endif
    }
    render::TraceForViews t{.paths = a.paths};
    if (!a.parameters.empty()) t.parameters = parse_assignments("--parameters", a.parameters);
    if (!a.rays.empty()) t.rays = parse_count("--rays", a.rays, 4e9);
    if (a.pick >= 0) t.pick = std::uint64_t(a.pick);
    const Scene scene = load_scene(a.scene);
    render::ViewportOptions vo{.camera = render::frame_holder(scene.holder),
                               .quadtree = a.quadtree_level >= 0,
                               .quadtree_level =
                                   std::uint32_t(std::max<std::int64_t>(0, a.quadtree_level)),
                               .height_colours = a.height_colours,
                               .slope_colours = a.slope_colours,
                               .curvature_colours = a.curvature_colours};
    if (!a.camera.empty()) vo.camera = parse_camera(a.camera, vo.camera);
    const auto ctx = vk::Context::create(context_options(global));
    // The viewport is drawn by the device: a device that cannot is refused before the trace.
    if (a.view == "all" || a.view == "viewport") vk::require_fragment_shaders(ctx);
    const render::TracedScene traced = render::trace_for_views(ctx, scene, t);
    create_output_directory(a.out);
    nlohmann::json files = nlohmann::json::array();
    const auto path = [&](const char* n) {
        const std::string p = (std::filesystem::path(a.out) / n).string();
        files.push_back(p);
        return p;
    };
    const auto wrote = [&](const std::string& p) {
        if (!a.json) std::printf("wrote %s\n", p.c_str());
    };
    const bool all = a.view == "all";
    if (all || a.view == "viewport") {
        render::ViewportRenderer renderer(ctx);
        render::write_rgba_png(path("viewport.png"),
                               render::render_viewport(ctx, renderer, traced.viewport, vo, w, h), w,
                               h);
        wrote(files.back());
    }
    if (all || a.view == "farfield") {
        plot::Canvas cv{int(w), int(h)};
        render::draw_farfield_view(cv, {0, 0, double(w), double(h)}, traced.farfield,
                                   {.log_scale = a.log});
        cv.write_png(path("farfield.png"));
        wrote(files.back());
    }
    // The luminaire views (beside the desired ones): one file each, named as the view.
    for (const LuminaireView view :
         {LuminaireView::PolarMap, LuminaireView::Isocandela, LuminaireView::Illuminance}) {
        const std::string name = luminaire_view_name(view);
        if (!all && a.view != name) continue;
        plot::Canvas cv{int(w), int(h)};
        render::draw_farfield_view(
            cv, {0, 0, double(w), double(h)}, traced.farfield,
            {.log_scale = a.log, .luminaire = view, .plane_distance_m = a.plane_distance_m});
        cv.write_png(path((name + ".png").c_str()));
        wrote(files.back());
    }
    if (all || a.view == "plots") {
        plot::Canvas cv{int(w), int(h)};
        render::draw_profile_plots(cv, {0, 0, double(w), double(h)}, traced.farfield);
        cv.write_png(path("plots.png"));
        wrote(files.back());
    }
    if (ctx.validation_errors() > 0)
        throw std::runtime_error("Vulkan validation errors were reported (see above)");
    if (a.json) {
        nlohmann::json j{{"files", files}, {"rayset_rays", traced.rayset_rays}};
        if (traced.viewport.picked) j["picked_ray"] = picked_ray_json(*traced.viewport.picked);
        std::printf("%s\n", j.dump(2).c_str());
    }
    return 0;
}

} // namespace

void register_screenshot(CLI::App& app, const GlobalOptions& global, std::function<int()>& run) {
    auto* cmd = app.add_subcommand("screenshot", "Trace the scene and write its views as PNG "
                                                 "(no window, no display)");
    auto a = std::make_shared<ScreenshotArgs>();
    cmd->add_option("SCENE", a->scene, "Scene file (TOML)")->required();
    cmd->add_option("--out", a->out, "Output directory")->required();
    cmd->add_option("--size", a->size, "Image size WxH (default 1280x800)");
    cmd->add_option("--view", a->view,
                    "viewport, farfield, plots, polar, isocandela, illuminance, all (default) or "
                    "workbench");
    cmd->add_option("--plane-distance", a->plane_distance_m,
                    "Metres from the luminaire to the illuminance view's plane (default 3)")
        ->check(finite_range(1e-3, 1e4));
    cmd->add_option("--camera", a->camera, "Orbit camera AZ,EL,DIST (deg, deg, mm)");
    cmd->add_option("--parameters", a->parameters, "Reflector values, e.g. fx=15,fy=10");
    cmd->add_option("--rays", a->rays, "Rays to trace (default: the scene's)");
    cmd->add_option("--paths", a->paths, "Sample ray paths drawn")->check(CLI::Range(0.0, 5000.0));
    cmd->add_option("--pick-ray", a->pick,
                    "Trace ray INDEX of the rayset alone and show its path and RQRM walk")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--quadtree-level", a->quadtree_level, "Draw the quadtree nodes of a level")
        ->check(CLI::Range(0.0, 64.0));
    cmd->add_flag("--height-colours", a->height_colours, "Colour the reflector by height");
    CLI::Option* slope = cmd->add_flag(
        "--slope-colours", a->slope_colours,
        "Colour the reflector by its slope from the press plane, the steepest point marked");
    cmd->add_flag("--curvature-colours", a->curvature_colours,
                  "Colour the reflector by its bend radius (1000 mm blue to 1 mm yellow), the "
                  "tightest bend marked")
        ->excludes(slope);
    cmd->add_flag("--log", a->log, "Far fields on a log scale");
    cmd->add_flag("--json", a->json,
                  "Print one JSON object: the files written, and the picked ray's path and walk");
    cmd->callback(
        [&global, &run, a] { run = [&global, a] { return run_screenshot(global, *a); }; });
}

} // namespace fird::app
