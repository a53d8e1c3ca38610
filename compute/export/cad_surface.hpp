// The reflector as one OpenCASCADE B-spline surface over the holder rectangle, in the
// height-field form S(u, v) = (u, v, z(u, v)) with u, v the x, y in mm: the bspline family
// exactly (same degree, knots and control heights), every other family and a mesh fitted
// to its height field until the largest deviation, found on a grid denser than the fit's,
// is within the tolerance.
#pragma once

#include "export/cad_option_error.hpp"
#include <stdexcept>

#include <Geom_BSplineSurface.hxx>
#include <glm/vec2.hpp>

#include "model/surface.hpp"

namespace fird {

struct CadSurface {
    Handle(Geom_BSplineSurface) surface;
    bool exact = false;            // the family's own B-spline, not a fit
    double max_deviation_mm = 0.0; // largest |S_z - f| over the check grid
    glm::dvec2 worst_xy_mm{0.0};   // where
    int fit_nx = 0, fit_ny = 0;    // height samples interpolated (the B-spline's grid if exact)
    int check_nx = 0, check_ny = 0;
};

// The largest height sample grid a fit may use per axis (the STEP file grows with its
// square: about 85 bytes a control point).
inline constexpr int kMaxFitSamples = 1025;

// Which function the CAD surface follows: the family as the tracer sees it (clamped to the
// holder's z range) or without the clamp (to be trimmed at the holder's top: cad_crease).
enum class Heights { Clamped, Unclamped };

struct HeightFunction {
    const Surface& surface;
    Heights heights;
    double height(double x, double y) const {
        return heights == Heights::Clamped ? surface.height(x, y) : surface.raw(x, y);
    }
    glm::dvec2 gradient(double x, double y) const {
        return heights == Heights::Clamped ? surface.gradient(x, y) : surface.raw_gradient(x, y);
    }
};

// Throws CadOptionError naming --cad-tolerance when no fit within kMaxFitSamples meets it.
CadSurface make_cad_surface(const Surface& surface, double tolerance_mm,
                            Heights heights = Heights::Clamped);

// Largest vertical distance |S_z(u, v) - f(S_x, S_y)| over an nx x ny grid of the
// surface's parameter rectangle (vertical distance bounds the normal distance from above).
double max_vertical_deviation(const Geom_BSplineSurface& s, const HeightFunction& f, int nx, int ny,
                              glm::dvec2* where = nullptr);

} // namespace fird
