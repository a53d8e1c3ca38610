// FIRD's objects as VTK datasets (the types ParaView opens), from the plain data the
// engine computes: height field, quadtree, ray paths, far fields, source and holder.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <vtkSmartPointer.h>

#include "farfield/farfield.hpp"
#include "fastpath/fast_tracer.hpp"
#include "fastpath/scene_params.hpp"
#include "model/scene.hpp"
#include "model/surface.hpp"

class vtkImageData;
class vtkPolyData;
class vtkStructuredGrid;
class vtkUnstructuredGrid;

namespace fird::vtkio {

// Points at the texel centres (z = the texel's height), point arrays height_mm, normal,
// and, with hits, hits (reflections at the texel, all bounces) and first_hits.
vtkSmartPointer<vtkStructuredGrid> reflector_grid(const Holder& holder, std::uint32_t width,
                                                  std::uint32_t height,
                                                  const std::vector<float>& heights_mm,
                                                  const std::vector<glm::vec2>& gradients,
                                                  const TexelHits* hits);

// The exact surface sampled at the centres of a w x h grid (a search's reflectors).
vtkSmartPointer<vtkStructuredGrid> surface_grid(const Surface& surface, std::uint32_t w,
                                                std::uint32_t h);

// Nodes of the given quadtree levels as boxes from the holder's floor to the node's
// maximum height: cell arrays level and max_height_mm.
vtkSmartPointer<vtkUnstructuredGrid> quadtree_boxes(const Holder& holder,
                                                    const QuadtreeLayout& layout,
                                                    const std::vector<float>& tree,
                                                    const std::vector<std::uint32_t>& levels);
// Boxes the given levels hold.
std::uint64_t quadtree_box_count(const QuadtreeLayout& layout,
                                 const std::vector<std::uint32_t>& levels);

// Polylines: point array bounce (reflections before the point), cell arrays bounces and
// energy_lm.
vtkSmartPointer<vtkPolyData> ray_paths(const std::vector<RayPath>& paths, double energy_lm);

// The far field as an image of W x H cells, azimuth across and altitude up, spacing and
// origin in degrees: cell arrays lumens and candela (and target_lumens,
// difference_lumens with a target).
vtkSmartPointer<vtkImageData> farfield_image(const FarField& farfield, const FarField* target);
// The same cells as quads on the unit sphere, with solid_angle_sr besides.
vtkSmartPointer<vtkPolyData> farfield_sphere(const FarField& farfield, const FarField* target);

vtkSmartPointer<vtkPolyData> source_surface(const SourceDesc& source);
vtkSmartPointer<vtkPolyData> holder_box(const Holder& holder);

} // namespace fird::vtkio
