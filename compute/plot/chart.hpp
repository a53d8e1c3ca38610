// Line plots with axes, ticks and labels, log axes, scatter with sizes, bands and
// reference lines, drawn on a Canvas: optimization progress, parameter paths, Table 1,
// semivariograms with their fitted curves, run time against error.
#pragma once

#include <optional>
#include <string>
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

} // namespace fird::plot
