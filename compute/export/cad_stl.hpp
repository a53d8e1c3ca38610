// The reflector as a binary STL: the CAD surface sampled on a grid and triangulated, as
// an open surface (normals up) or, given a thickness, a closed solid sheet: the top, the
// back (each vertex offset by the thickness against the surface's upward normal, as the
// STEP solid's back face) and the four side walls joining their rims, every facet
// facing out. Written directly (binary STL is 50 bytes a triangle): a mesher on the
// offset solid would add OpenCASCADE's tessellation tolerances to the heights.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Geom_BSplineSurface.hxx>
#include <TopoDS_Shape.hxx>
#include <glm/vec3.hpp>

#include "model/surface.hpp"

namespace fird {

struct SurfaceGrid {
    int nx = 0, ny = 0;
    std::vector<glm::dvec3> points;  // (i, j) at j * nx + i, mm
    std::vector<glm::dvec3> normals; // unit, up
};

// nx x ny points evenly over the surface's parameter rectangle.
SurfaceGrid sample_surface(const Handle(Geom_BSplineSurface) & surface, int nx, int ny);

// nx x ny points evenly over the holder rectangle on the family without its clamp, the
// normals from its analytic gradient: the STL of a surface written exactly in another form
// (the revolved profile), its vertices on the family to rounding.
SurfaceGrid sample_family(const Surface& surface, int nx, int ny);

// Largest vertical gap between the triangles and the surface z = height(x, y), at each
// triangle's centroid and edge midpoints (where a flat facet strays furthest from a smooth
// surface).
double chord_error_mm(const SurfaceGrid& grid,
                      const std::function<double(double, double)>& height_mm);

// A triangle, counter-clockwise seen from outside (mm).
using StlTriangle = std::array<glm::dvec3, 3>;

// A creased reflector (cad_crease) as OpenCASCADE tessellates it (BRepMesh, facets within
// deflection_mm of the faces, the crease an edge of the mesh, which no regular grid
// follows; triangles with two corners at one point, a pole's, dropped). Throws
// std::runtime_error where BRepMesh fails or leaves a face unmeshed.
std::vector<StlTriangle> tessellate(const TopoDS_Shape& shape, double deflection_mm);

// Binary STL of the triangles (each normal from its winding) with an 80-byte header,
// whole or not at all; returns its size.
std::uint64_t write_stl(const std::vector<StlTriangle>& triangles, const std::string& header,
                        const std::string& path);

// Writes the STL whole or not at all; returns its size in bytes.
std::uint64_t write_reflector_stl(const SurfaceGrid& grid, double thickness_mm,
                                  const std::string& path);

} // namespace fird
