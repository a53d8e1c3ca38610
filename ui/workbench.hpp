// The interactive workbench: a GLFW window whose Dear ImGui panels show what the compute
// floor produces, drawn on the same Vulkan device, compute running beside the frames.
// The same frame also renders with no window (fird screenshot --view workbench).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fird::ui {

struct WorkbenchOptions {
    std::string device_name;
    bool validation = false;
    std::uint64_t max_batch_rays = 0; // rays per submission; 0: the workbench's bound
    std::string scene;                // opened at start (empty: none)
    std::string script;               // a scripted session (empty: none)
    // Stop after this many frames (0: run until the window closes); for smoke tests.
    std::uint32_t max_frames = 0;
    bool stats = false; // print frame-time statistics as JSON at exit
    // Both > 0: no window; the frames are drawn into an image of this size on the frames'
    // queue, the session starts from the default settings and saves none.
    std::uint32_t offscreen_w = 0, offscreen_h = 0;
};

// Runs the frame loop; returns the process exit code. Throws on a missing display (with a
// window).
int run_workbench(const WorkbenchOptions& options);

// The whole workbench frame for a scene, traced (full rays) and drawn offscreen:
// RGBA rows, top first. No window, no display.
std::vector<std::uint8_t> render_workbench_offscreen(const std::string& device_name,
                                                     bool validation, const std::string& scene,
                                                     std::uint32_t width, std::uint32_t height,
                                                     std::uint64_t* validation_errors);

} // namespace fird::ui
