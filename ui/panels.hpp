// The workbench's panels, one file each (panel_*.cpp). Each reads and edits the plain
// state, asks the worker for work, and shows the textures of its views.
#pragma once

#include <memory>

#include "viewport.hpp"
#include "workbench_state.hpp"
#include "worker.hpp"

namespace fird::ui {

struct Frame {
    const vk::Context& ctx;
    Worker& worker;
    WorkbenchState& state;
    render::ViewportRenderer& renderer;
    std::shared_ptr<const SceneSnapshot> snapshot; // the latest traced state, if any
    std::shared_ptr<const PickOutcome> picked;     // the last ray traced alone, if any
};

// Asks the worker for a progressive trace of the edited scene (preview, then full).
void request_trace(Frame& f);

// Starts the Optimization panel's method on the edited scene (files in a new folder under the
// state's runs_dir).
void start_search(Frame& f, SearchMethod method);
// Starts a calibration: Table 1, or the semivariogram of a parameter (empty: all).
void start_calibration(Frame& f, bool rays_table, const std::string& parameter);

// Picks the sample path under viewport pixel (px, py); false when none is near.
bool pick_at(Frame& f, float px, float py);
// Picks ray `index` of the shown trace's rayset: its path and walk are traced alone (the
// worker's PickJob). Throws std::invalid_argument, one line, for an index past the rayset
// or a ray the holder discards; std::logic_error when nothing is traced yet.
void pick_index(Frame& f, std::uint64_t index);
// The picked ray's path and walk as traced through the shown snapshot's reflector, once
// they are there (nullptr before, or with nothing picked).
const PickedRay* shown_pick(const Frame& f);

// Begins the panel's window where the layout puts it this frame: fixed (its title bar
// neither moves nor resizes it), its content scrolling when it is below its minimum size.
void begin_panel(Frame& f, PanelId id);

void scene_panel(Frame& f);
// The scene panel's source editor (a collapsing section).
void source_section(WorkbenchState& state);
// The script's `source KEY VALUE` (KEY as in a scene's [source]; vectors as 0,0,-1): the
// empty string when the scene takes it, else why not.
std::string set_source_field(WorkbenchState& state, const std::string& key,
                             const std::string& value);
// The scene panel's finish editor: the reflector's material and the direct light.
void material_section(WorkbenchState& state);
// The script's `material KEY VALUE` (reflectance, spread_deg, lobe as in [reflector.material];
// direct as in [trace]): the empty string when the scene takes it, else why not.
std::string set_material_field(WorkbenchState& state, const std::string& key,
                               const std::string& value);
// The scene panel's CAD section (panel_cad.cpp).
void cad_section(WorkbenchState& state);
// Starts writing the shown reflector as CAD with the section's options (the script's
// export-cad): false, with the form's error, where it cannot start.
bool start_cad_export(WorkbenchState& state);
// Takes an export that has ended (logged, its report or error in the form); true while one
// is being written. Called every frame.
bool poll_cad_export(WorkbenchState& state);
void viewport_panel(Frame& f);
void farfield_panel(Frame& f);
void optimize_panel(Frame& f);
// The optimize panel's section for other machines: a job for the search shown (its folder's
// scene.toml, run.sh for mpirun, slurm.sh for sbatch) and a folder to follow.
void cluster_section(Frame& f);
// Writes the cluster form's job for the open scene and the panel's method into a new run
// folder, and follows it; false (logged) when it cannot.
bool write_job(Frame& f);
// The followed search's best on the sliders (the script's apply-best); throws
// std::runtime_error, one line, when there is none or the open scene is another.
void apply_followed_best(WorkbenchState& state);
void calibrate_panel(Frame& f);
// Starts the calibrate panel's tolerance form on the edited scene (fird tolerance's
// realisations; files in a new folder under the state's runs_dir).
void start_tolerance(Frame& f);
// Whether the form's tolerances can be drawn for the open scene (the Start button).
bool tolerance_can_start(WorkbenchState& state);
// The calibrate panel's tolerance form and results.
void tolerance_section(Frame& f);
// The script's `tolerance KEY VALUE` (KEY as in a scene's [tolerance], or seed; a shift as
// 0.1 or 0.1,0.1,0.2): the empty string when the form takes it, else why not.
std::string set_tolerance_field(WorkbenchState& state, const std::string& key,
                                const std::string& value);
void log_panel(Frame& f);
void help_panel(Frame& f);

// The menu bar, every panel tiled on the display, the splitters, the keyboard shortcuts.
void build_frame(Frame& f);

} // namespace fird::ui
