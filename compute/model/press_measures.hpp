// What a press cares about in a reflector, measured once for every reader (the search's
// constraints, the manufacturability report, the workbench's overlay): the steepest slope
// from the press plane (the draft the die needs), the smallest radius of curvature (the
// tightest bend a tool forms), the depth, the area, and the vertical walls left at the
// holder's rim. Sampled on a grid over the holder rectangle from the family's own heights
// and gradient; each extreme comes with how far the grid may have missed it.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "model/scene.hpp"
#include "model/surface.hpp"

namespace fird {

// A stretch of the holder's rim where the reflector's edge lies below the holder's top (the
// press plane, where the blank is held): the part would need a vertical wall up to it
// there, a step the press cannot draw.
struct RimWall {
    std::string side; // "x_min", "x_max", "y_min" or "y_max"
    glm::dvec2 from_mm{0.0}, to_mm{0.0};
    double length_mm = 0.0;
    double height_mm = 0.0; // the tallest point of the wall
};

// Per sample, row-major (ny rows of nx, row 0 at the holder's y min): the maps the picture
// and the workbench colour. NaN where the clamp holds the surface (no measure there).
struct PressMaps {
    int nx = 0, ny = 0;
    std::vector<float> slope_deg;
    std::vector<float> curvature_per_mm; // the larger principal curvature in magnitude
};

struct PressMeasures {
    int nx = 0, ny = 0; // the sampling grid, rim included
    double dx_mm = 0.0, dy_mm = 0.0;
    bool any_unclamped = false; // false: the clamp holds the whole surface (a flat part)
    double max_slope_deg = 0.0;
    glm::dvec2 max_slope_at_mm{0.0};
    // How much steeper the surface may be between samples: over the cells of the grid, the
    // largest corner plus the corners' spread (one step's change), less the largest sample
    // (press_measures.cpp, missed_by_cells).
    double slope_error_deg = 0.0;
    // Infinity for a plane; the curvature from the Hessian by central differences of the
    // family's analytic gradient (docs/export.md); NaN for a mesh (its facets have none).
    double min_radius_mm = std::numeric_limits<double>::infinity();
    glm::dvec2 min_radius_at_mm{0.0};
    // The surface has a kink there (its gradient jumps: radius 0, min_radius_mm = 0), found
    // where the curvature exceeds what the differences resolve (docs/export.md).
    bool kink = false;
    // As slope_error_deg, for the curvature 1 / radius (0 at a kink: no bound is meant).
    double curvature_error_per_mm = 0.0;
    // The bending energy: the integral of k1^2 + k2^2 (the principal curvatures) over the
    // unclamped surface's area, dimensionless (a sphere's cap of any radius covering a
    // solid angle w: 2 w). The clamp's flats and the kink where they meet the family are
    // left out (that bend is the holder's, not the part's), and so are samples on a kink
    // (`kink` below: a profile's crease where it turns flat at its radius, a cup's apex of
    // power below 2), where the differences would read the grid's step, not the part; the
    // kink itself is what min_radius_mm = 0 reports. NaN for a mesh, or without curvature.
    double bending_energy = 0.0;
    double depth_mm = 0.0; // highest minus lowest point of the surface
    double area_mm2 = 0.0; // the whole surface, the clamp's flats included
    double unclamped_area_mm2 = 0.0;
    std::vector<RimWall> rim_walls;
    PressMaps maps; // filled when asked for
};

// Samples along the holder's longer side; the shorter gets the same step.
constexpr int kPressGridIntervals = 512;

struct PressOptions {
    bool curvature = true; // false: no Hessian (a third of the work; min_radius_mm NaN)
    bool maps = false;     // fill PressMeasures::maps
    // Measure every stride-th sample of the grid (and its last) only: a subset of the full
    // grid's samples, each measured exactly as there, so an extreme that breaks a limit
    // here breaks it on the full grid too (the search's quick refusal). Area and the
    // sampling errors are then the coarse grid's.
    int stride = 1;
};

// The surface measured on a grid of kPressGridIntervals along the holder's longer side.
PressMeasures press_measures(const Surface& surface, const PressOptions& options = {});
// The same on a grid of `nx` x `ny` samples (tests use coarser and finer grids).
PressMeasures press_measures(const Surface& surface, int nx, int ny,
                             const PressOptions& options = {});

// The bending energy as a search's smoothness penalty takes it ([optimize] smoothness):
// on every 4th sample of the press grid (128 intervals along the holder's longer side), a
// sixteenth of the full grid's work. Converges as the square of the interval on a smooth
// surface (press_measures_test.cpp measures it).
double search_bending_energy(const Surface& surface);

// One constraint of [reflector.constraints] against its measure.
struct ConstraintCheck {
    std::string name; // the scene key: "max_slope_deg", "min_radius_mm", "max_depth_mm"
    double value = 0.0;
    double limit = 0.0;
    bool met = true;
    // How far it is broken, as a share of the limit (0 when met): a penalty's scale.
    double violation = 0.0;
};
// Every constraint given, in the scene keys' order above.
std::vector<ConstraintCheck> check_constraints(const PressMeasures& m, const ConstraintsDesc& c);

// The constraints on the surface as a search needs them: curvature only where a radius is
// limited, and first on every 8th sample, where a broken limit is broken on the full grid
// too (the checks then are those of the coarse grid: the same verdict, its own values);
// else on the full grid. An infeasible candidate costs a sixty-fourth of a feasible one.
std::vector<ConstraintCheck> constraint_checks(const Surface& surface, const ConstraintsDesc& c);

} // namespace fird
