// The views drawn into textures the panels show: the viewport rendered on the device and
// read back, the far fields and plots drawn by cairo. Redrawn only when what they show,
// or their size, changed.
#pragma once

#include <cstdint>
#include <vector>

#include "viewport.hpp"
#include "views.hpp"
#include "workbench_state.hpp"
#include "worker.hpp"

namespace fird::ui {

// Replaces the texture's pixels (a new texture when the size changed).
void upload(const vk::Context& ctx, ViewTexture& t, const std::vector<std::uint8_t>& rgba,
            std::uint32_t width, std::uint32_t height, std::uint64_t generation);

// `picked`: the picked ray's path and walk (shown_pick), drawn up to the current step.
void update_viewport_image(const vk::Context& ctx, render::ViewportRenderer& renderer,
                           WorkbenchState& state, const SceneSnapshot& snapshot,
                           const PickedRay* picked, std::uint32_t width, std::uint32_t height);
// The far-field view the panel shows: the state's scale, zoom and maps, in `columns`.
render::FarFieldViewOptions farfield_view_options(const WorkbenchState& state,
                                                  const render::FarFieldContent& content,
                                                  int columns);
void update_farfield_image(const vk::Context& ctx, WorkbenchState& state,
                           const SceneSnapshot& snapshot,
                           const render::FarFieldViewOptions& options, std::uint32_t width,
                           std::uint32_t height);
// The altitude band the far-field view shows at the state's zoom.
std::pair<double, double> farfield_band(const WorkbenchState& state, const FarField& farfield);

} // namespace fird::ui
