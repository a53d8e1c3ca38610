#include "farfield_picture.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "plot/colormap.hpp"

namespace fird::plot {

namespace {

// Room around the map: the title above, degree ticks and the azimuth label below and the
// altitude label left, the colour bar with its labels right. A small area (a workbench panel)
// gets the compact set: one line of title, tick labels only, a narrow bar.
struct Margins {
    double left, top, bottom, bar_gap, bar_w, bar_labels;
    bool axis_labels;
};
constexpr Margins kFull{70, 40, 56, 26, 22, 92, true};
constexpr Margins kCompact{44, 20, 22, 8, 12, 58, false};
constexpr double kFontPx = 12.0;

Margins margins(const Rect& a) {
    return a.h < 300.0 || a.w < 560.0 ? kCompact : kFull;
}

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

// Columns [c0, c1) of the far field shown for the options' azimuth window.
std::pair<std::uint32_t, std::uint32_t> shown_columns(const FarField& f, const FarFieldPicture& o) {
    if (!o.azimuth_deg) return {0, f.width};
    const auto column = [&](double az_deg) {
        return std::clamp((az_deg + 180.0) / 360.0 * f.width, 0.0, double(f.width));
    };
    const auto c0 = std::uint32_t(std::floor(column(o.azimuth_deg->first)));
    const auto c1 = std::uint32_t(std::ceil(column(o.azimuth_deg->second)));
    return {std::min(c0, f.width - 1), std::max(c0 + 1, std::min(c1, f.width))};
}

// [first, last) of the profile without `fraction` of its total, half from each end.
std::pair<std::size_t, std::size_t> lit_range(const std::vector<double>& p, double fraction) {
    const double total = std::accumulate(p.begin(), p.end(), 0.0);
    std::size_t first = 0, last = p.size();
    for (double s = 0.0; first < p.size() && s + p[first] <= 0.5 * fraction * total; ++first)
        s += p[first];
    for (double s = 0.0; last > first + 1 && s + p[last - 1] <= 0.5 * fraction * total; --last)
        s += p[last - 1];
    return {first, last};
}

// The start of the `span` consecutive entries in [first, last] holding the most light.
std::size_t brightest_start(const std::vector<double>& p, std::size_t first, std::size_t last,
                            std::size_t span) {
    std::size_t best_start = first;
    double best = -1.0;
    for (std::size_t start = first; start + span - 1 <= last && start + span <= p.size(); ++start) {
        double sum = 0.0;
        for (std::size_t k = start; k < start + span; ++k)
            sum += p[k];
        if (sum > best) best = sum, best_start = start;
    }
    return best_start;
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

namespace {

// One axis of the far field in degrees: entry i (a row or a column) spans
// [first_deg + i * step_deg, first_deg + (i + 1) * step_deg); rows step down from +90,
// columns up from -180.
struct DegreeAxis {
    const std::vector<double>& profile; // the light per entry
    double first_deg, step_deg;         // step_deg < 0 for rows
    double low_deg, high_deg;           // the axis's ends
    double min_margin_deg;              // the least margin a lit band gets
    std::size_t entries;
    std::size_t index(double deg) const {
        return std::size_t(
            std::clamp(int(std::floor((deg - first_deg) / step_deg)), 0, int(entries) - 1));
    }
    double edge(double i) const { return first_deg + i * step_deg; }
};

DegreeAxis altitude_axis(const FarFieldProfiles& p) {
    const auto rows = p.per_row.size();
    return {p.per_row, 90.0, -180.0 / double(std::max<std::size_t>(rows, 1)), -90.0, 90.0,
            2.0,       rows};
}
DegreeAxis azimuth_axis(const FarFieldProfiles& p) {
    const auto columns = p.per_column.size();
    return {p.per_column, -180.0, 360.0 / double(std::max<std::size_t>(columns, 1)), -180.0, 180.0,
            4.0,          columns};
}

// The band as (start, end) in the axis's order: (high, low) for rows, (left, right) for
// columns.
std::pair<double, double> lit_band(const DegreeAxis& axis, double fraction) {
    const std::vector<double>& profile = axis.profile;
    const double start = axis.step_deg > 0 ? axis.low_deg : axis.high_deg;
    const double end = axis.step_deg > 0 ? axis.high_deg : axis.low_deg;
    if (!(std::accumulate(profile.begin(), profile.end(), 0.0) > 0.0)) return {start, end};
    const auto [i0, i1] = lit_range(profile, fraction);
    const double a = axis.edge(double(i0)), b = axis.edge(double(i1));
    const double margin = std::max(axis.min_margin_deg, 0.1 * std::abs(b - a));
    const double sign = axis.step_deg > 0 ? 1.0 : -1.0;
    return {std::clamp(a - sign * margin, axis.low_deg, axis.high_deg),
            std::clamp(b + sign * margin, axis.low_deg, axis.high_deg)};
}

// The window of `size_deg` inside `band` (in the axis's order) holding the most light, as
// many whole entries as its size covers, centred on those entries and kept in the band.
std::pair<double, double> brightest_window(const DegreeAxis& axis, std::pair<double, double> band,
                                           double size_deg) {
    const auto [a, b] = band;
    if (!(size_deg < std::abs(b - a)) || axis.entries == 0) return band;
    const double step = std::abs(axis.step_deg);
    const std::size_t span = std::size_t(std::max(1, int(std::round(size_deg / step))));
    const std::size_t start = brightest_start(axis.profile, axis.index(a), axis.index(b), span);
    const double centre = axis.edge(double(start) + 0.5 * double(span));
    const double half = 0.5 * size_deg;
    const double c = std::clamp(centre, std::min(a, b) + half, std::max(a, b) - half);
    return axis.step_deg > 0 ? std::pair{c - half, c + half} : std::pair{c + half, c - half};
}

} // namespace

FarFieldProfiles light_profiles(const FarField& f) {
    FarFieldProfiles p{std::vector<double>(f.height, 0.0), std::vector<double>(f.width, 0.0)};
    for (std::uint32_t r = 0; r < f.height; ++r)
        for (std::uint32_t c = 0; c < f.width; ++c) {
            const double lm = std::abs(f.lm[std::size_t(r) * f.width + c]);
            p.per_row[r] += lm;
            p.per_column[c] += lm;
        }
    return p;
}

std::pair<double, double> lit_altitude_band(const FarFieldProfiles& p, double fraction) {
    return lit_band(altitude_axis(p), fraction);
}

std::pair<double, double> brightest_altitude_window(const FarFieldProfiles& p,
                                                    std::pair<double, double> band,
                                                    double height_deg) {
    return brightest_window(altitude_axis(p), band, height_deg);
}

std::pair<double, double> lit_azimuth_band(const FarFieldProfiles& p, double fraction) {
    return lit_band(azimuth_axis(p), fraction);
}

std::pair<double, double> brightest_azimuth_window(const FarFieldProfiles& p,
                                                   std::pair<double, double> band,
                                                   double width_deg) {
    return brightest_window(azimuth_axis(p), band, width_deg);
}

FarFieldMapPlacement farfield_map_placement(const Rect& a, const FarField& f,
                                            const FarFieldPicture& o) {
    const auto [r0, r1] = shown_rows(f, o);
    const auto [c0, c1] = shown_columns(f, o);
    const Margins m = margins(a);
    return {{a.x + m.left, a.y + m.top,
             std::max(1.0, a.w - m.left - m.bar_gap - m.bar_w - m.bar_labels),
             std::max(1.0, a.h - m.top - m.bottom)},
            r0,
            r1,
            c0,
            c1};
}

void draw_farfield(Canvas& cv, const Rect& a, const FarField& f, const FarFieldPicture& o) {
    const FarFieldMapPlacement placed = farfield_map_placement(a, f, o);
    const std::uint32_t r0 = placed.row0, r1 = placed.row1;
    const std::uint32_t c0 = placed.column0, c1 = placed.column1, columns = c1 - c0;
    const double map_x = placed.map.x, map_y = placed.map.y;
    const double map_w = placed.map.w, map_h = placed.map.h;
    // One image pixel per screen pixel (at most one per cell): each shows the largest
    // |value| of the cells it covers.
    const int iw = int(std::clamp<double>(std::min<double>(columns, map_w), 1.0, 4096.0));
    const int ih = int(std::clamp<double>(std::min<double>(r1 - r0, map_h), 1.0, 4096.0));
    double peak = 0.0;
    for (std::uint32_t r = r0; r < r1; ++r)
        for (std::uint32_t c = c0; c < c1; ++c)
            peak = std::max(peak, std::abs(f.lm[std::size_t(r) * f.width + c]));
    std::vector<std::uint8_t> rgb(std::size_t(iw) * ih * 3);
    const std::uint32_t rows = r1 - r0;
    for (int py = 0; py < ih; ++py) {
        const auto ra = r0 + std::uint32_t(std::uint64_t(py) * rows / ih);
        const auto rb = std::max(ra + 1, r0 + std::uint32_t(std::uint64_t(py + 1) * rows / ih));
        for (int px = 0; px < iw; ++px) {
            const auto ca = c0 + std::uint32_t(std::uint64_t(px) * columns / iw);
            const auto cb =
                std::max(ca + 1, c0 + std::uint32_t(std::uint64_t(px + 1) * columns / iw));
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

    // Degree axes: azimuth at 45 deg steps and altitude at round steps of the band shown,
    // as many as fit without their labels touching (compute/plot's axis_ticks).
    const Margins mg = margins(a);
    const auto width = [&](const std::string& t) { return cv.text_width(t, kFontPx); };
    const auto height = [&](const std::string&) { return kFontPx; };
    const double az_left = -180.0 + c0 * 360.0 / f.width, az_right = -180.0 + c1 * 360.0 / f.width;
    const AxisMapping azimuth{Scale::Linear, az_left, az_right, map_x, map_x + map_w};
    if (c1 - c0 < f.width) { // a window: round steps of it (compute/plot's axis_ticks)
        for (const Tick& t : axis_ticks(azimuth, width, kFontPx)) {
            const double x = azimuth(t.value);
            cv.line({x, map_y + map_h}, {x, map_y + map_h + 4}, {kInk, 1.0});
            cv.text(x, map_y + map_h + 16, t.label + "°", kFontPx, Align::Centre);
        }
    }
    for (int step = 45; c1 - c0 == f.width && step <= 360; step *= 2) {
        std::vector<Tick> ticks;
        for (int deg = -180; deg <= 180; deg += step)
            ticks.push_back({double(deg), fmt::format("{}°", deg)});
        bool fits = true;
        for (std::size_t i = 1; i < ticks.size(); ++i)
            fits = fits && azimuth(ticks[i].value) - azimuth(ticks[i - 1].value) >=
                               width(ticks[i].label) + kFontPx;
        if (!fits && step < 360) continue;
        for (const Tick& t : ticks) {
            const double x = azimuth(t.value);
            cv.line({x, map_y + map_h}, {x, map_y + map_h + 4}, {kInk, 1.0});
            cv.text(x, map_y + map_h + 16, t.label, kFontPx, Align::Centre);
        }
        break;
    }
    const double alt_hi = 90.0 - r0 * 180.0 / f.height, alt_lo = 90.0 - r1 * 180.0 / f.height;
    const AxisMapping altitude{Scale::Linear, alt_lo, alt_hi, map_y + map_h, map_y};
    for (const Tick& t : axis_ticks(altitude, height, 0.5 * kFontPx)) {
        const double y = altitude(t.value);
        cv.line({map_x - 4, y}, {map_x, y}, {kInk, 1.0});
        cv.text(map_x - 7, y + 4.5, t.label + "°", kFontPx, Align::Right);
    }
    if (mg.axis_labels) {
        cv.text(map_x + map_w / 2, a.y + a.h - 12, "azimuth φ", 13.0, Align::Centre);
        cv.text(a.x + 16, map_y + map_h / 2, "altitude θ", 13.0, Align::Centre, kInk, 90.0);
    }
    // The title, with the grid and total where the width allows.
    const std::string full = fmt::format("{}   ({} × {} cells, total {:.4g} lm)", o.title, f.width,
                                         f.height, f.total_lm());
    const double size = mg.axis_labels ? std::clamp(a.w / 60.0, 11.0, 15.0) : kFontPx;
    cv.text(a.x + a.w / 2, a.y + (mg.axis_labels ? 24 : 14),
            cv.text_width(full, size, true) < a.w - 20 ? full : o.title, size, Align::Centre, kInk,
            0.0, true);

    // Colour bar with its scale (the unit under it, clear of the title).
    const double bx = map_x + map_w + mg.bar_gap, bar_w = mg.bar_w;
    std::vector<std::uint8_t> bar(256 * 3);
    for (int k = 0; k < 256; ++k) {
        const double t = 1.0 - k / 255.0;
        const Rgb col = colour(o.signed_values ? 2.0 * t - 1.0 : t, o.signed_values);
        std::copy(col.begin(), col.end(), bar.begin() + k * 3);
    }
    cv.image(bar, 1, 256, bx, map_y, bar_w, map_h);
    cv.stroke_rect(bx, map_y, bar_w, map_h, {kInk, 1.0});
    const auto bar_label = [&](double t, const std::string& s) {
        const double y = map_y + (1.0 - t) * map_h;
        cv.line({bx + bar_w, y}, {bx + bar_w + 4, y}, {kInk, 1.0});
        cv.text(bx + bar_w + 6, y + 4.5, s, kFontPx);
    };
    if (o.log_scale) {
        // Decades below the peak, as many as the bar's height has room for (a signed bar
        // labels each twice).
        const double labels_per_decade = o.signed_values ? 2.0 : 1.0;
        int stride = 1;
        while (stride < 4 && (4.0 / stride + 1.0) * labels_per_decade * (kFontPx + 3.0) > map_h)
            stride *= 2;
        for (int d = 0; d <= 4; d += stride) {
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
        if (map_h >= 3.0 * (kFontPx + 3.0) || !o.signed_values)
            bar_label(o.signed_values ? 0.5 : 0.0, "0");
        if (o.signed_values) bar_label(0.0, fmt::format("{:.3g}", -peak));
    }
    cv.text(std::max(bx + bar_w / 2, map_x + map_w + 0.5 * width("180°") + 6), map_y + map_h + 16,
            "lm/cell", kFontPx, Align::Left);
}

void write_farfield_png(const std::string& path, const FarField& f, const FarFieldPicture& o) {
    const auto [r0, r1] = shown_rows(f, o);
    const double map_w = std::clamp<double>(f.width, 720.0, 1800.0);
    const double map_h = std::clamp<double>(double(r1 - r0) * map_w / f.width, 180.0, 900.0);
    const int w = int(map_w + kFull.left + kFull.bar_gap + kFull.bar_w + kFull.bar_labels);
    const int h = int(map_h + kFull.top + kFull.bottom);
    Canvas cv(w, h);
    draw_farfield(cv, {0, 0, double(w), double(h)}, f, o);
    cv.write_png(path);
}

} // namespace fird::plot
