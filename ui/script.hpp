// Scripted sessions (fird gui --script FILE): one action a line, '#' for comments. How
// the windowed tests drive the workbench, and how users record a reproducible session.
// An open's PATH is relative to the script's folder; a screenshot's to the working directory.
//   open PATH | set NAME VALUE | trace | optimize [METHOD [scene|tailored]] |
//   calibrate rays|semivariogram [NAME] | tolerance [KEY VALUE] | stop | wait FRAMES | wait-idle |
//   pick-ray X Y | pick-ray INDEX | drag X Y DX DY [left|right] | resize W H | screenshot PATH |
//   write-job [RANKS] | follow DIR | wait-follow [ROWS] | apply-best |
//   export-cad DIR [SHEET_MM [BEND_RADIUS_MM]] | quit
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "panels.hpp"

namespace fird::ui {

struct ScriptAction {
    enum class Kind {
        Open,
        Set,
        Source,
        Material,
        FarFieldView,
        Trace,
        Optimize,
        Calibrate,
        Tolerance,
        Stop,
        Wait,
        WaitIdle,
        PickRay,
        Drag,
        Resize,
        Screenshot,
        WriteJob,
        Follow,
        WaitFollow,
        ApplyBest,
        ExportCad,
        Quit
    } kind;
    std::vector<std::string> args;
    int line = 0;
};

struct Script {
    std::string path;
    std::vector<ScriptAction> actions;
};

// Throws std::invalid_argument "FILE:LINE: ..." for an unknown action or bad arguments.
Script parse_script(const std::string& path);
Script parse_script_text(const std::string& text, const std::string& path);

// What a script needs from the window it runs in.
struct ScriptHost {
    std::function<void(const std::string&)> screenshot; // capture the frame as PNG
    std::function<void(int, int)> resize;               // ask for this window size
};

class ScriptRunner {
  public:
    explicit ScriptRunner(Script script) : script_(std::move(script)) {}
    // Runs what is due this frame, through the host's window. Returns false
    // when the script is done (after quit, or its last action). Throws
    // std::runtime_error "FILE:LINE: ..." when an action fails.
    bool step(Frame& f, const ScriptHost& host);

  private:
    [[noreturn]] void fail(const ScriptAction& a, const std::string& why) const;
    Script script_;
    std::size_t next_ = 0;
    // Plays the drag action's mouse, one frame at a time; true while it goes on.
    bool drag(const ScriptAction& a, WorkbenchState& s);
    std::uint64_t idle_frames_ = 0, waited_ = 0;
    std::pair<float, float> drag_from_{0.0f, 0.0f}; // window pixels
    bool quit_ = false;
};

} // namespace fird::ui
