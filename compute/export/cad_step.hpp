// The reflector as a STEP part in millimetres: its face over the holder rectangle (a
// height-field B-spline's own parameter rectangle, or a revolved profile trimmed to it), or
// thickened into a solid sheet whose back face is the surface offset by the thickness
// against its upward normal (the reflector is solid below the surface, open above).
#pragma once

#include <string>

#include <Geom_BSplineSurface.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>

namespace fird {

// The height-field B-spline's face over its parameter rectangle (its normal up).
TopoDS_Face height_field_face(const Handle(Geom_BSplineSurface) & surface);

// A face or a shell, its normal up, as a solid sheet thickness_mm thick (> 0): its back
// faces offset by the thickness against the normal. Throws std::runtime_error where
// OpenCASCADE fails or the solid is not valid.
TopoDS_Shape thickened(const TopoDS_Shape& top, double thickness_mm);

// `face` (a face or a shell)'s normal is up; thickness_mm 0: the surface alone. Throws
// std::runtime_error where OpenCASCADE fails.
TopoDS_Shape reflector_shape(const TopoDS_Shape& face, double thickness_mm);

// Writes `shape` as STEP AP214 (unit mm) to `path`, whole or not at all.
void write_step(const TopoDS_Shape& shape, const std::string& path);

} // namespace fird
