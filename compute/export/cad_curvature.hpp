// Where a sheet thickened from the reflector surface would intersect itself: the back
// face, offset by the thickness against the upward normal, folds over wherever the
// surface bends towards its back (the centre of curvature below it) with a radius of
// curvature at or under the thickness.
#pragma once

#include <Geom_Surface.hxx>
#include <glm/vec2.hpp>

#include "model/scene.hpp"

namespace fird {

struct BackCurvature {
    double smallest_radius_mm = 0.0; // infinity where the surface never bends towards its back
    glm::dvec2 where_xy_mm{0.0};
};

// Principal curvatures on an nx x ny grid over the surface's parameter rectangle, at the
// points over the holder rectangle (a revolved surface's disc reaches beyond it), signed
// about the upward normal whichever way the parameters run.
// Only points within the holder's z range count (a creased part: the family beyond the
// clamp is trimmed away).
BackCurvature smallest_back_radius(const Handle(Geom_Surface) & s, const Holder& holder, int nx,
                                   int ny);

} // namespace fird
