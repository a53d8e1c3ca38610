// Whether a reflector keeps clear of the light source (DESIGN.md §2: a reflector that
// cuts the source is invalid), and by how much, for scene checks and the optimizer.
#pragma once

#include "model/scene.hpp"
#include "model/surface.hpp"

namespace fird {

// The axis-aligned box that holds every point of the source's surface, in mm.
struct SourceBox {
    glm::dvec3 lo, hi;
};
SourceBox source_box(const SourceDesc& source);

// The lowest point of the source's bounding box minus the highest the surface reaches
// under it, in mm (conservative: the surface's height bound over the footprint). Positive
// when the reflector is clear; +infinity when the source is not over the reflector.
double source_clearance_mm(const Surface& surface, const SourceDesc& source);

// Throws std::invalid_argument when the reflector cuts the light source.
void check_reflector_clear_of_source(const Surface& surface, const SourceDesc& source);

} // namespace fird
