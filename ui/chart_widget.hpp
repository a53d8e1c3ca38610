// A plot::Chart drawn natively with Dear ImGui at the pixel size the panel gives it: text
// in the UI's font, as many ticks as fit without their labels touching, the legend a
// wrapping row above the data (never over it), the y label written above its axis, and a
// readout of the point under the mouse. The axes are compute/plot's (axis_limits,
// axis_ticks), so a chart reads the same here and in the PNGs.
#pragma once

#include <imgui.h>

#include "plot/chart.hpp"

namespace fird::ui {

// The chart into the next `size` pixels of the window: an item of its own that takes the
// mouse (a drag over it never moves the window), with a tooltip naming the point under the
// mouse (its series, x and y), or the axes' values there when no point is near.
void chart_widget(const char* id, const plot::Chart& chart, ImVec2 size);

} // namespace fird::ui
