// The far field a scene asks for, on the scene's grid, computed once: the target
// reflector traced with its own seed and ray count (on the fast path, or on the CPU
// reference for a search that runs there), or the photometric file integrated over each
// cell.
#pragma once

#include <string>

#include "evaluation/evaluator.hpp"
#include "farfield/farfield.hpp"
#include "model/scene.hpp"
#include "vk/context.hpp"

namespace fird {

struct DesiredFarField {
    FarField farfield;
    std::string description;    // for reports: what it is and how it was scaled
    double scale_flux_lm = 0.0; // a relative photometric target's total after scaling
};

// The scene's [target] (which must exist). A relative photometric target is scaled to
// `reference_flux_lm`: the caller passes one figure per search (the far-field flux of the
// search's starting reflector), so a candidate that sends less light, or none, cannot
// score better by shrinking the target with it (docs/optimization.md).
DesiredFarField desired_farfield(const vk::Context& ctx, const Scene& scene,
                                 double reference_flux_lm, Backend backend = Backend::Fast);

} // namespace fird
