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

// The range of a value or of a log axis's decades, padded.
std::pair<double, double> padded(Scale scale, Range r) {
    if (!(r.lo <= r.hi)) r = {scale == Scale::Log ? 0.1 : 0.0, 1.0};
    double lo = r.lo, hi = r.hi;
    if (scale == Scale::Log) {
        lo = std::pow(10.0, std::floor(std::log10(lo)));
        hi = std::pow(10.0, std::ceil(std::log10(hi)));
        if (hi <= lo) hi = lo * 10.0;
    } else if (hi - lo <= 1e-12 * std::max(1.0, std::abs(hi))) {
        // One value (a single point, or a parameter that has not moved yet): a range
        // about it that reads as one, ±1 about 0.
        const double pad = hi != 0.0 ? 0.05 * std::abs(hi) : 1.0;
        lo -= pad, hi += pad;
    } else {
        const double pad = 0.04 * (hi - lo);
        lo -= pad, hi += pad;
    }
    return {lo, hi};
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

std::pair<double, double> axis_limits(const Chart& c, bool y_axis) {
    const Axis& axis = y_axis ? c.y : c.x;
    Range r;
    for (const Series& s : c.series) {
        for (double v : y_axis ? s.y : s.x)
            r.add(v, axis.scale);
        if (y_axis)
            for (double v : s.y_upper)
                r.add(v, axis.scale);
    }
    for (const Mark& m : c.marks)
        if (m.vertical != y_axis) r.add(m.value, axis.scale);
    auto [lo, hi] = padded(axis.scale, r);
    lo = axis.min.value_or(lo), hi = axis.max.value_or(hi);
    if (!(hi > lo)) {
        // One fixed limit on the wrong side of the data: a range on the fixed side.
        const double span = axis.scale == Scale::Log ? 0.0 : std::max(1.0, 0.1 * std::abs(lo));
        if (axis.max)
            lo = axis.scale == Scale::Log ? hi / 10.0 : hi - span;
        else
            hi = axis.scale == Scale::Log ? lo * 10.0 : lo + span;
    }
    return {lo, hi};
}

double AxisMapping::operator()(double v) const {
    const double t = scale == Scale::Log
                         ? (std::log10(v) - std::log10(lo)) / (std::log10(hi) - std::log10(lo))
                         : (v - lo) / (hi - lo);
    return p0 + t * (p1 - p0);
}

double AxisMapping::value_at(double p) const {
    const double t = (p - p0) / (p1 - p0);
    return scale == Scale::Log
               ? std::pow(10.0, std::log10(lo) + t * (std::log10(hi) - std::log10(lo)))
               : lo + t * (hi - lo);
}

bool AxisMapping::inside(double v) const {
    return std::isfinite(v) && (scale == Scale::Linear || v > 0.0) &&
           v >= std::min(lo, hi) - 1e-12 * std::abs(hi - lo) &&
           v <= std::max(lo, hi) + 1e-12 * std::abs(hi - lo);
}

std::vector<Tick> axis_ticks(const AxisMapping& m,
                             const std::function<double(const std::string&)>& extent_px,
                             double gap_px, int most) {
    // Candidate tick sets from the densest down; the first whose labels keep apart wins.
    const auto fits = [&](const std::vector<Tick>& t) {
        for (std::size_t i = 1; i < t.size(); ++i)
            if (std::abs(m(t[i].value) - m(t[i - 1].value)) <
                0.5 * (extent_px(t[i].label) + extent_px(t[i - 1].label)) + gap_px)
                return false;
        return true;
    };
    std::vector<Tick> out;
    if (m.scale == Scale::Log) {
        const int d0 = int(std::ceil(std::log10(std::min(m.lo, m.hi)) - 1e-9)),
                  d1 = int(std::floor(std::log10(std::max(m.lo, m.hi)) + 1e-9));
        for (int stride = std::max(1, (d1 - d0 + 1) / 8); stride <= std::max(1, d1 - d0 + 1);
             ++stride) {
            out.clear();
            for (int d = d0; d <= d1; d += stride) {
                const double v = std::pow(10.0, d);
                out.push_back(
                    {v, d >= -3 && d <= 4 ? fmt::format("{:g}", v) : fmt::format("1e{}", d)});
            }
            if (fits(out)) return out;
        }
    } else {
        for (int target = std::max(1, most); target >= 1; --target) {
            const auto values = linear_ticks(std::min(m.lo, m.hi), std::max(m.lo, m.hi), target);
            const double spacing = values.size() > 1 ? values[1] - values[0] : 1.0;
            out.clear();
            for (double v : values)
                if (m.inside(v)) out.push_back({v, tick_label(v, spacing)});
            if (fits(out)) return out;
        }
    }
    // Not even two labels fit: the first alone.
    if (out.size() > 1) out.resize(1);
    return out;
}

std::optional<NearestPoint> nearest_point(const Chart& c, const AxisMapping& x,
                                          const AxisMapping& y, double px, double py,
                                          double within_px) {
    std::optional<NearestPoint> best;
    for (std::size_t s = 0; s < c.series.size(); ++s) {
        const Series& series = c.series[s];
        if (series.kind == Series::Kind::Band) continue;
        const std::size_t n = std::min(series.x.size(), series.y.size());
        for (std::size_t i = 0; i < n; ++i) {
            if (!x.inside(series.x[i]) || !y.inside(series.y[i])) continue;
            const double d = std::hypot(x(series.x[i]) - px, y(series.y[i]) - py);
            if (d <= within_px && (!best || d < best->distance_px)) best = {s, i, d};
        }
    }
    return best;
}

Colour palette(std::size_t i) {
    static constexpr Colour kColours[] = {
        {0.12, 0.40, 0.75}, {0.85, 0.33, 0.10}, {0.20, 0.60, 0.25}, {0.55, 0.25, 0.65},
        {0.80, 0.60, 0.05}, {0.10, 0.60, 0.65}, {0.75, 0.20, 0.45}, {0.40, 0.40, 0.40}};
    return kColours[i % (sizeof(kColours) / sizeof(kColours[0]))];
}

void draw_chart(Canvas& cv, const Rect& a, const Chart& c) {
    const auto [x0, x1] = axis_limits(c, false);
    const auto [y0, y1] = axis_limits(c, true);
    // The plot box inside the area: room for tick labels, axis labels and the title.
    const double left = a.x + 74, right = a.x + a.w - 16;
    const double top = a.y + (c.title.empty() ? 14 : 36), bottom = a.y + a.h - 50;
    const AxisMapping mx{c.x.scale, x0, x1, left, right};
    const AxisMapping my{c.y.scale, y0, y1, bottom, top};

    const auto width = [&](const std::string& s) { return cv.text_width(s, kFontPx); };
    const auto height = [&](const std::string&) { return kFontPx; };
    for (const auto& [v, label] : axis_ticks(mx, width, kFontPx)) {
        const double px = mx(v);
        cv.line({px, top}, {px, bottom}, {kGrid, 1.0});
        cv.line({px, bottom}, {px, bottom + 5}, {kInk, 1.0});
        cv.text(px, bottom + 19, label, kFontPx, Align::Centre);
    }
    for (const auto& [v, label] : axis_ticks(my, height, 0.5 * kFontPx)) {
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
