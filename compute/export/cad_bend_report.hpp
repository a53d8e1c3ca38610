// What bending a creased sheet's creases did (cad_bend), in the CAD report: a header of
// plain data, so that the command line includes no OpenCASCADE header.
#pragma once

#include <glm/vec2.hpp>

namespace fird {

struct Bend {
    double radius_mm = 0.0;
    int creases = 0; // crease edges rounded
    double crease_length_mm = 0.0;
    double max_deviation_mm = 0.0; // largest |z - family| over the bends' faces
    glm::dvec2 worst_xy_mm{0.0};
};

} // namespace fird
