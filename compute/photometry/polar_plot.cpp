#include "polar_plot.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "plot/chart.hpp"

namespace fird {

void draw_polar_plot(plot::Canvas& cv, const plot::Rect& area, const CandelaTable& t) {
    using plot::Point;
    constexpr double kDeg = std::numbers::pi / 180.0;
    const double cx = area.x + area.w / 2, cy = area.y + 40 + (area.h - 90) / 2;
    const double radius = std::min(area.w, area.h - 90) / 2 - 34;
    const double peak = t.peak_cd();
    // Rings at round candela values; spokes every 30 deg of gamma, labelled.
    const auto rings = plot::linear_ticks(0.0, peak > 0 ? peak : 1.0, 4);
    const double outer = rings.back() > 0 ? rings.back() : 1.0;
    for (double v : rings) {
        if (v <= 0.0) continue;
        std::vector<Point> ring;
        for (int k = 0; k <= 360; ++k)
            ring.push_back({cx + radius * v / outer * std::cos(k * kDeg),
                            cy + radius * v / outer * std::sin(k * kDeg)});
        cv.polyline(ring, {plot::kGrid, 1.0});
        cv.text(cx + 6, cy - radius * v / outer + 14, fmt::format("{:g} cd", v), 11.0);
    }
    for (int a = 0; a < 360; a += 30) {
        const Point end{cx + radius * std::sin(a * kDeg), cy + radius * std::cos(a * kDeg)};
        cv.line({cx, cy}, end, {plot::kGrid, 1.0});
        const int gamma = a <= 180 ? a : 360 - a;
        cv.text(cx + (radius + 16) * std::sin(a * kDeg),
                cy + (radius + 16) * std::cos(a * kDeg) + 4, fmt::format("{}°", gamma), 11.0,
                plot::Align::Centre);
    }
    // Gamma 0 (nadir) points down the picture; each plane pair spans left (C180 / C270)
    // and right (C0 / C90).
    const struct {
        double right_c, left_c;
        plot::Colour colour;
        const char* label;
    } planes[] = {{0.0, 180.0, plot::palette(1), "C0 – C180"},
                  {90.0, 270.0, plot::palette(0), "C90 – C270"}};
    for (const auto& p : planes) {
        std::vector<Point> curve;
        for (int k = 0; k <= 720; ++k) {
            const double signed_gamma = k * 0.5 - 180.0;
            const double c = signed_gamma >= 0.0 ? p.right_c : p.left_c;
            const double r = radius * intensity_cd(t, c, std::abs(signed_gamma)) / outer;
            curve.push_back(
                {cx + r * std::sin(signed_gamma * kDeg), cy + r * std::cos(signed_gamma * kDeg)});
        }
        cv.polyline(curve, {p.colour, 2.0});
    }
    cv.text(area.x + area.w / 2, area.y + 24,
            "Luminous intensity, principal planes (γ 0 = nadir, down)", 14.0, plot::Align::Centre,
            plot::kInk, 0.0, true);
    const double ly = area.y + area.h - 20;
    for (std::size_t i = 0; i < 2; ++i) {
        const double lx = area.x + area.w / 2 - 150 + 170.0 * double(i);
        cv.line({lx, ly - 4}, {lx + 26, ly - 4}, {planes[i].colour, 2.0});
        cv.text(lx + 32, ly, planes[i].label, 13.0);
    }
}

void write_polar_plot_png(const std::string& path, const CandelaTable& table) {
    plot::Canvas cv(680, 720);
    draw_polar_plot(cv, {0, 0, 680, 720}, table);
    cv.write_png(path);
}

} // namespace fird
