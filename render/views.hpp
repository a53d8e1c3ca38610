// The views a workbench window and a screenshot show, drawn from what compute produced:
// the 3D viewport (Vulkan, on the shared device), the far fields (desired, obtained and
// difference in false colour, zoomed to the lit band, with the polar curves of the
// principal planes) and the profile plots (cairo, compute/plot).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "farfield/farfield.hpp"
#include "photometry/luminaire_pictures.hpp"
#include "plot/chart.hpp"
#include "plot/farfield_picture.hpp"
#include "viewport.hpp"

namespace fird::render {

enum class FarFieldMapKind { Desired, Obtained, Difference };

struct FarFieldViewOptions {
    bool log_scale = false;
    // Altitudes shown (high, low, deg); empty: the lit band of the obtained far field.
    std::optional<std::pair<double, double>> altitude_deg;
    // Azimuths shown (left, right, deg); empty: all of them.
    std::optional<std::pair<double, double>> azimuth_deg;
    // One map alone (filling the area); empty: every map there is.
    std::optional<FarFieldMapKind> only;
    // The maps in this many columns, row by row (the polar curves only beside one column).
    int columns = 1;
    // Instead of the maps: a luminaire view (polar map, isocandela lines, illuminance on a
    // plane this far below), beside the desired one and the difference.
    std::optional<LuminaireView> luminaire;
    double plane_distance_m = 3.0;
};

// How an area of w x h pixels shows n maps: in the columns that give each map the most
// height, and the height they need: h, or more where a map would be lower than
// kFarFieldMapMinPx (the panel then scrolls rather than squeezing them).
inline constexpr double kFarFieldMapMinPx = 80.0;
struct FarFieldViewGrid {
    int columns = 1;
    double height = 0.0;
};
FarFieldViewGrid farfield_view_grid(double w, double h, std::size_t n);

struct FarFieldContent {
    std::string title;
    FarField obtained;
    std::optional<FarField> desired;
    std::optional<double> l2_lm;
};

// Desired, obtained and difference maps (or the one the options name) in the options'
// columns, then the polar curves.
void draw_farfield_view(plot::Canvas& canvas, const plot::Rect& area, const FarFieldContent& c,
                        const FarFieldViewOptions& options);
// The maps draw_farfield_view draws, in order (desired, obtained, difference; the obtained
// alone without a desired far field; the options' one alone), where each is placed: for a
// readout of the cell under the mouse.
struct FarFieldViewMap {
    FarFieldMapKind kind;
    plot::FarFieldMapPlacement placement;
};
std::vector<FarFieldViewMap> farfield_view_maps(const plot::Rect& area, const FarFieldContent& c,
                                                const FarFieldViewOptions& options);

// The cell under pixel (px, py) of the view, and the map it is in; none off the maps.
struct FarFieldCellAt {
    FarFieldMapKind kind;
    std::uint32_t row = 0, column = 0;
};
std::optional<FarFieldCellAt> farfield_cell_at(const std::vector<FarFieldViewMap>& maps,
                                               const FarField& grid, double px, double py);

// Light against altitude and against azimuth, obtained and desired.
void draw_profile_plots(plot::Canvas& canvas, const plot::Rect& area, const FarFieldContent& c);

// The viewport rendered offscreen and read back (RGBA rows, top first).
std::vector<std::uint8_t> render_viewport(const vk::Context& ctx, ViewportRenderer& renderer,
                                          const ViewportContent& content,
                                          const ViewportOptions& options, std::uint32_t width,
                                          std::uint32_t height);

// RGBA pixels as a PNG (through cairo), written atomically.
void write_rgba_png(const std::string& path, const std::vector<std::uint8_t>& rgba,
                    std::uint32_t width, std::uint32_t height);

} // namespace fird::render
