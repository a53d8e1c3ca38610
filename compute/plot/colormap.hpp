// False-colour maps for far fields and height fields.
#pragma once

#include <array>
#include <cstdint>

namespace fird::plot {

using Rgb = std::array<std::uint8_t, 3>;

// Sequential: black - purple - orange - yellow - white, t in [0, 1].
Rgb sequential_colour(double t);
// Diverging: blue - white - red, t in [-1, 1].
Rgb diverging_colour(double t);

} // namespace fird::plot
