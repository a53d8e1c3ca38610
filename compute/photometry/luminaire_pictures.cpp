#include "luminaire_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_views.hpp"
#include "plot/canvas.hpp"
#include "plot/colormap.hpp"

namespace fird {

namespace {

using plot::Align;
using plot::Canvas;
using plot::kInk;
using plot::Rect;

constexpr double kFontPx = 12.0;
constexpr double kDeg = std::numbers::pi / 180.0;

// A panel's parts: the title line above, the picture, the colour bar to its right.
struct Panel {
    Rect picture, bar;
};
Panel panel_layout(const Rect& a) {
    // Room for the title and the polar map's C labels (14 px beyond its rim) above and
    // beside it, the colour bar and its labels (+1.23e+03) to the right.
    const double top = 48.0, bottom = 44.0, left = 48.0, bar_gap = 30.0, bar_room = 110.0;
    const double side = std::max(40.0, std::min(a.w - left - bar_room, a.h - top - bottom));
    // Centred across the panel where it is wider than the picture needs.
    const double x = a.x + std::max(left, 0.5 * (a.w - side - bar_room + left));
    const Rect picture{x, a.y + top, side, side};
    return {picture, {picture.x + side + bar_gap, picture.y, 12.0, side}};
}

plot::Rgb colour_of(double v, double peak, bool signed_values) {
    if (!(peak > 0.0))
        return signed_values ? plot::diverging_colour(0.0) : plot::sequential_colour(0.0);
    return signed_values ? plot::diverging_colour(std::clamp(v / peak, -1.0, 1.0))
                         : plot::sequential_colour(std::clamp(v / peak, 0.0, 1.0));
}

void colour_bar(Canvas& cv, const Rect& bar, double peak, bool signed_values,
                const std::string& unit) {
    std::vector<std::uint8_t> rgb(256 * 3);
    for (int k = 0; k < 256; ++k) {
        const double t = 1.0 - k / 255.0;
        const plot::Rgb c =
            signed_values ? plot::diverging_colour(2.0 * t - 1.0) : plot::sequential_colour(t);
        std::copy(c.begin(), c.end(), rgb.begin() + k * 3);
    }
    cv.image(rgb, 1, 256, bar.x, bar.y, bar.w, bar.h);
    cv.stroke_rect(bar.x, bar.y, bar.w, bar.h, {kInk, 1.0});
    const auto label = [&](double t, const std::string& s) {
        const double y = bar.y + (1.0 - t) * bar.h;
        cv.line({bar.x + bar.w, y}, {bar.x + bar.w + 4, y}, {kInk, 1.0});
        cv.text(bar.x + bar.w + 6, y + 4.5, s, kFontPx);
    };
    label(1.0, fmt::format("{}{:.4g}", signed_values ? "+" : "", peak));
    label(signed_values ? 0.5 : 0.0, "0");
    if (signed_values) label(0.0, fmt::format("−{:.4g}", peak));
    cv.text(bar.x, bar.y + bar.h + 18, unit, kFontPx);
}

// An RGB image of n x n samples of value(u, v), u and v in [-1, 1] (v up), NaN outside.
template <class Value>
void draw_square_image(Canvas& cv, const Rect& r, int n, double peak, bool signed_values,
                       const Value& value) {
    std::vector<std::uint8_t> rgb(std::size_t(n) * n * 3, 255);
    for (int py = 0; py < n; ++py)
        for (int px = 0; px < n; ++px) {
            const double u = -1.0 + 2.0 * (px + 0.5) / n, v = 1.0 - 2.0 * (py + 0.5) / n;
            const double x = value(u, v);
            if (std::isnan(x)) continue;
            const plot::Rgb c = colour_of(x, peak, signed_values);
            std::copy(c.begin(), c.end(), rgb.begin() + (std::size_t(py) * n + px) * 3);
        }
    cv.image(rgb, n, n, r.x, r.y, r.w, r.h);
}

// The intensity (or a difference of two) in the direction (C, gamma).
struct Intensity {
    const CandelaTable* a;
    const CandelaTable* minus = nullptr;
    double operator()(double c_deg, double gamma_deg) const {
        const double v = intensity_cd(*a, c_deg, gamma_deg);
        return minus ? v - intensity_cd(*minus, c_deg, gamma_deg) : v;
    }
};

double largest_abs_difference(const CandelaTable& a, const CandelaTable& b) {
    double m = 0.0;
    for (int c = 0; c < 360; c += 2)
        for (double g = 0.0; g <= 180.0; g += 0.5)
            m = std::max(m, std::abs(intensity_cd(a, c, g) - intensity_cd(b, c, g)));
    return m;
}

// The polar map: gamma outwards from nadir at the centre, C counter-clockwise from C0 on the
// right (C90 up), oriented as the illuminance plane below it.
void polar_panel(Canvas& cv, const Rect& a, const Intensity& f, double peak, bool signed_values,
                 double gamma_max, const std::string& title) {
    const Panel p = panel_layout(a);
    const Rect& r = p.picture;
    cv.text(a.x + a.w / 2, a.y + 20, title, 13.0, Align::Centre, kInk, 0.0, true);
    const int n = int(std::clamp(r.w, 64.0, 480.0));
    draw_square_image(cv, r, n, peak, signed_values, [&](double u, double v) {
        const double rho = std::hypot(u, v);
        if (rho > 1.0) return std::nan("");
        double c = std::atan2(v, u) / kDeg;
        if (c < 0.0) c += 360.0;
        return f(c, rho * gamma_max);
    });
    const plot::Point centre{r.x + r.w / 2, r.y + r.h / 2};
    const double radius = r.w / 2;
    const double ring_step = gamma_max > 90.0 ? 30.0 : gamma_max > 40.0 ? 15.0 : 10.0;
    for (double g = ring_step; g <= gamma_max + 1e-9; g += ring_step) {
        std::vector<plot::Point> ring;
        for (int k = 0; k <= 96; ++k)
            ring.push_back(
                {centre.x + radius * g / gamma_max * std::cos(2.0 * std::numbers::pi * k / 96),
                 centre.y - radius * g / gamma_max * std::sin(2.0 * std::numbers::pi * k / 96)});
        cv.polyline(ring, {{0.6, 0.6, 0.6, 0.8}, 0.8});
        cv.text(centre.x + radius * g / gamma_max * 0.7071 + 2,
                centre.y + radius * g / gamma_max * 0.7071 + 10, fmt::format("{:g}°", g), 10.0,
                Align::Left, {0.55, 0.55, 0.55});
    }
    for (int c = 0; c < 360; c += 90) {
        const double t = c * kDeg;
        cv.line(centre, {centre.x + radius * std::cos(t), centre.y - radius * std::sin(t)},
                {{0.6, 0.6, 0.6, 0.8}, 0.8});
        cv.text(centre.x + (radius + 14) * std::cos(t), centre.y - (radius + 14) * std::sin(t) + 4,
                fmt::format("C{}", c), kFontPx, Align::Centre);
    }
    colour_bar(cv, p.bar, peak, signed_values, "cd");
    cv.text(a.x + a.w / 2, r.y + r.h + 34, fmt::format("γ 0–{:g}° from nadir (centre)", gamma_max),
            kFontPx, Align::Centre);
}

// Isocandela lines in C-gamma: C across, gamma down from nadir; a second table's lines
// dashed (the overlay of obtained and desired).
// The isocandela panel's C-gamma frame: C 0-360 across, gamma 0-gamma_max down.
Rect isocandela_frame(const Rect& a) {
    return {a.x + 48, a.y + 34, std::max(40.0, a.w - 60), std::max(40.0, a.h - 34 - 62)};
}

void isocandela_panel(Canvas& cv, const Rect& a, const CandelaTable& t, const CandelaTable* dashed,
                      double peak, double gamma_max, const std::string& title) {
    const Rect r = isocandela_frame(a);
    cv.text(a.x + a.w / 2, a.y + 20, title, 13.0, Align::Centre, kInk, 0.0, true);
    cv.stroke_rect(r.x, r.y, r.w, r.h, {kInk, 1.0});
    const plot::AxisMapping cx{plot::Scale::Linear, 0.0, 360.0, r.x, r.x + r.w};
    const plot::AxisMapping gy{plot::Scale::Linear, 0.0, gamma_max, r.y, r.y + r.h};
    for (int c = 0; c <= 360; c += 90) {
        cv.line({cx(c), r.y + r.h}, {cx(c), r.y + r.h + 4}, {kInk, 1.0});
        cv.text(cx(c), r.y + r.h + 16, fmt::format("C{}", c), kFontPx, Align::Centre);
    }
    for (const double g : plot::linear_ticks(0.0, gamma_max, 5)) {
        cv.line({r.x - 4, gy(g)}, {r.x, gy(g)}, {kInk, 1.0});
        cv.text(r.x - 6, gy(g) + 4, fmt::format("{:g}°", g), kFontPx, Align::Right);
    }
    const std::vector<double> shares{0.1, 0.25, 0.5, 0.75, 0.9};
    std::vector<double> levels;
    for (double s : shares)
        levels.push_back(s * peak);
    cv.clip(r.x, r.y, r.w, r.h);
    const auto draw = [&](const CandelaTable& table, bool dash) {
        for (const IsoSegment& s : isocandela_segments(table, levels, gamma_max)) {
            const auto k =
                std::size_t(std::find(levels.begin(), levels.end(), s.level_cd) - levels.begin());
            cv.line({cx(s.c0_deg), gy(s.gamma0_deg)}, {cx(s.c1_deg), gy(s.gamma1_deg)},
                    {plot::palette(k), 1.4, dash});
        }
    };
    draw(t, false);
    if (dashed) draw(*dashed, true);
    cv.unclip();
    // The legend: each level's share of the peak.
    double x = r.x;
    for (std::size_t k = 0; k < shares.size(); ++k) {
        const std::string s = fmt::format("{:.0f} %", 100.0 * shares[k]);
        cv.line({x, r.y + r.h + 36}, {x + 16, r.y + r.h + 36}, {plot::palette(k), 2.0});
        cv.text(x + 20, r.y + r.h + 40, s, kFontPx);
        x += 28 + cv.text_width(s, kFontPx);
    }
    cv.text(x + 6, r.y + r.h + 40,
            fmt::format("of {:.4g} cd{}", peak, dashed ? "; dashed: desired" : ""), kFontPx);
}

// The illuminance on the plane: x along C0 to the right, y along C90 up, with a scale bar.
void illuminance_panel(Canvas& cv, const Rect& a, const IlluminanceMap& m,
                       const IlluminanceMap* minus, double peak, bool signed_values,
                       const std::string& title) {
    const Panel p = panel_layout(a);
    const Rect& r = p.picture;
    cv.text(a.x + a.w / 2, a.y + 20, title, 13.0, Align::Centre, kInk, 0.0, true);
    const int n = m.samples;
    std::vector<std::uint8_t> rgb(std::size_t(n) * n * 3);
    for (int iy = 0; iy < n; ++iy)
        for (int ix = 0; ix < n; ++ix) {
            const double v = m.at(ix, iy) - (minus ? minus->at(ix, iy) : 0.0);
            const plot::Rgb c = colour_of(v, peak, signed_values);
            // Row 0 of the map is y = -half: the picture's bottom row.
            std::copy(c.begin(), c.end(), rgb.begin() + (std::size_t(n - 1 - iy) * n + ix) * 3);
        }
    cv.image(rgb, n, n, r.x, r.y, r.w, r.h);
    cv.stroke_rect(r.x, r.y, r.w, r.h, {kInk, 1.0});
    const plot::AxisMapping ax{plot::Scale::Linear, -m.half_width_m, m.half_width_m, r.x,
                               r.x + r.w};
    for (const double x : plot::linear_ticks(-m.half_width_m, m.half_width_m, 5)) {
        cv.line({ax(x), r.y + r.h}, {ax(x), r.y + r.h + 4}, {kInk, 1.0});
        cv.text(ax(x), r.y + r.h + 16, fmt::format("{:g}", x), kFontPx, Align::Centre);
    }
    // The scale bar: the roundest length near a quarter of the width.
    const double quarter = 0.5 * m.half_width_m;
    const double unit = std::pow(10.0, std::floor(std::log10(quarter)));
    const double length = quarter >= 5 * unit ? 5 * unit : quarter >= 2 * unit ? 2 * unit : unit;
    const double bx = r.x + 10, by = r.y + r.h - 12, bw = length / (2.0 * m.half_width_m) * r.w;
    cv.fill_rect(bx - 4, by - 16, bw + 8, 22, {1, 1, 1, 0.8});
    cv.line({bx, by}, {bx + bw, by}, {kInk, 3.0});
    cv.text(bx + bw / 2, by - 5, fmt::format("{:g} m", length), kFontPx, Align::Centre);
    colour_bar(cv, p.bar, peak, signed_values, "lx");
    cv.text(a.x + a.w / 2, r.y + r.h + 34,
            fmt::format("plane {:g} m below, x along C0 (m), C90 up", m.distance_m), kFontPx,
            Align::Centre);
}

} // namespace

double luminaire_view_gamma_deg(const CandelaTable& a, const CandelaTable* b) {
    double g = gamma_holding_deg(a, 0.995);
    if (b) g = std::max(g, gamma_holding_deg(*b, 0.995));
    return std::clamp(10.0 * std::ceil(g / 10.0), 30.0, 180.0);
}

const char* luminaire_view_name(LuminaireView view) {
    switch (view) {
    case LuminaireView::PolarMap:
        return "polar";
    case LuminaireView::Isocandela:
        return "isocandela";
    case LuminaireView::Illuminance:
        return "illuminance";
    }
    return "polar";
}

namespace {
// A table step of m cells, at least `least_deg`, with m even and dividing the cells: a
// step of an odd number of cells puts some cell's centre halfway between two nodes, where
// table_from_farfield's nearest node is the outer one (with one cell a step, nadir would
// read 0 cd and all the light half a cell out). One cell where no even m divides.
double view_step_deg(std::uint32_t cells, double range_deg, double least_deg) {
    const double cell = range_deg / cells;
    for (std::uint32_t m = 2; m <= cells; m += 2)
        if (cells % m == 0 && m * cell >= least_deg - 1e-9) return m * cell;
    return cell;
}
} // namespace

CandelaTable view_table(const FarField& f) {
    // About photometrics' patches: C every 5 deg, gamma every 1 deg, or coarser.
    return table_from_farfield(f, view_step_deg(f.width, 360.0, 5.0),
                               view_step_deg(f.height, 180.0, 1.0));
}

namespace {

// Where a view's panels go in `a`: obtained, desired, difference side by side, or stacked
// where that leaves each panel's picture larger (a tall workbench panel): the picture's
// side is the panel's less its margins.
struct ViewLayout {
    Rect a;
    int columns = 1;
    double w = 0.0, h = 0.0;
    Rect area(int k) const { return {a.x + (k % columns) * w, a.y + (k / columns) * h, w, h}; }
};
ViewLayout view_layout(const Rect& a, int panels) {
    const auto side = [&](int columns) {
        const int rows = (panels + columns - 1) / columns;
        return std::min(a.w / columns - 158.0, a.h / rows - 92.0);
    };
    const int columns = side(panels) >= side(1) ? panels : 1;
    const int rows = (panels + columns - 1) / columns;
    return {a, columns, a.w / columns, a.h / rows};
}

// The illuminance plane's half width: out to where the light ends, at most 75 deg from
// nadir (beyond, the plane is grazed and its width grows without bound).
double plane_half_width_m(double distance_m, double gamma_max_deg) {
    return distance_m * std::tan(std::min(gamma_max_deg, 75.0) * kDeg);
}

} // namespace

void draw_luminaire_view(Canvas& cv, const Rect& a, LuminaireView view,
                         const CandelaTable& obtained, const CandelaTable* desired,
                         const LuminaireViewOptions& o) {
    const ViewLayout layout = view_layout(a, desired ? 3 : 1);
    const auto area = [&](int k) { return layout.area(k); };
    const double gamma_max = luminaire_view_gamma_deg(obtained, desired);
    const double peak = std::max(obtained.peak_cd(), desired ? desired->peak_cd() : 0.0);
    const std::string name = o.title.empty() ? std::string() : o.title + ": ";
    switch (view) {
    case LuminaireView::PolarMap:
        polar_panel(cv, area(0), {&obtained}, peak, false, gamma_max, name + "intensity");
        if (desired) {
            polar_panel(cv, area(1), {desired}, peak, false, gamma_max, "desired");
            polar_panel(cv, area(2), {&obtained, desired},
                        largest_abs_difference(obtained, *desired), true, gamma_max,
                        "obtained − desired");
        }
        break;
    case LuminaireView::Isocandela:
        isocandela_panel(cv, area(0), obtained, nullptr, peak, gamma_max, name + "isocandela");
        if (desired) {
            isocandela_panel(cv, area(1), *desired, nullptr, peak, gamma_max, "desired");
            isocandela_panel(cv, area(2), obtained, desired, peak, gamma_max,
                             "obtained (solid), desired (dashed)");
        }
        break;
    case LuminaireView::Illuminance: {
        const double half = plane_half_width_m(o.plane_distance_m, gamma_max);
        constexpr int samples = 240;
        const IlluminanceMap e = illuminance_on_plane(obtained, o.plane_distance_m, half, samples);
        std::optional<IlluminanceMap> d;
        if (desired) d = illuminance_on_plane(*desired, o.plane_distance_m, half, samples);
        double top = *std::max_element(e.lux.begin(), e.lux.end());
        if (d) top = std::max(top, *std::max_element(d->lux.begin(), d->lux.end()));
        illuminance_panel(cv, area(0), e, nullptr, top, false, name + "illuminance");
        if (d) {
            illuminance_panel(cv, area(1), *d, nullptr, top, false, "desired");
            double diff = 0.0;
            for (std::size_t i = 0; i < e.lux.size(); ++i)
                diff = std::max(diff, std::abs(e.lux[i] - d->lux[i]));
            illuminance_panel(cv, area(2), e, &*d, diff, true, "obtained − desired");
        }
        break;
    }
    }
}

std::optional<LuminaireReadout> luminaire_view_readout(const Rect& a, LuminaireView view,
                                                       const CandelaTable& obtained,
                                                       const CandelaTable* desired,
                                                       const LuminaireViewOptions& o,
                                                       double gamma_max, double px, double py) {
    const int panels = desired ? 3 : 1;
    const ViewLayout layout = view_layout(a, panels);
    for (int k = 0; k < panels; ++k) {
        const Rect area = layout.area(k);
        // The picture (polar map, plane) or the C-gamma frame this panel draws.
        const Rect r =
            view == LuminaireView::Isocandela ? isocandela_frame(area) : panel_layout(area).picture;
        if (!(px >= r.x && px < r.x + r.w && py >= r.y && py < r.y + r.h)) continue;
        LuminaireReadout out{.panel = LuminairePanel(k)};
        const double u = (px - r.x) / r.w, v = (py - r.y) / r.h; // 0..1, v down
        if (view == LuminaireView::PolarMap) {
            // As polar_panel draws it: nadir at the centre, C counter-clockwise from the right.
            const double x = 2.0 * u - 1.0, y = 1.0 - 2.0 * v, rho = std::hypot(x, y);
            if (rho > 1.0) return std::nullopt;
            out.c_deg = std::atan2(y, x) / kDeg;
            if (out.c_deg < 0.0) out.c_deg += 360.0;
            out.gamma_deg = rho * gamma_max;
        } else if (view == LuminaireView::Isocandela) {
            out.c_deg = u * 360.0;
            out.gamma_deg = v * gamma_max;
        } else {
            const double half = plane_half_width_m(o.plane_distance_m, gamma_max);
            out.on_plane = true;
            out.x_m = -half + 2.0 * half * u;
            out.y_m = half - 2.0 * half * v;
            const PlanePoint e = illuminance_at(obtained, o.plane_distance_m, out.x_m, out.y_m);
            out.c_deg = e.c_deg;
            out.gamma_deg = e.gamma_deg;
            out.obtained = e.lux;
            if (desired)
                out.desired = illuminance_at(*desired, o.plane_distance_m, out.x_m, out.y_m).lux;
            return out;
        }
        out.obtained = intensity_cd(obtained, out.c_deg, out.gamma_deg);
        if (desired) out.desired = intensity_cd(*desired, out.c_deg, out.gamma_deg);
        return out;
    }
    return std::nullopt;
}

void write_luminaire_views(const std::string& dir, const FarField& obtained,
                           const FarField* desired, const LuminaireViewOptions& o) {
    const CandelaTable a = view_table(obtained);
    std::optional<CandelaTable> b;
    if (desired) b = view_table(*desired);
    const int panels = desired ? 3 : 1;
    for (const LuminaireView view :
         {LuminaireView::PolarMap, LuminaireView::Isocandela, LuminaireView::Illuminance}) {
        const int w = 520 * panels, h = view == LuminaireView::Isocandela ? 420 : 480;
        Canvas cv(w, h);
        draw_luminaire_view(cv, {0, 0, double(w), double(h)}, view, a, b ? &*b : nullptr, o);
        cv.write_png(
            (std::filesystem::path(dir) / (std::string(luminaire_view_name(view)) + ".png"))
                .string());
    }
}

} // namespace fird
