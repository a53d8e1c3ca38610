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
#include "views.hpp"

namespace fird::render {

struct TraceForViews {
    std::map<std::string, double> parameters; // reflector overrides
    std::optional<std::uint64_t> rays;
    std::uint32_t paths = 300;
    std::optional<std::size_t> pick; // a path whose walk is recorded
};

struct TracedScene {
    Scene scene;
    std::unique_ptr<Evaluator> evaluator;
    FarFieldContent farfield;
    ViewportContent viewport;
    RayTally tally;
};

// Throws std::invalid_argument naming the parameter for a bad override, or the pick.
TracedScene trace_for_views(const vk::Context& ctx, const Scene& scene, const TraceForViews& o);

} // namespace fird::render
