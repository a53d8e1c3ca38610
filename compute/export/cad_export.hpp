// fird export --cad: the reflector as CAD, reflector.step (OpenCASCADE, mm: a B-spline
// surface, the profile family's revolved one trimmed to the holder, a solid sheet of
// either, or where the holder clamps the family a trimmed face and the flat flange beyond)
// and reflector.stl (binary), with how far each strays from the family.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "export/cad_bend_report.hpp"
#include "export/scene_export.hpp"
#include "model/surface.hpp"

namespace fird {

struct CadOptions {
    double tolerance_mm = 0.01; // largest height deviation a fitted surface may have
    double thickness_mm = 0.0;  // 0: the surface alone; else a solid sheet this thick
    // A creased sheet's bend radius at its creases (cad_bend); 0: twice the thickness.
    double bend_radius_mm = 0.0;
};

struct CadReport {
    bool exact = false;    // the family's own B-spline (no fit)
    bool revolved = false; // the profile's meridian revolved and trimmed (cad_revolution)
    // The holder-rectangle edges' tolerance of a revolved face (OpenCASCADE's intersection).
    double trim_tolerance_mm = 0.0;
    bool creased = false; // trimmed at the holder's top, a flat flange beyond (cad_crease)
    double edge_tolerance_mm = 0.0; // the crease edges' (OpenCASCADE's intersection) tolerance
    double max_deviation_mm = 0.0;  // largest |CAD - family| height on the check grid
    glm::dvec2 worst_xy_mm{0.0};
    int fit_nx = 0, fit_ny = 0, check_nx = 0, check_ny = 0;
    // Smallest radius of curvature bending towards the back (the thickness must stay under it).
    double back_radius_mm = std::numeric_limits<double>::infinity();
    glm::dvec2 back_radius_xy_mm{0.0};
    int stl_nx = 0, stl_ny = 0;
    double stl_chord_mm = 0.0; // largest gap between the STL's facets and the CAD surface
                               // (a creased one: BRepMesh's deflection, the tolerance)
    std::optional<Bend> bend;  // a creased sheet's bends
    std::vector<ExportedFile> files;
};

// Checks everything before it writes: throws CadOptionError (cad_option_error.hpp) naming
// --cad-tolerance, --thickness or --bend-radius, std::runtime_error naming the directory or
// a file that cannot be written. Each file is written whole or not at all. Calls from two
// threads run one after the other (OpenCASCADE's STEP options are process-wide).
CadReport export_cad(const Surface& surface, const CadOptions& options,
                     const std::string& directory);

} // namespace fird
