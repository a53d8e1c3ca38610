// The far field in false colour with degree axes and a colour bar, laid out as the
// paper's figures: azimuth across (-180..180 deg), altitude down (+90 at the top).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "farfield/farfield.hpp"
#include "plot/chart.hpp"

namespace fird::plot {

struct FarFieldPicture {
    std::string title;
    bool signed_values = false; // a difference: diverging colours around 0
    bool log_scale = false;     // colour by log10 over four decades below the peak
    // Altitudes shown, degrees (high, low); empty: the whole sphere.
    std::optional<std::pair<double, double>> altitude_deg;
    // Azimuths shown, degrees (left, right, within -180..180); empty: all of them.
    std::optional<std::pair<double, double>> azimuth_deg;
};

void draw_farfield(Canvas& canvas, const Rect& area, const FarField& farfield,
                   const FarFieldPicture& options);

// Where draw_farfield puts the map in `area` and which rows [row0, row1) and columns
// [column0, column1) it shows: what a readout of the cell under a pixel needs.
struct FarFieldMapPlacement {
    Rect map;
    std::uint32_t row0 = 0, row1 = 0;
    std::uint32_t column0 = 0, column1 = 0;
};
FarFieldMapPlacement farfield_map_placement(const Rect& area, const FarField& farfield,
                                            const FarFieldPicture& options);

// The picture alone: one pixel per cell up to 1800 x 900 (each pixel the largest |value|
// of its cells, so narrow peaks survive).
void write_farfield_png(const std::string& path, const FarField& farfield,
                        const FarFieldPicture& options);

// The light per row (altitude) and per column (azimuth) of a far field: what a zoomed
// view's bands are found from. Computed once per far field (the workbench keeps it with
// each trace), so that a frame does not sum a 1800 x 900 map again.
struct FarFieldProfiles {
    std::vector<double> per_row, per_column; // |lm| summed; rows from +90 deg down
};
FarFieldProfiles light_profiles(const FarField& farfield);

// The altitude band (high, low, degrees) that holds all but `fraction` of the light,
// widened by a margin: where a zoomed view should look.
std::pair<double, double> lit_altitude_band(const FarFieldProfiles& profiles,
                                            double fraction = 1e-3);

// The window of `height_deg` altitude inside `band` (high, low) that holds the most light:
// where a view zoomed into the band looks (on the bright part, not on the middle of the
// band, which stray light far from it can stretch).
std::pair<double, double> brightest_altitude_window(const FarFieldProfiles& profiles,
                                                    std::pair<double, double> band,
                                                    double height_deg);

// The same across: the azimuth band (left, right, degrees) holding all but `fraction` of
// the light, widened by a margin, and the window of `width_deg` inside it holding the most.
std::pair<double, double> lit_azimuth_band(const FarFieldProfiles& profiles,
                                           double fraction = 1e-3);
std::pair<double, double> brightest_azimuth_window(const FarFieldProfiles& profiles,
                                                   std::pair<double, double> band,
                                                   double width_deg);

} // namespace fird::plot
