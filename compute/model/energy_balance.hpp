// The energy terms of an evaluation in lumens (DESIGN.md §2): emitted = discarded + direct
// + far field + lost + absorbed, where a reflector of reflectance R keeps R^k of a ray's
// flux after k reflections and absorbs the rest. Every command's --json, the workbench and
// the tests read them from here.
#pragma once

#include "model/evaluation_result.hpp"

namespace fird {

struct EnergyBalance {
    double emitted_lm = 0.0;
    double farfield_lm = 0.0;  // reflected light that left for the far field
    double direct_lm = 0.0;    // left without touching the reflector
    double discarded_lm = 0.0; // missed the holder box
    double lost_lm = 0.0;      // what the lost rays still carried
    double absorbed_lm = 0.0;  // taken by the reflections (far-field and lost rays alike)
    // What the far field holds: the reflected light, and the direct light where the scene
    // bins it ([trace] direct = "include").
    double binned_lm = 0.0;
};

EnergyBalance energy_balance(const RayTally& tally, double lm_per_ray);

} // namespace fird
