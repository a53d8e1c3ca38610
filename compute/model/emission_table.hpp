// A photometric emitter's sampling table: the candela table of an IES / LDT file laid out
// for shaders/emitter.h's photometric_direction, which both tracers run.
#pragma once

#include "model/scene.hpp"
#include "photometry/candela_table.hpp"

namespace fird {

// The layout (floats): C (radians; the table's C angles and the first again at 2 pi),
// cos(gamma) for each gamma angle, the intensity (cd) at each (C, gamma) with C outer, and
// per cell (C_j..C_j+1, gamma_i..gamma_i+1; index j (gammas - 1) + i) the cumulative share
// of the flux, the exact integral of the table's interpolation (bilinear in C and cos
// gamma), ending at 1. Throws std::invalid_argument when the table emits no flux.
EmissionTable emission_table(const CandelaTable& table);

} // namespace fird
