#include "views.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "photometry/farfield_photometry.hpp"
#include "photometry/polar_plot.hpp"
#include "plot/farfield_picture.hpp"

namespace fird::render {

namespace {

// Side by side with the polar curves when there is room (and the maps are one column); a
// narrow area shows the maps alone.
bool shows_polar(const plot::Rect& a, const FarFieldViewOptions& o) {
    return a.w >= 900.0 && o.columns <= 1;
}
double maps_width(const plot::Rect& a, const FarFieldViewOptions& o) {
    return shows_polar(a, o) ? a.w * 0.62 : a.w;
}
// The k-th of n maps, row by row in the options' columns.
plot::Rect map_area(const plot::Rect& a, std::size_t k, std::size_t n,
                    const FarFieldViewOptions& o) {
    const std::size_t columns = std::clamp<std::size_t>(std::size_t(std::max(1, o.columns)), 1, n);
    const std::size_t rows = (n + columns - 1) / columns;
    const double w = maps_width(a, o) / double(columns), h = a.h / double(rows);
    return {a.x + w * double(k % columns), a.y + h * double(k / columns), w, h};
}
// The maps the options show, in order.
std::vector<FarFieldMapKind> shown_maps(const FarFieldContent& c, const FarFieldViewOptions& o) {
    if (o.only && (c.desired || *o.only == FarFieldMapKind::Obtained)) return {*o.only};
    std::vector<FarFieldMapKind> kinds;
    if (c.desired) kinds.push_back(FarFieldMapKind::Desired);
    kinds.push_back(FarFieldMapKind::Obtained);
    if (c.desired) kinds.push_back(FarFieldMapKind::Difference);
    return kinds;
}
plot::FarFieldPicture picture(const FarFieldContent& c, const FarFieldViewOptions& o,
                              const std::string& name, bool difference) {
    return {.title = c.title.empty() ? name : c.title + ": " + name,
            .signed_values = difference,
            .log_scale = o.log_scale,
            .altitude_deg = o.altitude_deg
                                ? *o.altitude_deg
                                : plot::lit_altitude_band(plot::light_profiles(c.obtained)),
            .azimuth_deg = o.azimuth_deg};
}

} // namespace

FarFieldViewGrid farfield_view_grid(double w, double h, std::size_t n) {
    // A map's height in an area of one cell of the grid: the compact picture's margins
    // (title and tick labels, 42 px) off, and no more than a 360 deg map a third as high as
    // wide would use (beyond that, height is better spent in another row).
    const auto map_height = [&](int columns) {
        const std::size_t rows = (n + std::size_t(columns) - 1) / std::size_t(columns);
        const double cell_w = w / columns, cell_h = h / double(rows);
        return std::min(cell_h - 42.0, (cell_w - 110.0) / 3.0);
    };
    FarFieldViewGrid best{1, h};
    for (int columns = 2; columns <= int(std::max<std::size_t>(1, n)); ++columns)
        if (map_height(columns) > map_height(best.columns)) best.columns = columns;
    const std::size_t rows = (n + std::size_t(best.columns) - 1) / std::size_t(best.columns);
    if (map_height(best.columns) < kFarFieldMapMinPx)
        best = {1, std::max(h, double(n) * (kFarFieldMapMinPx + 42.0))};
    else
        best.height = std::max(h, double(rows) * (kFarFieldMapMinPx + 42.0));
    return best;
}

std::vector<FarFieldViewMap> farfield_view_maps(const plot::Rect& a, const FarFieldContent& c,
                                                const FarFieldViewOptions& o) {
    const std::vector<FarFieldMapKind> kinds = shown_maps(c, o);
    std::vector<FarFieldViewMap> maps;
    for (std::size_t k = 0; k < kinds.size(); ++k)
        maps.push_back({kinds[k], plot::farfield_map_placement(
                                      map_area(a, k, kinds.size(), o), c.obtained,
                                      picture(c, o, "", kinds[k] == FarFieldMapKind::Difference))});
    return maps;
}

std::optional<FarFieldCellAt> farfield_cell_at(const std::vector<FarFieldViewMap>& maps,
                                               const FarField& grid, double px, double py) {
    for (const FarFieldViewMap& m : maps) {
        const plot::Rect& r = m.placement.map;
        if (!(px >= r.x && px < r.x + r.w && py >= r.y && py < r.y + r.h)) continue;
        const std::uint32_t rows = m.placement.row1 - m.placement.row0;
        const std::uint32_t columns = m.placement.column1 - m.placement.column0;
        const auto col =
            std::min(grid.width - 1,
                     m.placement.column0 +
                         std::min(columns - 1, std::uint32_t((px - r.x) / r.w * double(columns))));
        const auto row =
            m.placement.row0 + std::min(rows - 1, std::uint32_t((py - r.y) / r.h * double(rows)));
        return FarFieldCellAt{m.kind, row, col};
    }
    return std::nullopt;
}

void draw_farfield_view(plot::Canvas& cv, const plot::Rect& a, const FarFieldContent& c,
                        const FarFieldViewOptions& o) {
    if (o.luminaire) {
        if (!(c.obtained.total_lm() > 0.0)) {
            cv.text(a.x + a.w / 2, a.y + a.h / 2, "no light in the far field", 13.0,
                    plot::Align::Centre);
            return;
        }
        const CandelaTable obtained = view_table(c.obtained);
        std::optional<CandelaTable> desired;
        if (c.desired && c.desired->total_lm() > 0.0) desired = view_table(*c.desired);
        draw_luminaire_view(cv, a, *o.luminaire, obtained, desired ? &*desired : nullptr,
                            {.title = c.title, .plane_distance_m = o.plane_distance_m});
        return;
    }
    const bool polar = shows_polar(a, o);
    const double maps_w = maps_width(a, o);
    const std::vector<FarFieldMapKind> kinds = shown_maps(c, o);
    for (std::size_t k = 0; k < kinds.size(); ++k) {
        const plot::Rect area = map_area(a, k, kinds.size(), o);
        if (kinds[k] == FarFieldMapKind::Desired) {
            plot::draw_farfield(cv, area, *c.desired, picture(c, o, "desired", false));
        } else if (kinds[k] == FarFieldMapKind::Obtained) {
            plot::draw_farfield(cv, area, c.obtained, picture(c, o, "obtained", false));
        } else {
            FarField diff = c.obtained;
            for (std::size_t i = 0; i < diff.lm.size(); ++i)
                diff.lm[i] -= c.desired->lm[i];
            plot::draw_farfield(
                cv, area, diff,
                picture(c, o,
                        c.l2_lm ? fmt::format("obtained − desired, l2 = {:.4g} lm", *c.l2_lm)
                                : "obtained − desired",
                        true));
        }
    }
    // Candela curves of the obtained light (and the desired, when there is one), as a
    // photometric viewer draws them.
    if (polar && c.obtained.total_lm() > 0.0 && c.obtained.width >= 72 && c.obtained.height >= 36) {
        const double cstep = std::max(5.0, 360.0 / c.obtained.width);
        const double gstep = std::max(1.0, 180.0 / c.obtained.height);
        draw_polar_plot(cv, {a.x + maps_w, a.y, a.w - maps_w, std::min(a.h, (a.w - maps_w) * 1.06)},
                        table_from_farfield(c.obtained, cstep, gstep));
    }
}

void draw_profile_plots(plot::Canvas& cv, const plot::Rect& a, const FarFieldContent& c) {
    const auto profile = [](const FarField& f, bool by_altitude) {
        std::vector<double> x, y;
        const std::uint32_t n = by_altitude ? f.height : f.width;
        for (std::uint32_t k = 0; k < n; ++k) {
            double s = 0.0;
            for (std::uint32_t m = 0; m < (by_altitude ? f.width : f.height); ++m)
                s += by_altitude ? f.lm[std::size_t(k) * f.width + m]
                                 : f.lm[std::size_t(m) * f.width + k];
            x.push_back(by_altitude ? 90.0 - (k + 0.5) * 180.0 / n
                                    : -180.0 + (k + 0.5) * 360.0 / n);
            y.push_back(s);
        }
        return std::pair{x, y};
    };
    for (int panel = 0; panel < 2; ++panel) {
        const bool alt = panel == 0;
        plot::Chart ch{.title = alt ? "Light against altitude" : "Light against azimuth",
                       .x = {alt ? "altitude θ (deg)" : "azimuth φ (deg)", plot::Scale::Linear},
                       .y = {alt ? "lm per row" : "lm per column", plot::Scale::Linear}};
        if (alt) {
            const auto band = plot::lit_altitude_band(plot::light_profiles(c.obtained));
            ch.x.min = band.second;
            ch.x.max = band.first;
        }
        auto [x, y] = profile(c.obtained, alt);
        ch.series.push_back({.label = "obtained", .x = x, .y = y, .colour = plot::palette(0)});
        if (c.desired) {
            auto [dx, dy] = profile(*c.desired, alt);
            ch.series.push_back(
                {.label = "desired", .x = dx, .y = dy, .colour = plot::palette(1), .dashed = true});
        }
        plot::draw_chart(cv, {a.x, a.y + a.h / 2 * panel, a.w, a.h / 2}, ch);
    }
}

std::vector<std::uint8_t> render_viewport(const vk::Context& ctx, ViewportRenderer& renderer,
                                          const ViewportContent& content,
                                          const ViewportOptions& options, std::uint32_t width,
                                          std::uint32_t height) {
    const OffscreenTarget target(ctx, width, height, "fird.viewport.target");
    ctx.submit_and_wait([&](VkCommandBuffer cb) { renderer.record(cb, target, content, options); });
    return target.read_rgba(ctx);
}

void write_rgba_png(const std::string& path, const std::vector<std::uint8_t>& rgba,
                    std::uint32_t width, std::uint32_t height) {
    plot::Canvas cv{int(width), int(height)};
    std::vector<std::uint8_t> rgb(std::size_t(width) * height * 3);
    for (std::size_t i = 0; i < std::size_t(width) * height; ++i)
        for (int k = 0; k < 3; ++k)
            rgb[i * 3 + k] = rgba[i * 4 + k];
    cv.image(rgb, int(width), int(height), 0, 0, double(width), double(height));
    cv.write_png(path);
}

} // namespace fird::render
