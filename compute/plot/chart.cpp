#include "chart.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

namespace fird::plot {

namespace {

constexpr double kFontPx = 13.0;

struct Range {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -std::numeric_limits<double>::infinity();
    void add(double v, Scale s) {
        if (!std::isfinite(v) || (s == Scale::Log && !(v > 0.0))) return;
        lo = std::min(lo, v);
        hi = std::max(hi, v);
    }
};

// Data range of an axis, padded, with the axis's fixed limits applied.
std::pair<double, double> limits(const Axis& axis, Range r) {
    if (!(r.lo <= r.hi)) r = {axis.scale == Scale::Log ? 0.1 : 0.0, 1.0};
    double lo = r.lo, hi = r.hi;
    if (axis.scale == Scale::Log) {
        lo = std::pow(10.0, std::floor(std::log10(lo)));
        hi = std::pow(10.0, std::ceil(std::log10(hi)));
        if (hi <= lo) hi = lo * 10.0;
    } else {
        if (hi - lo <= 1e-12 * std::max(1.0, std::abs(hi))) {
            const double pad = std::max(std::abs(hi) * 0.05, 1e-9);
            lo -= pad, hi += pad;
        } else {
            const double pad = 0.04 * (hi - lo);
            lo -= pad, hi += pad;
        }
    }
    return {axis.min.value_or(lo), axis.max.value_or(hi)};
}

struct Mapping {
    Scale scale;
    double lo, hi; // data
    double p0, p1; // pixels
    double operator()(double v) const {
        const double t = scale == Scale::Log
                             ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                             : (v - lo) / (hi - lo);
        return p0 + t * (p1 - p0);
    }
    bool inside(double v) const {
        return std::isfinite(v) && (scale == Scale::Linear || v > 0.0) &&
               v >= std::min(lo, hi) - 1e-12 * std::abs(hi - lo) &&
               v <= std::max(lo, hi) + 1e-12 * std::abs(hi - lo);
    }
};

// Tick values and their labels for one axis.
std::vector<std::pair<double, std::string>> ticks(const Mapping& m) {
    std::vector<std::pair<double, std::string>> out;
    if (m.scale == Scale::Log) {
        const int d0 = int(std::ceil(std::log10(m.lo) - 1e-9)),
                  d1 = int(std::floor(std::log10(m.hi) + 1e-9));
        const int stride = std::max(1, (d1 - d0 + 1) / 8);
        for (int d = d0; d <= d1; d += stride) {
            const double v = std::pow(10.0, d);
            out.emplace_back(v,
                             d >= -3 && d <= 4 ? fmt::format("{:g}", v) : fmt::format("1e{}", d));
        }
        return out;
    }
    const auto values = linear_ticks(m.lo, m.hi);
    const double spacing = values.size() > 1 ? values[1] - values[0] : 1.0;
    for (double v : values)
        out.emplace_back(v, tick_label(v, spacing));
    return out;
}

} // namespace

std::vector<double> linear_ticks(double lo, double hi, int target) {
    if (!(hi > lo)) return {lo};
    const double raw = (hi - lo) / std::max(1, target);
    const double mag = std::pow(10.0, std::floor(std::log10(raw)));
    double step = mag;
    for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
        if (m * mag >= raw) {
            step = m * mag;
            break;
        }
    std::vector<double> out;
    for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
        out.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
    return out;
}

std::string tick_label(double v, double spacing) {
    const int decimals = std::clamp(int(-std::floor(std::log10(spacing) + 1e-9)), 0, 8);
    if (std::abs(v) >= 1e5 || (std::abs(v) > 0 && std::abs(v) < 1e-4))
        return fmt::format("{:.3g}", v);
    return fmt::format("{:.{}f}", v, decimals);
}

Colour palette(std::size_t i) {
    static constexpr Colour kColours[] = {
        {0.12, 0.40, 0.75}, {0.85, 0.33, 0.10}, {0.20, 0.60, 0.25}, {0.55, 0.25, 0.65},
        {0.80, 0.60, 0.05}, {0.10, 0.60, 0.65}, {0.75, 0.20, 0.45}, {0.40, 0.40, 0.40}};
    return kColours[i % (sizeof(kColours) / sizeof(kColours[0]))];
}

void draw_chart(Canvas& cv, const Rect& a, const Chart& c) {
    Range rx, ry;
    for (const Series& s : c.series) {
        for (double v : s.x)
            rx.add(v, c.x.scale);
        for (double v : s.y)
            ry.add(v, c.y.scale);
        for (double v : s.y_upper)
            ry.add(v, c.y.scale);
    }
    for (const Mark& m : c.marks)
        (m.vertical ? rx : ry).add(m.value, m.vertical ? c.x.scale : c.y.scale);
    const auto [x0, x1] = limits(c.x, rx);
    const auto [y0, y1] = limits(c.y, ry);
    // The plot box inside the area: room for tick labels, axis labels and the title.
    const double left = a.x + 74, right = a.x + a.w - 16;
    const double top = a.y + (c.title.empty() ? 14 : 36), bottom = a.y + a.h - 50;
    const Mapping mx{c.x.scale, x0, x1, left, right};
    const Mapping my{c.y.scale, y0, y1, bottom, top};

    for (const auto& [v, label] : ticks(mx)) {
        if (!mx.inside(v)) continue;
        const double px = mx(v);
        cv.line({px, top}, {px, bottom}, {kGrid, 1.0});
        cv.line({px, bottom}, {px, bottom + 5}, {kInk, 1.0});
        cv.text(px, bottom + 19, label, kFontPx, Align::Centre);
    }
    for (const auto& [v, label] : ticks(my)) {
        if (!my.inside(v)) continue;
        const double py = my(v);
        cv.line({left, py}, {right, py}, {kGrid, 1.0});
        cv.line({left - 5, py}, {left, py}, {kInk, 1.0});
        cv.text(left - 8, py + 4.5, label, kFontPx, Align::Right);
    }
    cv.stroke_rect(left, top, right - left, bottom - top, {kInk, 1.0});
    if (!c.title.empty())
        cv.text(a.x + a.w / 2, a.y + 22, c.title, 15.0, Align::Centre, kInk, 0, true);
    cv.text((left + right) / 2, a.y + a.h - 12, c.x.label, kFontPx, Align::Centre);
    cv.text(a.x + 16, (top + bottom) / 2, c.y.label, kFontPx, Align::Centre, kInk, 90.0);

    cv.clip(left, top, right - left, bottom - top);
    const auto point = [&](double x, double y) { return Point{mx(x), my(y)}; };
    for (const Series& s : c.series) {
        const std::size_t n = std::min(s.x.size(), s.y.size());
        if (s.kind == Series::Kind::Band) {
            std::vector<Point> poly;
            for (std::size_t i = 0; i < n; ++i)
                if (mx.inside(s.x[i]) && std::isfinite(my(s.y[i])))
                    poly.push_back(point(s.x[i], s.y[i]));
            for (std::size_t i = std::min(n, s.y_upper.size()); i-- > 0;)
                if (mx.inside(s.x[i]) && std::isfinite(my(s.y_upper[i])))
                    poly.push_back(point(s.x[i], s.y_upper[i]));
            Colour fill = s.colour;
            fill.a = 0.22;
            if (poly.size() >= 3) cv.fill_polygon(poly, fill);
        } else if (s.kind == Series::Kind::Points) {
            for (std::size_t i = 0; i < n; ++i)
                if (mx.inside(s.x[i]) && std::isfinite(my(s.y[i])) &&
                    (c.y.scale == Scale::Linear || s.y[i] > 0))
                    cv.fill_circle(point(s.x[i], s.y[i]),
                                   i < s.radius_px.size() ? s.radius_px[i] : 3.5, s.colour);
        } else {
            // Breaks at values the axis cannot show (NaN, or <= 0 on a log axis).
            std::vector<Point> run;
            const auto flush = [&] {
                if (run.size() >= 2) cv.polyline(run, {s.colour, s.width, s.dashed});
                run.clear();
            };
            for (std::size_t i = 0; i < n; ++i) {
                const bool ok = std::isfinite(s.x[i]) && std::isfinite(s.y[i]) &&
                                (c.x.scale == Scale::Linear || s.x[i] > 0) &&
                                (c.y.scale == Scale::Linear || s.y[i] > 0);
                if (ok)
                    run.push_back(point(s.x[i], s.y[i]));
                else
                    flush();
            }
            flush();
        }
    }
    for (const Mark& m : c.marks) {
        const Stroke st{m.colour, 1.3, true};
        if (m.vertical && mx.inside(m.value)) {
            cv.line({mx(m.value), top}, {mx(m.value), bottom}, st);
            cv.text(mx(m.value) + 4, top + 14, m.label, 12.0, Align::Left, m.colour);
        } else if (!m.vertical && my.inside(m.value)) {
            cv.line({left, my(m.value)}, {right, my(m.value)}, st);
            cv.text(right - 4, my(m.value) - 5, m.label, 12.0, Align::Right, m.colour);
        }
    }
    cv.unclip();

    if (!c.legend) return;
    std::vector<const Series*> entries;
    double widest = 0.0;
    for (const Series& s : c.series)
        if (!s.label.empty()) {
            entries.push_back(&s);
            widest = std::max(widest, cv.text_width(s.label, 12.0));
        }
    if (entries.empty()) return;
    const double lw = widest + 44, lh = 18.0 * double(entries.size()) + 8;
    const double lx = right - lw - 8, ly = top + 8;
    cv.fill_rect(lx, ly, lw, lh, {1, 1, 1, 0.88});
    cv.stroke_rect(lx, ly, lw, lh, {kGrid, 1.0});
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const Series& s = *entries[i];
        const double y = ly + 16 + 18.0 * double(i);
        if (s.kind == Series::Kind::Points)
            cv.fill_circle({lx + 18, y - 4}, 4.0, s.colour);
        else if (s.kind == Series::Kind::Band)
            cv.fill_rect(lx + 8, y - 9, 20, 10, {s.colour.r, s.colour.g, s.colour.b, 0.3});
        else
            cv.line({lx + 8, y - 4}, {lx + 28, y - 4}, {s.colour, s.width, s.dashed});
        cv.text(lx + 36, y, s.label, 12.0);
    }
}

void write_chart_png(const std::string& path, const Chart& chart, int w, int h) {
    Canvas cv(w, h);
    draw_chart(cv, {0, 0, double(w), double(h)}, chart);
    cv.write_png(path);
}

} // namespace fird::plot
