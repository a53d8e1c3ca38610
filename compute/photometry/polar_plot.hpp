// A polar plot of a candela table's principal planes (C0-C180 and C90-C270) as PNG, the
// picture lighting engineers read a distribution from.
#pragma once

#include <string>

#include "photometry/candela_table.hpp"
#include "plot/chart.hpp"

namespace fird {

// Into a region of a canvas (the workbench's and the reports' view).
void draw_polar_plot(plot::Canvas& canvas, const plot::Rect& area, const CandelaTable& table);

// Throws std::runtime_error naming the path on failure.
void write_polar_plot_png(const std::string& path, const CandelaTable& table);

} // namespace fird
