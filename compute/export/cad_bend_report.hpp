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
    // Clamped flats smaller than the bend's disc (pi R^2) are not formed: the sheet follows
    // the family through them, up to this far past the holder's top or floor.
    int unformed_flats = 0;
    double unformed_depth_mm = 0.0;
};

} // namespace fird
