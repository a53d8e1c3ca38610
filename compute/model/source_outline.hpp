// The emitting surface of a light source as a triangle mesh, for every view that draws it
// (the workbench's viewport, the VTK export): one shape per emitter, written once.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "model/scene.hpp"

namespace fird {

struct SourceOutline {
    std::vector<glm::dvec3> vertices_mm;
    std::vector<std::array<std::uint32_t, 3>> triangles; // indices into vertices_mm
};

// A cylinder's lateral surface (its caps are dark), a sphere, a disk, a rectangle; a point
// as a small sphere of `point_radius_mm`. `around`: segments of a full circle.
SourceOutline source_outline(const SourceDesc& source, double point_radius_mm, int around = 32);

} // namespace fird
