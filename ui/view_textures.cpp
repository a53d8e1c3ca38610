#include "view_textures.hpp"

#include <algorithm>
#include <cstring>
#include <functional>

#include "calibrate/calibration_report.hpp"
#include "optimize/search_report.hpp"
#include "plot/farfield_picture.hpp"

namespace fird::ui {

namespace {

std::uint64_t camera_hash(const WorkbenchState& s, const PickedRay* picked, std::uint32_t w,
                          std::uint32_t h) {
    const auto& c = s.viewport.camera;
    const auto& o = s.viewport.options;
    const double values[] = {c.target.x,
                             c.target.y,
                             c.target.z,
                             c.azimuth_deg,
                             c.elevation_deg,
                             c.distance_mm,
                             double(o.rays),
                             double(o.quadtree),
                             double(o.quadtree_level),
                             double(o.height_colours),
                             double(s.viewport.walk_step),
                             double(s.viewport.walk_trail),
                             double(w),
                             double(h),
                             picked ? double(picked->index) : -1.0,
                             picked ? double(picked->walk.size()) : -1.0};
    std::uint64_t hash = 1469598103934665603ull;
    for (double v : values) {
        std::uint64_t bits;
        std::memcpy(&bits, &v, 8);
        hash = (hash ^ bits) * 1099511628211ull;
    }
    return hash;
}

std::vector<std::uint8_t> canvas_rgba(plot::Canvas& cv) {
    return cv.rgba();
}

} // namespace

void upload(const vk::Context& ctx, ViewTexture& t, const std::vector<std::uint8_t>& rgba,
            std::uint32_t w, std::uint32_t h, std::uint64_t generation) {
    if (!t.texture || t.width != w || t.height != h) {
        t.texture = std::make_unique<vk::Texture>(ctx, w, h, "fird.workbench.view");
        t.width = w;
        t.height = h;
    }
    t.texture->upload(ctx, rgba.data());
    t.generation = generation;
}

void update_viewport_image(const vk::Context& ctx, render::ViewportRenderer& renderer,
                           WorkbenchState& s, const SceneSnapshot& snap, const PickedRay* picked,
                           std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 64u), h = std::max(h, 64u);
    const std::uint64_t view = camera_hash(s, picked, w, h);
    if (s.viewport_image.generation == snap.generation && s.drawn_camera_hash == view) return;
    render::ViewportContent content = snap.traced.viewport;
    content.picked = picked ? std::make_optional(*picked) : std::nullopt;
    render::ViewportOptions o = s.viewport.options;
    o.camera = s.viewport.camera;
    o.walk_steps = s.viewport.walk_step + 1; // up to the current step
    o.walk_trail = s.viewport.walk_trail;
    upload(ctx, s.viewport_image, render::render_viewport(ctx, renderer, content, o, w, h), w, h,
           snap.generation);
    s.drawn_camera_hash = view;
}

std::pair<double, double> farfield_band(const WorkbenchState& s, const FarField& f) {
    const auto band = plot::lit_altitude_band(f);
    const double centre = 0.5 * (band.first + band.second);
    const double half = 0.5 * (band.first - band.second) / std::max(1.0f, s.farfield.zoom);
    return {std::min(90.0, centre + half), std::max(-90.0, centre - half)};
}

void update_farfield_image(const vk::Context& ctx, WorkbenchState& s, const SceneSnapshot& snap,
                           std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 200u), h = std::max(h, 200u);
    const std::uint64_t generation = snap.generation * 64 + (s.farfield.log_scale ? 1 : 0) +
                                     2 * std::uint64_t(std::min(30.0f, s.farfield.zoom * 2.0f));
    if (s.farfield_image.generation == generation && s.farfield_image.width == w &&
        s.farfield_image.height == h)
        return;
    plot::Canvas cv{int(w), int(h)};
    render::draw_farfield_view(cv, {0, 0, double(w), double(h)}, snap.traced.farfield,
                               {.log_scale = s.farfield.log_scale,
                                .altitude_deg = farfield_band(s, snap.traced.farfield.obtained)});
    upload(ctx, s.farfield_image, canvas_rgba(cv), w, h, generation);
}

void update_search_plot(const vk::Context& ctx, WorkbenchState& s, const SearchProgress& p,
                        std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 200u), h = std::max(h, 200u);
    if (s.search_plot.generation == p.generation && s.search_plot.width == w &&
        s.search_plot.height == h)
        return;
    SearchResult r = p.result.value_or(SearchResult{});
    r.method = p.method;
    r.names = p.names;
    r.history = p.history;
    r.stages = p.stages;
    plot::Canvas cv{int(w), int(h)};
    draw_progress(cv, {0, 0, double(w), double(h)}, r);
    upload(ctx, s.search_plot, canvas_rgba(cv), w, h, p.generation);
}

void update_calibration_plot(const vk::Context& ctx, WorkbenchState& s,
                             const CalibrationProgress& c, const std::string& scene,
                             std::uint32_t w, std::uint32_t h) {
    w = std::max(w, 200u), h = std::max(h, 200u);
    if (s.calibration_plot.generation == c.generation && s.calibration_plot.width == w &&
        s.calibration_plot.height == h)
        return;
    plot::Canvas cv{int(w), int(h)};
    if (c.rays) {
        plot::draw_chart(cv, {0, 0, double(w), double(h)}, rays_table_chart(*c.rays, scene));
    } else if (c.semivariogram && !c.semivariogram->parameters.empty()) {
        const auto& ps = c.semivariogram->parameters;
        const double ph = double(h) / double(ps.size());
        for (std::size_t k = 0; k < ps.size(); ++k)
            plot::draw_chart(cv, {0, ph * double(k), double(w), ph},
                             semivariogram_chart(ps[k], c.semivariogram->rays, scene));
    } else {
        plot::Series runs{
            .kind = plot::Series::Kind::Points, .label = "l2 so far", .colour = plot::palette(0)};
        for (std::size_t i = 0; i < c.partial.size(); ++i) {
            runs.x.push_back(double(i));
            runs.y.push_back(c.partial[i]);
        }
        plot::draw_chart(cv, {0, 0, double(w), double(h)},
                         {.title = "Calibration running",
                          .x = {"run or point"},
                          .y = {"l2 (lm)"},
                          .series = {runs}});
    }
    upload(ctx, s.calibration_plot, canvas_rgba(cv), w, h, c.generation);
}

} // namespace fird::ui
