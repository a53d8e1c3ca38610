#include "manufacturability.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>

#include "io/atomic_file.hpp"
#include "plot/canvas.hpp"
#include "plot/chart.hpp"
#include "plot/colormap.hpp"

namespace fird {

namespace {

nlohmann::json xy(const glm::dvec2& p) {
    return {p.x, p.y};
}

// JSON has no infinity: a radius without curvature (a plane) or unmeasured (a mesh) is null.
nlohmann::json finite_or_null(double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

struct MapPanel {
    const std::vector<float>& values;
    std::string title, unit;
    glm::dvec2 worst;
    std::string worst_label;
};

// One map seen from above (+y up), coloured 0 .. its largest value, the clamp's flats grey,
// the worst point ringed, a colour bar on the right.
void draw_map(plot::Canvas& cv, const plot::Rect& a, const PressMeasures& m, const Holder& h,
              const MapPanel& p) {
    using namespace plot;
    // The colours span 0 to the 99.5th percentile: a kink's one huge value would leave
    // the rest of the map black.
    std::vector<float> finite;
    for (float v : p.values)
        if (std::isfinite(v)) finite.push_back(v);
    double top = 0.0;
    if (!finite.empty()) {
        const std::size_t k =
            std::min(finite.size() - 1, std::size_t(0.995 * double(finite.size())));
        std::nth_element(finite.begin(), finite.begin() + std::ptrdiff_t(k), finite.end());
        top = finite[k];
    }
    const double wx = h.max_mm.x - h.min_mm.x, wy = h.max_mm.y - h.min_mm.y;
    const double avail_w = a.w - 110.0, avail_h = a.h - 90.0;
    const double scale = std::min(avail_w / wx, avail_h / wy);
    const double mw = wx * scale, mh = wy * scale;
    const double mx = a.x + 40.0, my = a.y + 40.0;
    std::vector<std::uint8_t> rgb(std::size_t(m.nx) * m.ny * 3);
    for (int j = 0; j < m.ny; ++j)
        for (int i = 0; i < m.nx; ++i) {
            const float v = p.values[std::size_t(j) * m.nx + i];
            const Rgb c = std::isfinite(v)
                              ? sequential_colour(top > 0.0 ? std::min(v / top, 1.0) : 0.0)
                              : Rgb{200, 200, 200};
            // Row 0 of the picture is the holder's y max (seen from above, +y up).
            std::copy(c.begin(), c.end(), rgb.begin() + (std::size_t(m.ny - 1 - j) * m.nx + i) * 3);
        }
    cv.text(a.x + 40.0, a.y + 22.0, p.title, 15.0, Align::Left, kInk, 0.0, true);
    cv.image(rgb, m.nx, m.ny, mx, my, mw, mh);
    cv.stroke_rect(mx, my, mw, mh, {kInk, 1.0});
    const Point worst{mx + (p.worst.x - h.min_mm.x) * scale, my + (h.max_mm.y - p.worst.y) * scale};
    cv.polyline({{worst.x - 9, worst.y}, {worst.x + 9, worst.y}}, {kWhite, 3.0});
    cv.polyline({{worst.x, worst.y - 9}, {worst.x, worst.y + 9}}, {kWhite, 3.0});
    cv.polyline({{worst.x - 8, worst.y}, {worst.x + 8, worst.y}}, {{0.0, 0.6, 1.0}, 1.8});
    cv.polyline({{worst.x, worst.y - 8}, {worst.x, worst.y + 8}}, {{0.0, 0.6, 1.0}, 1.8});
    cv.text(mx, my + mh + 18.0, p.worst_label, 12.0);
    cv.text(mx, my + mh + 34.0,
            fmt::format("x {:g} .. {:g} mm, y {:g} .. {:g} mm; grey: held flat by the clamp",
                        h.min_mm.x, h.max_mm.x, h.min_mm.y, h.max_mm.y),
            11.0);
    // The colour bar, 0 at the bottom.
    const double bx = mx + mw + 14.0, bw = 14.0;
    std::vector<std::uint8_t> bar(256 * 3);
    for (int k = 0; k < 256; ++k) {
        const Rgb c = sequential_colour(1.0 - k / 255.0);
        std::copy(c.begin(), c.end(), bar.begin() + k * 3);
    }
    cv.image(bar, 1, 256, bx, my, bw, mh);
    cv.stroke_rect(bx, my, bw, mh, {kInk, 1.0});
    cv.text(bx + bw + 4.0, my + 10.0, fmt::format("≥ {:.3g}", top), 11.0);
    cv.text(bx + bw + 4.0, my + mh, "0", 11.0);
    cv.text(bx + bw + 4.0, my + mh * 0.5, p.unit, 11.0);
}

} // namespace

nlohmann::json manufacturability_json(const PressMeasures& m, const ConstraintsDesc& c) {
    nlohmann::json walls = nlohmann::json::array();
    for (const RimWall& w : m.rim_walls)
        walls.push_back({{"side", w.side},
                         {"from_mm", xy(w.from_mm)},
                         {"to_mm", xy(w.to_mm)},
                         {"length_mm", w.length_mm},
                         {"height_mm", w.height_mm}});
    nlohmann::json constraints = nlohmann::json::object();
    for (const ConstraintCheck& k : check_constraints(m, c))
        constraints[k.name] = {
            {"value", finite_or_null(k.value)}, {"limit", k.limit}, {"met", k.met}};
    return {{"max_slope_deg", m.max_slope_deg},
            {"max_slope_at_mm", xy(m.max_slope_at_mm)},
            {"min_radius_mm", finite_or_null(m.min_radius_mm)},
            {"min_radius_at_mm", std::isfinite(m.min_radius_mm) ? xy(m.min_radius_at_mm) : nullptr},
            {"min_radius_is_kink", m.kink},
            {"depth_mm", m.depth_mm},
            // What an [optimize] smoothness weight penalises (on the full grid here).
            {"bending_energy", finite_or_null(m.bending_energy)},
            {"area_mm2", m.area_mm2},
            {"unclamped_area_mm2", m.unclamped_area_mm2},
            {"rim_walls", walls},
            {"constraints", constraints},
            {"sampling",
             {{"grid", {m.nx, m.ny}},
              {"step_mm", {m.dx_mm, m.dy_mm}},
              {"slope_error_deg", m.slope_error_deg},
              {"curvature_error_per_mm", m.curvature_error_per_mm},
              {"curvature", "central differences of the family's analytic gradient"}}}};
}

void write_manufacturability_png(const std::string& path, const PressMeasures& m, const Holder& h) {
    if (m.maps.slope_deg.empty())
        throw std::logic_error("write_manufacturability_png: the measures have no maps");
    const double wx = h.max_mm.x - h.min_mm.x, wy = h.max_mm.y - h.min_mm.y;
    const double panel_w = 560.0;
    const double panel_h = std::clamp((panel_w - 110.0) * wy / wx, 200.0, 700.0) + 90.0;
    plot::Canvas cv(int(2 * panel_w), int(panel_h));
    draw_map(cv, {0, 0, panel_w, panel_h}, m, h,
             {m.maps.slope_deg, "Slope from the press plane", "deg", m.max_slope_at_mm,
              fmt::format("steepest {:.2f}° at ({:.2f}, {:.2f}) mm (the draft the die needs)",
                          m.max_slope_deg, m.max_slope_at_mm.x, m.max_slope_at_mm.y)});
    draw_map(cv, {panel_w, 0, panel_w, panel_h}, m, h,
             {m.maps.curvature_per_mm, "Curvature (larger principal)", "1/mm", m.min_radius_at_mm,
              m.kink ? fmt::format("a kink (radius 0) at ({:.2f}, {:.2f}) mm", m.min_radius_at_mm.x,
                                   m.min_radius_at_mm.y)
              : std::isfinite(m.min_radius_mm)
                  ? fmt::format("smallest radius {:.3g} mm at ({:.2f}, {:.2f}) mm", m.min_radius_mm,
                                m.min_radius_at_mm.x, m.min_radius_at_mm.y)
                  : std::string("no curvature")});
    cv.write_png(path);
}

nlohmann::json write_manufacturability(const std::string& directory, const Surface& surface,
                                       const ConstraintsDesc& constraints) {
    const PressMeasures m = press_measures(surface, {.maps = true});
    const nlohmann::json j = manufacturability_json(m, constraints);
    const std::filesystem::path dir(directory);
    write_text_file((dir / "manufacturability.json").string(), j.dump(2) + "\n");
    write_manufacturability_png((dir / "manufacturability.png").string(), m, surface.holder());
    return j;
}

} // namespace fird
