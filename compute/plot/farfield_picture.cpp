#include "farfield_picture.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "plot/colormap.hpp"

namespace fird::plot {

namespace {

constexpr double kMarginLeft = 70, kMarginTop = 40, kMarginBottom = 56, kBarGap = 26, kBarW = 22,
                 kBarLabels = 92;

// Rows [r0, r1) of the far field shown for the options' altitude band.
std::pair<std::uint32_t, std::uint32_t> shown_rows(const FarField& f, const FarFieldPicture& o) {
    if (!o.altitude_deg) return {0, f.height};
    const auto row = [&](double alt_deg) {
        return std::clamp(std::floor((90.0 - alt_deg) / 180.0 * f.height), 0.0, double(f.height));
    };
    const auto r0 = std::uint32_t(row(o.altitude_deg->first));
    const auto r1 = std::uint32_t(std::ceil((90.0 - o.altitude_deg->second) / 180.0 * f.height));
    return {r0, std::max(r0 + 1, std::min(r1, f.height))};
}

double colour_position(double v, double peak, const FarFieldPicture& o) {
    if (!(peak > 0.0)) return 0.0;
    if (!o.log_scale) return v / peak;
    // Four decades below the peak; the sign is kept for differences.
    const double a = std::abs(v) / peak;
    const double t = a > 1e-4 ? (std::log10(a) + 4.0) / 4.0 : 0.0;
    return v < 0 ? -t : t;
}

Rgb colour(double t, bool signed_values) {
    return signed_values ? diverging_colour(t) : sequential_colour(t);
}

} // namespace

std::pair<double, double> lit_altitude_band(const FarField& f, double fraction) {
    std::vector<double> rows(f.height, 0.0);
    double total = 0.0;
    for (std::uint32_t r = 0; r < f.height; ++r)
        for (std::uint32_t c = 0; c < f.width; ++c) {
            rows[r] += std::abs(f.lm[std::size_t(r) * f.width + c]);
            total += std::abs(f.lm[std::size_t(r) * f.width + c]);
        }
    if (!(total > 0.0)) return {90.0, -90.0};
    std::uint32_t r0 = 0, r1 = f.height;
    for (double s = 0.0; r0 < f.height && s + rows[r0] <= 0.5 * fraction * total; ++r0)
        s += rows[r0];
    for (double s = 0.0; r1 > r0 + 1 && s + rows[r1 - 1] <= 0.5 * fraction * total; --r1)
        s += rows[r1 - 1];
    const double deg_per_row = 180.0 / f.height;
    const double hi = 90.0 - r0 * deg_per_row, lo = 90.0 - r1 * deg_per_row;
    const double margin = std::max(2.0, 0.1 * (hi - lo));
    return {std::min(90.0, hi + margin), std::max(-90.0, lo - margin)};
}

FarFieldMapPlacement farfield_map_placement(const Rect& a, const FarField& f,
                                            const FarFieldPicture& o) {
    const auto [r0, r1] = shown_rows(f, o);
    return {{a.x + kMarginLeft, a.y + kMarginTop, a.w - kMarginLeft - kBarGap - kBarW - kBarLabels,
             a.h - kMarginTop - kMarginBottom},
            r0,
            r1};
}

void draw_farfield(Canvas& cv, const Rect& a, const FarField& f, const FarFieldPicture& o) {
    const FarFieldMapPlacement placed = farfield_map_placement(a, f, o);
    const std::uint32_t r0 = placed.row0, r1 = placed.row1;
    const double map_x = placed.map.x, map_y = placed.map.y;
    const double map_w = placed.map.w, map_h = placed.map.h;
    // One image pixel per screen pixel (at most one per cell): each shows the largest
    // |value| of the cells it covers.
    const int iw = int(std::clamp<double>(std::min<double>(f.width, map_w), 1.0, 4096.0));
    const int ih = int(std::clamp<double>(std::min<double>(r1 - r0, map_h), 1.0, 4096.0));
    double peak = 0.0;
    for (std::uint32_t r = r0; r < r1; ++r)
        for (std::uint32_t c = 0; c < f.width; ++c)
            peak = std::max(peak, std::abs(f.lm[std::size_t(r) * f.width + c]));
    std::vector<std::uint8_t> rgb(std::size_t(iw) * ih * 3);
    const std::uint32_t rows = r1 - r0;
    for (int py = 0; py < ih; ++py) {
        const auto ra = r0 + std::uint32_t(std::uint64_t(py) * rows / ih);
        const auto rb = std::max(ra + 1, r0 + std::uint32_t(std::uint64_t(py + 1) * rows / ih));
        for (int px = 0; px < iw; ++px) {
            const auto ca = std::uint32_t(std::uint64_t(px) * f.width / iw);
            const auto cb = std::max(ca + 1, std::uint32_t(std::uint64_t(px + 1) * f.width / iw));
            double v = 0.0;
            for (std::uint32_t r = ra; r < rb; ++r)
                for (std::uint32_t c = ca; c < cb; ++c) {
                    const double x = f.lm[std::size_t(r) * f.width + c];
                    if (std::abs(x) > std::abs(v)) v = x;
                }
            const Rgb col = colour(colour_position(v, peak, o), o.signed_values);
            std::copy(col.begin(), col.end(), rgb.begin() + (std::size_t(py) * iw + px) * 3);
        }
    }
    cv.image(rgb, iw, ih, map_x, map_y, map_w, map_h);
    cv.stroke_rect(map_x, map_y, map_w, map_h, {kInk, 1.0});

    // Degree axes: azimuth every 45 deg, altitude at round steps of the band shown.
    for (int deg = -180; deg <= 180; deg += 45) {
        const double x = map_x + (deg + 180.0) / 360.0 * map_w;
        cv.line({x, map_y + map_h}, {x, map_y + map_h + 5}, {kInk, 1.0});
        cv.text(x, map_y + map_h + 19, fmt::format("{}°", deg), 12.0, Align::Centre);
    }
    const double alt_hi = 90.0 - r0 * 180.0 / f.height, alt_lo = 90.0 - r1 * 180.0 / f.height;
    for (double deg : linear_ticks(alt_lo, alt_hi, 6)) {
        const double y = map_y + (alt_hi - deg) / (alt_hi - alt_lo) * map_h;
        cv.line({map_x - 5, y}, {map_x, y}, {kInk, 1.0});
        cv.text(map_x - 8, y + 4.5, fmt::format("{:g}°", deg), 12.0, Align::Right);
    }
    cv.text(map_x + map_w / 2, a.y + a.h - 12, "azimuth φ", 13.0, Align::Centre);
    cv.text(a.x + 16, map_y + map_h / 2, "altitude θ", 13.0, Align::Centre, kInk, 90.0);
    // The title, with the grid and total where the width allows.
    const std::string full = fmt::format("{}   ({} × {} cells, total {:.4g} lm)", o.title, f.width,
                                         f.height, f.total_lm());
    const double size = std::clamp(a.w / 60.0, 11.0, 15.0);
    cv.text(a.x + a.w / 2, a.y + 24, cv.text_width(full, size, true) < a.w - 20 ? full : o.title,
            size, Align::Centre, kInk, 0.0, true);

    // Colour bar with its scale.
    const double bx = map_x + map_w + kBarGap;
    std::vector<std::uint8_t> bar(256 * 3);
    for (int k = 0; k < 256; ++k) {
        const double t = 1.0 - k / 255.0;
        const Rgb col = colour(o.signed_values ? 2.0 * t - 1.0 : t, o.signed_values);
        std::copy(col.begin(), col.end(), bar.begin() + k * 3);
    }
    cv.image(bar, 1, 256, bx, map_y, kBarW, map_h);
    cv.stroke_rect(bx, map_y, kBarW, map_h, {kInk, 1.0});
    const auto bar_label = [&](double t, const std::string& s) {
        const double y = map_y + (1.0 - t) * map_h;
        cv.line({bx + kBarW, y}, {bx + kBarW + 4, y}, {kInk, 1.0});
        cv.text(bx + kBarW + 7, y + 4.5, s, 12.0);
    };
    if (o.log_scale) {
        for (int d = 0; d <= 4; ++d) {
            const std::string v = fmt::format("{:.2g}", peak * std::pow(10.0, -d));
            if (o.signed_values) {
                bar_label(0.5 + 0.5 * (4 - d) / 4.0, "+" + v);
                bar_label(0.5 - 0.5 * (4 - d) / 4.0, "−" + v);
            } else {
                bar_label((4 - d) / 4.0, v);
            }
        }
    } else {
        bar_label(1.0, fmt::format("{:.3g}", peak));
        bar_label(o.signed_values ? 0.5 : 0.0, "0");
        if (o.signed_values) bar_label(0.0, fmt::format("{:.3g}", -peak));
    }
    cv.text(bx + kBarW / 2, map_y - 8, "lm / cell", 12.0, Align::Centre);
}

void write_farfield_png(const std::string& path, const FarField& f, const FarFieldPicture& o) {
    const auto [r0, r1] = shown_rows(f, o);
    const double map_w = std::clamp<double>(f.width, 720.0, 1800.0);
    const double map_h = std::clamp<double>(double(r1 - r0) * map_w / f.width, 180.0, 900.0);
    const int w = int(map_w + kMarginLeft + kBarGap + kBarW + kBarLabels);
    const int h = int(map_h + kMarginTop + kMarginBottom);
    Canvas cv(w, h);
    draw_farfield(cv, {0, 0, double(w), double(h)}, f, o);
    cv.write_png(path);
}

} // namespace fird::plot
