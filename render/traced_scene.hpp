// One evaluation of a scene prepared for the views: the evaluator (which keeps the device
// height field the viewport draws), the far fields, sample ray paths from the very rayset
// the far field comes from, and a picked ray's walk. Shared by fird screenshot and the
// workbench.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "evaluation/evaluator.hpp"
#include "model/press_measures.hpp"
#include "views.hpp"

namespace fird::render {

struct TraceForViews {
    std::map<std::string, double> parameters; // reflector overrides
    std::optional<std::uint64_t> rays;        // traced for the far field (default: the scene's)
    // The trace whose rayset names the paths and the pick (default: `rays`): a preview
    // traced at fewer rays shows the full trace's rays, under the same indices.
    std::optional<std::uint64_t> rayset_rays;
    std::uint32_t paths = 300;
    std::optional<std::uint64_t> pick; // a ray (its rayset index) whose walk is recorded
    // A target reflector's far field traced before at these rays (a search's best views
    // reuse the first one's instead of tracing the unchanging target each time).
    std::optional<FarField> target_farfield;
};

struct TracedScene {
    Scene scene;                   // as traced for the far field
    std::uint64_t rayset_rays = 0; // the rayset the paths and picks are indices of
    std::unique_ptr<Evaluator> evaluator;
    FarFieldContent farfield;
    ViewportContent viewport;
    RayTally tally;
    // The reflector against the scene's [reflector.constraints] (none given: empty).
    std::vector<ConstraintCheck> constraints;
};

// Throws std::invalid_argument naming the parameter for a bad override, or the pick.
TracedScene trace_for_views(const vk::Context& ctx, const Scene& scene, const TraceForViews& o);

// The scene whose rayset the paths and picks index (the traced scene at rayset_rays).
Scene rayset_scene(const TracedScene& traced);

// Ray `index` of the traced scene's rayset re-traced alone through its reflector (one ray:
// no far field traced again); the tracer's scratch buffers change, the height field the
// views draw does not. Throws std::invalid_argument naming the index (picked_ray.hpp).
PickedRay pick_ray(const TracedScene& traced, std::uint64_t index);

} // namespace fird::render
