// What the workbench's panels show and edit, as plain data (testable without a window):
// the scene and its parameter values, view options, the log, and the textures the views
// were last drawn into.
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "camera.hpp"
#include "export/cad_export.hpp"
#include "layout.hpp"
#include "model/scene.hpp"
#include "offscreen_target.hpp"
#include "optimize/cluster_job.hpp"
#include "optimize/search_folder.hpp"
#include "viewport.hpp"
#include "vk/image.hpp"
#include "vk/submission.hpp"

namespace fird::ui {

struct ToleranceView; // panel_tolerance.cpp

struct SceneEditor {
    std::string path;                         // the scene file
    std::optional<Scene> scene;               // as loaded
    std::map<std::string, double> parameters; // the sliders' values
    std::uint64_t preview_rays = 100000;      // the quick trace first
    std::uint64_t rays = 0;                   // then this many (0: the scene's)
    std::string error;                        // the last load error, shown in red
    bool dirty = false;                       // a parameter moved: re-trace
    std::string emitter_file;                 // the source editor's IES / LDT file, as typed
};

struct ViewportState {
    render::OrbitCamera camera;
    render::ViewportOptions options;
    // The picked ray: its index in the rayset (the same ray in the preview and the full
    // trace), the current step of its walk (clamped to the last), whether the steps before
    // the current one are drawn too, and the snapshot its one-ray trace was asked for.
    std::optional<std::uint64_t> picked_ray;
    std::uint64_t picked_rayset_rays = 0; // the rayset it is an index of
    std::size_t walk_step = 0;
    bool walk_trail = true;
    std::size_t walk_scrolled_to = 0; // the step the list last scrolled to
    std::optional<std::uint64_t> pick_asked_generation;
    bool camera_set = false; // framed on the holder once a scene is open
    bool frame_all = false;  // asked for: fit the holder, keeping the direction
    // The snapshot last shown, and the last one of the previous scene (not to frame on).
    std::optional<std::uint64_t> shown_generation, stale_generation;
};

struct FarFieldState {
    bool log_scale = false;
    float zoom = 1.0f; // 1: the lit band; larger: a narrower window on its brightest part
    int maps = 0;      // shown: 0 all, 1 desired, 2 obtained, 3 difference (one fills the panel)
    // 0 the equirectangular maps; 1 polar map, 2 isocandela, 3 illuminance (LuminaireView + 1)
    int view = 0;
    float plane_distance_m = 3.0f; // the illuminance plane's distance below the luminaire
};

// A redraw of a view in flight: recorded and submitted without waiting, shown once the
// device has finished it, so that a frame never waits behind the worker's compute for a
// picture (on a device with one queue, every submission queues behind the one before).
struct ViewRedraw {
    std::unique_ptr<vk::Texture> texture;  // drawn into
    std::unique_ptr<vk::Buffer> staging;   // pixels drawn on the host (the far field)
    std::uint64_t generation = 0, key = 0; // what it draws
    // Textures frames showed before: freed when this finishes (its first transition waits
    // on all work submitted before it, those frames included).
    std::vector<std::unique_ptr<vk::Texture>> retired;
    // What the device reads while it draws (the snapshot whose height field the viewport
    // renders): freed only after the submission has finished.
    std::shared_ptr<const void> reads;
    vk::Submission submission; // last: waited for before the rest is freed
};

// A view's picture: the texture frames show, what it was drawn from, and its redraw.
struct ViewTexture {
    std::unique_ptr<vk::Texture> texture;              // shown (none before the first redraw ends)
    std::uint64_t generation = ~0ull, key = 0;         // the snapshot and view options it shows
    std::unique_ptr<vk::Texture> spare;                // shown before: the next redraw's target
    std::vector<std::unique_ptr<vk::Texture>> retired; // to free with the next redraw
    std::unique_ptr<render::OffscreenTarget> target;   // the viewport's render target
    // The far field's picture being drawn on the host (a thread of its own), and what.
    std::future<std::vector<std::uint8_t>> drawing;
    std::uint64_t drawing_generation = 0, drawing_key = 0;
    std::uint32_t drawing_width = 0, drawing_height = 0;
    std::optional<ViewRedraw> redraw; // last: waited for before the rest is freed
};

// Mouse input a script plays (drag): applied to Dear ImGui's input before a frame, in
// place of the window's, so a scripted drag goes through the same widgets as a user's.
struct ScriptedMouse {
    bool active = false;
    float x = 0, y = 0;               // window pixels
    bool left = false, right = false; // buttons held
};

// What the workbench did with a search's result (so it is applied once, when it ends).
struct SearchFollow {
    std::string scene_path;              // the scene it searched (its results are that scene's)
    std::map<std::string, double> start; // the sliders when it started ("revert to start")
    // The source when it started: [source.optimize]'s values (its tilts are relative to
    // this orientation) are applied to it, never to the source shown.
    std::optional<SourceDesc> start_source;
    bool running = false;         // started and not yet seen to end
    std::uint64_t generation = 0; // the worker's search generation before it started
    double started_s = 0.0;       // ImGui time at its start (what the panel shows)
};

// A search followed from its folder (a job written for a cluster, or any fird optimize
// --out): read again on a thread of its own about every second until it has ended
// (folder_follow.hpp). The optimize panel shows it in place of the worker's search.
// One read of a followed folder (on a thread of its own).
struct FollowRead {
    std::shared_ptr<const FollowedSearch> search; // null while no search has begun there
    bool scene_toml = false;                      // a job folder's scene.toml is there
};

struct FolderFollow {
    std::string dir;                              // followed (empty: none), absolute
    std::string typed;                            // the panel's path field
    std::shared_ptr<const FollowedSearch> search; // as last read (null until its search begins)
    bool scene_toml = false;                      // as last read
    std::future<FollowRead> reading;              // the read in flight
    double next_read_s = 0.0;                     // ImGui time of the next read
    std::string error; // why the last read failed (shown; the reads go on)
    // Reads of folders no longer followed, still running: dropped once done (a frame never
    // waits for one).
    std::vector<std::future<FollowRead>> retired;
};

// The scene panel's CAD section: fird export --cad's options, the export being written
// (on a thread of its own) and what the last one wrote, or why not.
struct CadExportForm {
    std::string dir; // empty: a new run folder
    double tolerance_mm = 0.01, thickness_mm = 0.0, bend_radius_mm = 0.0;
    std::future<CadReport> writing;
    std::string writing_dir, written_dir;
    std::optional<CadReport> report;
    std::string error;
};

// The optimize panel's cluster form: the job's shape, and the job it wrote last.
struct ClusterForm {
    ClusterShape shape;
    std::optional<WrittenJob> written;
    bool reveal = false; // open the section next frame (a job written, a folder followed)
};

struct WorkbenchState {
    SceneEditor editor;
    ViewportState viewport;
    FarFieldState farfield;
    int method = 0; // index into method_names()
    // The optimize panel's start: the profile tailored to the target (fird optimize --start
    // tailored), else the scene's reflector.
    bool tailored_start = false;
    int calibration_kind = 0; // 0 rays, 1 semivariogram, 2 tolerance
    int calibration_parameter = 0;
    std::string calibration_scene; // the scene the last calibration was of
    // The calibrate panel's tolerance form: fird tolerance's options for the open scene,
    // filled from its [tolerance] table (or the defaults of panel_tolerance.cpp) when a
    // scene is opened, then as edited.
    struct ToleranceForm {
        ToleranceDesc tolerances;
        std::uint64_t seed = 1;    // as fird tolerance --seed
        std::string filled_from;   // the scene path the form was filled from
        std::string last_scene;    // the scene the last tolerance run was of
        ToleranceDesc filled_with; // the scene's [tolerance] when it was filled
        // What the panel shows of the worker's run, taken again only when it moved.
        std::shared_ptr<const ToleranceView> view;
    } tolerance_form;
    std::deque<std::string> log;
    std::vector<std::string> recent;             // recently opened scenes, newest first
    std::string runs_dir;                        // a search's or calibration's folders go under it
    Layout layout;                               // the splits, kept between runs
    std::array<PanelRect, kPanelCount> panels{}; // where the layout puts each panel
    std::array<PanelRect, kPanelCount> drawn{};  // where Dear ImGui drew it (--stats)
    float display_w = 0, display_h = 0;          // the window, last frame
    ScriptedMouse scripted_mouse;
    SearchFollow search;
    FolderFollow follow;
    ClusterForm cluster;
    CadExportForm cad;
    bool show_help = false;
    bool quit = false;
    // Texture contents as last drawn.
    ViewTexture viewport_image, farfield_image;
    // Views are redrawn while frames go on (shown when done); an offscreen picture of the
    // workbench waits for them instead, so that it shows the current state.
    bool wait_for_views = false;
    // Where the viewport image was drawn (screen pixels): a script's pick-ray uses it.
    float viewport_x = 0, viewport_y = 0, viewport_w = 0, viewport_h = 0;
};

void add_log(WorkbenchState& state, std::string line);
// Opens a scene: errors go to editor.error and the log (the window keeps running).
bool open_scene(WorkbenchState& state, const std::string& path);
// A dropped IES / LDT file becomes the open scene's photometric target.
bool set_photometric_target(WorkbenchState& state, const std::string& path);
// Which source a file makes: a ray file (.tm25ray, .ray, .npy, .csv) its rays, any other
// (an IES / LDT file) its distribution.
SourceKind file_source_kind(const std::string& path);
// A ray file becomes the open scene's source (a drop): false, logged, where it is refused.
bool set_ray_file_source(WorkbenchState& state, const std::string& path);
// Any route (path field, recent list, drop, command line): an IES / LDT file becomes the
// target, a ray file (.tm25ray, .ray, .npy, .csv) the source, anything else is opened as a
// scene.
bool open_file(WorkbenchState& state, const std::string& path);
// What the open scene's desired far field is, in words ("none" without a target).
std::string target_description(const Scene& scene);
// A new folder under runs_dir for a job ("optimize", "calibrate") on the open scene;
// empty (and the error logged) when it cannot be created.
std::string new_run_folder(WorkbenchState& state, const std::string& job);
// Replaces the open scene's source (the scene panel's source editor, the script's
// `source`): false, with editor.error naming the key, where a scene file could not hold it.
bool set_source(WorkbenchState& state, const SourceDesc& source);
// Replaces the reflector's finish and the direct-light choice the same way.
bool set_finish(WorkbenchState& state, const MaterialDesc& material, DirectLight direct);
// The scene with the sliders' values.
Scene edited_scene(const WorkbenchState& state);

} // namespace fird::ui
