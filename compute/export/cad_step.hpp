// The reflector as a STEP part in millimetres: its B-spline surface as one face bounded
// by the holder rectangle (the surface's own parameter rectangle), or thickened into a
// solid sheet whose back face is the surface offset by the thickness against its upward
// normal (the reflector is solid below the surface, open above).
#pragma once

#include <string>

#include <Geom_BSplineSurface.hxx>
#include <TopoDS_Shape.hxx>

namespace fird {

// thickness_mm 0: the face alone. Throws std::runtime_error where OpenCASCADE fails.
TopoDS_Shape reflector_shape(const Handle(Geom_BSplineSurface) & surface, double thickness_mm);

// Writes `shape` as STEP AP214 (unit mm) to `path`, whole or not at all.
void write_step(const TopoDS_Shape& shape, const std::string& path);

} // namespace fird
