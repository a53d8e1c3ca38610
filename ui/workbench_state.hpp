// What the workbench's panels show and edit, as plain data (testable without a window):
// the scene and its parameter values, view options, the log, and the textures the views
// were last drawn into.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera.hpp"
#include "model/scene.hpp"
#include "viewport.hpp"
#include "vk/image.hpp"

namespace fird::ui {

struct SceneEditor {
    std::string path;                         // the scene file
    std::optional<Scene> scene;               // as loaded
    std::map<std::string, double> parameters; // the sliders' values
    std::uint64_t preview_rays = 100000;      // the quick trace first
    std::uint64_t rays = 0;                   // then this many (0: the scene's)
    std::string error;                        // the last load error, shown in red
    bool dirty = false;                       // a parameter moved: re-trace
};

struct ViewportState {
    render::OrbitCamera camera;
    render::ViewportOptions options;
    std::optional<std::size_t> picked_path;
    std::size_t walk_step = 0; // steps of the picked ray's walk shown
    bool camera_set = false;   // framed on the holder once a scene is open
};

struct FarFieldState {
    bool log_scale = false;
    float zoom = 1.0f; // 1: the lit band; larger: a narrower band about its centre
};

// A texture with the generation of the content it shows (redrawn when that changes).
struct ViewTexture {
    std::unique_ptr<vk::Texture> texture;
    std::uint64_t generation = ~0ull;
    std::uint32_t width = 0, height = 0;
};

struct WorkbenchState {
    SceneEditor editor;
    ViewportState viewport;
    FarFieldState farfield;
    int method = 0;           // index into method_names()
    int calibration_kind = 0; // 0 rays, 1 semivariogram
    int calibration_parameter = 0;
    std::deque<std::string> log;
    std::vector<std::string> recent; // recently opened scenes, newest first
    bool show_help = false;
    bool quit = false;
    // Texture contents as last drawn.
    ViewTexture viewport_image, farfield_image, search_plot, calibration_plot;
    std::uint64_t drawn_camera_hash = 0;
    // Where the viewport image was drawn (screen pixels): a script's pick-ray uses it.
    float viewport_x = 0, viewport_y = 0, viewport_w = 0, viewport_h = 0;
};

void add_log(WorkbenchState& state, std::string line);
// Opens a scene: errors go to editor.error and the log (the window keeps running).
bool open_scene(WorkbenchState& state, const std::string& path);
// A dropped IES / LDT file becomes the open scene's photometric target.
bool set_photometric_target(WorkbenchState& state, const std::string& path);
// The scene with the sliders' values.
Scene edited_scene(const WorkbenchState& state);

} // namespace fird::ui
