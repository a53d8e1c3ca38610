// Exact ray / height-field-surface intersection for the CPU reference tracer.
#pragma once

#include <optional>

#include "model/source.hpp"
#include "model/surface.hpp"

namespace fird {

enum class HitStart {
    Above,        // the search starts above the surface
    BelowSurface, // the ray starts inside the solid (a scene error when it is the source)
    Blocked,      // the ray enters the holder box through its side below the surface
};

struct SurfaceHit {
    HitStart start = HitStart::Above;
    std::optional<double> t; // distance to the first crossing, if any
};

// The first t >= t_min where the ray crosses from above the surface to below it, inside
// the holder box. Segments of the ray are culled when they lie above the surface's height
// range over their xy footprint (Surface::bounds) and split otherwise, front to back,
// down to 1e-4 mm; a crossing is then refined by bisection to ~1e-12 mm. Crossings that
// enter and leave within 1e-4 mm (a measure-zero graze) are the only ones not reported.
SurfaceHit first_surface_hit(const Surface& surface, const Ray& ray, double t_min);

// The upward unit normal of the surface at (x, y).
glm::dvec3 surface_normal(const Surface& surface, double x, double y);

} // namespace fird
