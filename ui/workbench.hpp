// The interactive workbench: a GLFW window whose Dear ImGui panels show what the
// compute floor produces, drawn on the same Vulkan device.
#pragma once

#include <cstdint>
#include <string>

namespace fird::ui {

struct WorkbenchOptions {
    std::string device_name;
    bool validation = false;
    // Stop after this many frames (0: run until the window closes); for smoke tests.
    std::uint32_t max_frames = 0;
};

// Runs the frame loop; returns the process exit code. Throws on a missing display.
int run_workbench(const WorkbenchOptions& options);

} // namespace fird::ui
