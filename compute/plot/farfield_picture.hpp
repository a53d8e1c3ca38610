// The far field in false colour with degree axes and a colour bar, laid out as the
// paper's figures: azimuth across (-180..180 deg), altitude down (+90 at the top).
#pragma once

#include <optional>
#include <string>
#include <utility>

#include "farfield/farfield.hpp"
#include "plot/chart.hpp"

namespace fird::plot {

struct FarFieldPicture {
    std::string title;
    bool signed_values = false; // a difference: diverging colours around 0
    bool log_scale = false;     // colour by log10 over four decades below the peak
    // Altitudes shown, degrees (high, low); empty: the whole sphere.
    std::optional<std::pair<double, double>> altitude_deg;
};

void draw_farfield(Canvas& canvas, const Rect& area, const FarField& farfield,
                   const FarFieldPicture& options);

// Where draw_farfield puts the map in `area` and which rows [row0, row1) it shows (all
// columns, azimuth -180 at the left): what a readout of the cell under a pixel needs.
struct FarFieldMapPlacement {
    Rect map;
    std::uint32_t row0 = 0, row1 = 0;
};
FarFieldMapPlacement farfield_map_placement(const Rect& area, const FarField& farfield,
                                            const FarFieldPicture& options);

// The picture alone: one pixel per cell up to 1800 x 900 (each pixel the largest |value|
// of its cells, so narrow peaks survive).
void write_farfield_png(const std::string& path, const FarField& farfield,
                        const FarFieldPicture& options);

// The altitude band (high, low, degrees) that holds all but `fraction` of the light,
// widened by a margin: where a zoomed view should look.
std::pair<double, double> lit_altitude_band(const FarField& farfield, double fraction = 1e-3);

// The window of `height_deg` altitude inside `band` (high, low) that holds the most light:
// where a view zoomed into the band looks (on the bright part, not on the middle of the
// band, which stray light far from it can stretch).
std::pair<double, double> brightest_altitude_window(const FarField& farfield,
                                                    std::pair<double, double> band,
                                                    double height_deg);

} // namespace fird::plot
