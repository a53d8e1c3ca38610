// The views a luminaire designer reads, drawn beside the desired ones and their difference
// (issue 26 item 8): the intensity on a polar map centred on nadir (the beam's axis), the
// isocandela lines in C-gamma, and the illuminance on a plane across the beam at a given
// distance. Written by every --out with a far field and drawn by the workbench's far-field
// panel; the data behind them is photometry/luminaire_views.hpp.
#pragma once

#include <optional>
#include <string>

#include "farfield/farfield.hpp"
#include "photometry/candela_table.hpp"
#include "plot/chart.hpp"

namespace fird {

enum class LuminaireView { PolarMap, Isocandela, Illuminance };
const char* luminaire_view_name(LuminaireView view); // "polar", "isocandela", "illuminance"

struct LuminaireViewOptions {
    std::string title;             // the scene's name
    double plane_distance_m = 3.0; // the illuminance plane's distance below the luminaire
};

// The candela table the views read from a far field: C every 5 deg, gamma every 1 deg
// (photometrics' patches), or the far field's own steps where it is coarser.
CandelaTable view_table(const FarField& farfield);

// One view into `area`: the obtained table alone, or (desired given) obtained | desired |
// difference side by side, the first two on one colour scale.
void draw_luminaire_view(plot::Canvas& canvas, const plot::Rect& area, LuminaireView view,
                         const CandelaTable& obtained, const CandelaTable* desired,
                         const LuminaireViewOptions& options);

// What a point of a view drawn by draw_luminaire_view into `area` reads (the workbench's
// hover readout): the panel it falls in, the direction (C, gamma in degrees) it shows, and
// the obtained and desired intensity there (cd); for the illuminance view, the point on the
// plane (m, x along C0, y along C90) and the illuminance there (lx) with the direction its
// light leaves in. None outside every panel's picture (or a polar map's disc).
// gamma_max_deg: luminaire_view_gamma_deg of the two tables, as the drawing takes it.
enum class LuminairePanel { Obtained, Desired, Difference };
struct LuminaireReadout {
    LuminairePanel panel = LuminairePanel::Obtained;
    double c_deg = 0.0, gamma_deg = 0.0;
    bool on_plane = false; // illuminance: x_m, y_m and values in lx
    double x_m = 0.0, y_m = 0.0;
    double obtained = 0.0;
    std::optional<double> desired;
};
std::optional<LuminaireReadout> luminaire_view_readout(const plot::Rect& area, LuminaireView view,
                                                       const CandelaTable& obtained,
                                                       const CandelaTable* desired,
                                                       const LuminaireViewOptions& options,
                                                       double gamma_max_deg, double px, double py);

// The gamma range a view shows: where all but 0.5 % of the light of either table leaves,
// rounded up to 10 deg, at least 30 (an integration over the tables: worth keeping).
double luminaire_view_gamma_deg(const CandelaTable& obtained, const CandelaTable* desired);

// polar.png, isocandela.png and illuminance.png in `dir` (which exists).
void write_luminaire_views(const std::string& dir, const FarField& obtained,
                           const FarField* desired, const LuminaireViewOptions& options);

} // namespace fird
