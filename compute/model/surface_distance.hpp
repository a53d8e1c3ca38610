// How far apart two reflector surfaces are: recovery is judged by the surface, not by
// parameter values (a family may reach one surface from several parameter vectors).
#pragma once

#include "model/surface.hpp"

namespace fird {

// RMS of the height difference over the holder rectangle (both surfaces clamped, sampled
// at the centres of an n x n grid), in mm.
double surface_rms_distance_mm(const Surface& a, const Surface& b, int samples = 256);

} // namespace fird
