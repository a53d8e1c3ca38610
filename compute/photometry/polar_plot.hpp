// A polar plot of a candela table's principal planes (C0-C180 and C90-C270) as PNG, the
// picture lighting engineers read a distribution from.
#pragma once

#include <string>

#include "photometry/candela_table.hpp"

namespace fird {

// Throws std::runtime_error naming the path on failure.
void write_polar_plot_png(const std::string& path, const CandelaTable& table);

} // namespace fird
