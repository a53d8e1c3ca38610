// The profile family as CAD, exactly: its meridian z = z0 + f(r) as the family's own
// uniform cubic B-spline in r (a plane annulus beyond radius_mm, where the family holds its
// last height), revolved about the axis through (cx, cy) into a rational B-spline surface
// (OpenCASCADE writes the circle exactly, as rational quadratics), and trimmed to the
// holder rectangle by a Boolean common with the holder's box. A surface of revolution has
// no exact height-field form S(u, v) = (u, v, z): r = sqrt(x^2 + y^2) is not rational.
#pragma once

#include <array>

#include <Geom_BSplineSurface.hxx>
#include <TopoDS_Shape.hxx>
#include <glm/vec2.hpp>

#include "model/surface.hpp"

namespace fird {

struct RevolvedProfile {
    // The spline's disc (out to radius_mm or the holder's farthest corner) in four quarter
    // turns (what a STEP reader can build a sheet's back face on: cad_revolution.cpp).
    std::array<Handle(Geom_BSplineSurface), 4> quarters;
    // A shell of their pieces in the holder rectangle and the flat annulus's, normal up.
    TopoDS_Shape faces;
    double trim_tolerance_mm = 0.0; // the trimming edges' (OpenCASCADE's intersection)
    // The family's slope jumps at radius_mm (f'(radius_mm) is not 0 and the flat beyond
    // lies in the holder): a kink, as sharp as a crease, around that circle, an edge between
    // the spline's faces and the annulus. Rising into it (f' > 0) it bends towards the back.
    bool kink = false;
    double slope_at_radius = 0.0;  // f'(radius_mm)
    double max_deviation_mm = 0.0; // largest |S_z - f| over the check grid inside the holder
    glm::dvec2 worst_xy_mm{0.0};
    int check_nu = 0, check_nv = 0; // the check grid over the angle and the meridian
};

// `surface` is of the profile family. Throws std::runtime_error where OpenCASCADE's
// Boolean fails.
RevolvedProfile revolve_profile(const Surface& surface);

} // namespace fird
