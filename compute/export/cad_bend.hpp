// A creased reflector (cad_crease) as the sheet a press forms: every crease, where the
// reflector meets the holder's flat top or floor, rounded to a bend radius (OpenCASCADE's
// rolling-ball fillet), then the shell thickened into a solid with its back face offset
// along the normal. Where the crease bends towards the back (a rim turning into the flange)
// the back face's bend has the radius less the thickness, so the bend radius must exceed it.
#pragma once

#include <TopoDS_Shape.hxx>

#include "export/cad_bend_report.hpp"
#include "model/surface.hpp"

namespace fird {

// `shell` is creased_shell's. Throws CadOptionError naming --bend-radius where OpenCASCADE
// cannot round a crease with that radius (the place is named) or the sheet comes out
// invalid, std::runtime_error where the offset fails.
TopoDS_Shape bent_sheet(const TopoDS_Shape& shell, const Surface& surface, double radius_mm,
                        double thickness_mm, Bend& bend);

} // namespace fird
