// The views drawn into textures the panels show: the viewport rendered on the device
// straight into its texture, the far fields drawn by cairo on a thread of their own and
// uploaded. Redrawn only when what they show, or their size, changed; a redraw is
// submitted without waiting and shown when done (state.wait_for_views: at once).
#pragma once

#include <cstdint>
#include <vector>

#include "viewport.hpp"
#include "views.hpp"
#include "workbench_state.hpp"
#include "worker.hpp"

namespace fird::ui {

// `picked`: the picked ray's path and walk (shown_pick), drawn up to the current step.
void update_viewport_image(const vk::Context& ctx, render::ViewportRenderer& renderer,
                           WorkbenchState& state,
                           const std::shared_ptr<const SceneSnapshot>& snapshot,
                           const PickedRay* picked, std::uint32_t width, std::uint32_t height);
// The far-field view the panel shows: the state's scale, zoom and maps, in `columns`.
render::FarFieldViewOptions farfield_view_options(const WorkbenchState& state,
                                                  const SceneSnapshot& snapshot, int columns);
void update_farfield_image(const vk::Context& ctx, WorkbenchState& state,
                           const std::shared_ptr<const SceneSnapshot>& snapshot,
                           const render::FarFieldViewOptions& options, std::uint32_t width,
                           std::uint32_t height);
// The altitude band the far-field view shows at the state's zoom.
std::pair<double, double> farfield_band(const WorkbenchState& state,
                                        const plot::FarFieldProfiles& profiles);

} // namespace fird::ui
