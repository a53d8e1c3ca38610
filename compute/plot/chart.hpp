// Line plots with axes, ticks and labels, log axes, scatter with sizes, bands and
// reference lines, drawn on a Canvas: optimization progress, parameter paths, Table 1,
// semivariograms with their fitted curves, run time against error.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "plot/canvas.hpp"

namespace fird::plot {

enum class Scale { Linear, Log };

struct Axis {
    std::string label;
    Scale scale = Scale::Linear;
    std::optional<double> min, max; // fixed limits (else from the data)
};

struct Series {
    enum class Kind { Line, Points, Band } kind = Kind::Line;
    std::string label;             // legend entry (empty: none)
    std::vector<double> x, y;      // Band: y is the lower edge
    std::vector<double> y_upper;   // Band: the upper edge
    std::vector<double> radius_px; // Points: per point (empty: 3.5 px each)
    Colour colour = kInk;
    double width = 1.8;
    bool dashed = false;
};

// A vertical or horizontal reference line across the plot, with a label.
struct Mark {
    bool vertical = true;
    double value = 0.0;
    std::string label;
    Colour colour = kInk;
};

struct Chart {
    std::string title;
    Axis x, y;
    std::vector<Series> series;
    std::vector<Mark> marks;
    bool legend = true;
};

struct Rect {
    double x = 0, y = 0, w = 0, h = 0;
};

void draw_chart(Canvas& canvas, const Rect& area, const Chart& chart);

// A chart alone as a PNG of w x h pixels.
void write_chart_png(const std::string& path, const Chart& chart, int w = 900, int h = 560);

// Colour i of a qualitative palette (distinguishable lines).
Colour palette(std::size_t i);

// Round tick values covering [lo, hi] (about `target` of them), and their labels.
std::vector<double> linear_ticks(double lo, double hi, int target = 6);
std::string tick_label(double value, double spacing);

// The axis logic both chart renderers share (cairo here, ImGui in the workbench).

// The range an axis of the chart shows: its series' and marks' values, padded, with the
// axis's fixed limits applied. A constant series is shown about its value (±5 %, or ±1
// about 0), never as a sliver of ±1e-9.
std::pair<double, double> axis_limits(const Chart& chart, bool y_axis);

// Axis values to pixels (and back), linear or log between lo and hi.
struct AxisMapping {
    Scale scale = Scale::Linear;
    double lo = 0, hi = 1; // data
    double p0 = 0, p1 = 1; // pixels
    double operator()(double value) const;
    double value_at(double pixel) const;
    bool inside(double value) const;
};

struct Tick {
    double value = 0;
    std::string label;
};
// The ticks of an axis whose labels never overlap: as many as fit (at most `most` on a
// linear axis, about 8 decades on a log axis), each label's extent along the axis measured by
// `extent_px` (its width on a horizontal axis, its height on a vertical one) and at least
// `gap_px` between neighbouring labels. Only ticks inside the axis's range.
std::vector<Tick> axis_ticks(const AxisMapping& axis,
                             const std::function<double(const std::string&)>& extent_px,
                             double gap_px, int most = 6);

// The drawn point (of a Line or Points series) nearest pixel (px, py), within `within_px`:
// what a hover readout names.
struct NearestPoint {
    std::size_t series = 0, index = 0;
    double distance_px = 0;
};
std::optional<NearestPoint> nearest_point(const Chart& chart, const AxisMapping& x,
                                          const AxisMapping& y, double px, double py,
                                          double within_px);

} // namespace fird::plot
