#include "script.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "folder_follow.hpp"
#include "io/parse_number.hpp"
#include "io/scene_file.hpp"

namespace fird::ui {

namespace {

// Each action's name and its argument counts (min, max).
const std::map<std::string, std::tuple<ScriptAction::Kind, int, int>>& actions() {
    using K = ScriptAction::Kind;
    static const std::map<std::string, std::tuple<K, int, int>> table = {
        {"open", {K::Open, 1, 1}},
        {"set", {K::Set, 2, 2}},
        {"source", {K::Source, 2, 2}},     // KEY VALUE: the scene panel's source editor
        {"material", {K::Material, 2, 2}}, // KEY VALUE: its material and direct light
        // map, polar, isocandela or illuminance [PLANE_M]: the far-field panel's view
        {"farfield", {K::FarFieldView, 1, 2}},
        {"trace", {K::Trace, 0, 0}},
        {"optimize", {K::Optimize, 0, 2}}, // [METHOD] [scene|tailored]: where it begins
        {"calibrate", {K::Calibrate, 1, 2}},
        {"tolerance", {K::Tolerance, 0, 2}}, // [KEY VALUE]: the tolerance form's field, or start
        {"stop", {K::Stop, 0, 0}},
        {"wait", {K::Wait, 1, 1}},
        {"wait-idle", {K::WaitIdle, 0, 0}},
        {"pick-ray", {K::PickRay, 1, 2}}, // X Y (a viewport pixel) or INDEX (in the rayset)
        {"drag", {K::Drag, 4, 5}},
        {"resize", {K::Resize, 2, 2}},
        {"screenshot", {K::Screenshot, 1, 1}},
        {"write-job", {K::WriteJob, 0, 1}}, // [RANKS]: the cluster form's "write job"
        {"follow", {K::Follow, 1, 1}},      // DIR: a search's folder (from the working directory)
        {"wait-follow", {K::WaitFollow, 0, 1}}, // [ROWS]: its end, or that many rows
        {"apply-best", {K::ApplyBest, 0, 0}},   // the followed search's best on the sliders
        // DIR [SHEET_MM [BEND_RADIUS_MM]]: the scene panel's CAD section, written and waited for
        {"export-cad", {K::ExportCad, 1, 3}},
        {"quit", {K::Quit, 0, 0}}};
    return table;
}

double number(const std::string& path, int line, const std::string& s) {
    const auto v = parse_finite_number(s);
    if (!v) throw std::invalid_argument(fmt::format("{}:{}: '{}' is not a number", path, line, s));
    return *v;
}

// The longest a wait-idle waits (frames at the frame loop's pace): a hung job fails the
// script instead of hanging it.
constexpr std::uint64_t kIdleFrameLimit = 200000;
// Frames a resize may take to reach the window (the X server answers within a few).
constexpr std::uint64_t kResizeFrameLimit = 600;
// A drag's moves: frames between the press and the release.
constexpr std::uint64_t kDragMoves = 10;

} // namespace

Script parse_script_text(const std::string& text, const std::string& path) {
    Script s{.path = path};
    std::istringstream in(text);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        if (const auto hash = line.find('#'); hash != std::string::npos) line.resize(hash);
        std::istringstream words(line);
        std::vector<std::string> w;
        for (std::string word; words >> word;)
            w.push_back(word);
        if (w.empty()) continue;
        const auto it = actions().find(w[0]);
        if (it == actions().end())
            throw std::invalid_argument(fmt::format("{}:{}: unknown action '{}'", path, n, w[0]));
        const auto [kind, lo, hi] = it->second;
        const int args = int(w.size()) - 1;
        if (args < lo || args > hi)
            throw std::invalid_argument(
                fmt::format("{}:{}: {} takes {} argument{}", path, n, w[0],
                            lo == hi ? std::to_string(lo) : fmt::format("{} to {}", lo, hi),
                            hi == 1 ? "" : "s"));
        ScriptAction a{kind, {w.begin() + 1, w.end()}, n};
        using K = ScriptAction::Kind;
        // The scene a script opens is found beside the script, as a scene's mesh is beside
        // the scene: the script runs the same from any working directory. Screenshots are
        // outputs and land where fird runs (as every command's --out), so a script kept
        // with its scenes need not be writable.
        if (kind == K::Open) a.args[0] = resolve_beside(path, a.args[0]);
        if (kind == K::Source && a.args[0] == "file") a.args[1] = resolve_beside(path, a.args[1]);
        if (kind == K::Set) (void)number(path, n, a.args[1]);
        if (kind == K::ExportCad)
            for (std::size_t k = 1; k < a.args.size(); ++k)
                (void)number(path, n, a.args[k]);
        if (kind == K::WaitFollow && !a.args.empty() && !(number(path, n, a.args[0]) >= 1))
            throw std::invalid_argument(
                fmt::format("{}:{}: wait-follow ROWS needs a row count >= 1", path, n));
        if (kind == K::WriteJob && !a.args.empty()) {
            const double ranks = number(path, n, a.args[0]);
            if (!(ranks >= 1 && ranks <= 1 << 20 && ranks == std::floor(ranks)))
                throw std::invalid_argument(
                    fmt::format("{}:{}: write-job RANKS needs a whole count >= 1", path, n));
        }
        if (kind == K::Wait && !(number(path, n, a.args[0]) >= 0))
            throw std::invalid_argument(
                fmt::format("{}:{}: wait needs a frame count >= 0", path, n));
        if (kind == K::PickRay && a.args.size() == 2)
            (void)number(path, n, a.args[0]), (void)number(path, n, a.args[1]);
        if (kind == K::PickRay && a.args.size() == 1) {
            const double index = number(path, n, a.args[0]);
            if (!(index >= 0 && index == std::floor(index) && index < 1.8e19))
                throw std::invalid_argument(
                    fmt::format("{}:{}: pick-ray INDEX needs a whole ray index >= 0", path, n));
        }
        if (kind == K::Drag) {
            for (std::size_t k = 0; k < 4; ++k)
                (void)number(path, n, a.args[k]);
            if (a.args.size() == 5 && a.args[4] != "left" && a.args[4] != "right")
                throw std::invalid_argument(fmt::format(
                    "{}:{}: drag's button is left or right, not '{}'", path, n, a.args[4]));
        }
        if (kind == K::FarFieldView) {
            if (a.args[0] != "map" && a.args[0] != "polar" && a.args[0] != "isocandela" &&
                a.args[0] != "illuminance")
                throw std::invalid_argument(fmt::format(
                    "{}:{}: farfield's view is map, polar, isocandela or illuminance, not '{}'",
                    path, n, a.args[0]));
            if (a.args.size() == 2 &&
                !(number(path, n, a.args[1]) >= 0.5 && number(path, n, a.args[1]) <= 20.0))
                throw std::invalid_argument(fmt::format(
                    "{}:{}: farfield illuminance's plane is 0.5 to 20 m away", path, n));
        }
        if (kind == K::Resize)
            for (std::size_t k = 0; k < 2; ++k) {
                const double v = number(path, n, a.args[k]);
                if (!(v >= 200 && v <= 16384 && v == std::floor(v)))
                    throw std::invalid_argument(fmt::format(
                        "{}:{}: resize needs whole pixel sizes from 200 to 16384", path, n));
            }
        if (kind == K::Optimize && a.args.size() == 2 && a.args[1] != "scene" &&
            a.args[1] != "tailored")
            throw std::invalid_argument(fmt::format(
                "{}:{}: optimize's start is scene or tailored, not '{}'", path, n, a.args[1]));
        if (kind == K::Optimize && !a.args.empty() && !method_from_name(a.args[0]))
            throw std::invalid_argument(fmt::format("{}:{}: unknown method '{}' (one of {})", path,
                                                    n, a.args[0], fmt::join(method_names(), ", ")));
        if (kind == K::Tolerance && a.args.size() == 1)
            throw std::invalid_argument(
                fmt::format("{}:{}: tolerance (start) or tolerance KEY VALUE", path, n));
        if (kind == K::Calibrate && a.args[0] != "rays" && a.args[0] != "semivariogram")
            throw std::invalid_argument(
                fmt::format("{}:{}: calibrate rays or calibrate semivariogram [NAME]", path, n));
        s.actions.push_back(std::move(a));
    }
    return s;
}

Script parse_script(const std::string& path) {
    if (std::filesystem::is_directory(path))
        throw std::invalid_argument(fmt::format("{}: is a directory, not a script", path));
    std::ifstream in(path);
    if (!in) throw std::invalid_argument(fmt::format("{}: cannot open the script", path));
    std::stringstream ss;
    ss << in.rdbuf();
    return parse_script_text(ss.str(), path);
}

void ScriptRunner::fail(const ScriptAction& a, const std::string& why) const {
    throw std::runtime_error(fmt::format("{}:{}: {}", script_.path, a.line, why));
}

bool ScriptRunner::drag(const ScriptAction& a, WorkbenchState& s) {
    // Frame 0 moves to the start, 1 presses, then kDragMoves moves, then the release;
    // the start is in viewport pixels (as pick-ray's), the moves add up to (DX, DY).
    const std::uint64_t k = waited_++;
    ScriptedMouse& m = s.scripted_mouse;
    // The start is fixed when the drag begins: what it drags (a splitter) may move the
    // viewport under it.
    if (k == 0)
        drag_from_ = {s.viewport_x + float(std::stod(a.args[0])),
                      s.viewport_y + float(std::stod(a.args[1]))};
    const auto [x, y] = drag_from_;
    const float dx = float(std::stod(a.args[2])), dy = float(std::stod(a.args[3]));
    const bool right = a.args.size() == 5 && a.args[4] == "right";
    if (k > kDragMoves + 2) {
        m = {};
        return false;
    }
    const float t = k < 2 ? 0.0f : float(std::min(k - 1, kDragMoves)) / float(kDragMoves);
    const bool down = k >= 1 && k <= kDragMoves + 1;
    m = {.active = true,
         .x = x + t * dx,
         .y = y + t * dy,
         .left = down && !right,
         .right = down && right};
    return true;
}

bool ScriptRunner::step(Frame& f, const ScriptHost& host) {
    using K = ScriptAction::Kind;
    WorkbenchState& s = f.state;
    while (!quit_ && next_ < script_.actions.size()) {
        const ScriptAction& a = script_.actions[next_];
        switch (a.kind) {
        case K::Wait:
            if (waited_++ < std::uint64_t(std::stod(a.args[0]))) return true;
            break;
        case K::WaitIdle:
            // Idle for two frames running: the snapshot it left is shown.
            if (f.worker.busy() || s.editor.dirty) {
                idle_frames_ = 0;
                if (++waited_ > kIdleFrameLimit) fail(a, "wait-idle: the work did not end");
                return true;
            }
            if (++idle_frames_ < 2) return true;
            break;
        case K::Open:
            if (!open_file(s, a.args[0])) fail(a, "open: " + s.editor.error);
            break;
        case K::Set: {
            if (!s.editor.scene) fail(a, "set: no scene is open");
            const auto it = s.editor.parameters.find(a.args[0]);
            if (it == s.editor.parameters.end())
                fail(a, "set: the reflector has no parameter " + a.args[0]);
            it->second = std::stod(a.args[1]);
            s.editor.dirty = true;
            break;
        }
        case K::Source:
            if (const std::string error = set_source_field(s, a.args[0], a.args[1]); !error.empty())
                fail(a, "source: " + error);
            break;
        case K::Material:
            if (const std::string error = set_material_field(s, a.args[0], a.args[1]);
                !error.empty())
                fail(a, "material: " + error);
            break;
        case K::FarFieldView:
            // As the panel's "view" combo (and its "plane" slider) set it.
            s.farfield.view = a.args[0] == "map"          ? 0
                              : a.args[0] == "polar"      ? 1
                              : a.args[0] == "isocandela" ? 2
                                                          : 3;
            if (a.args.size() == 2) s.farfield.plane_distance_m = std::stof(a.args[1]);
            break;
        case K::Trace:
            if (!s.editor.scene) fail(a, "trace: no scene is open");
            request_trace(f);
            break;
        case K::Optimize:
            s.tailored_start = a.args.size() == 2 && a.args[1] == "tailored";
            start_search(f, a.args.empty() ? SearchMethod::Auto : *method_from_name(a.args[0]));
            break;
        case K::Calibrate:
            start_calibration(f, a.args[0] == "rays", a.args.size() > 1 ? a.args[1] : "");
            break;
        case K::Tolerance:
            if (a.args.empty()) {
                if (!s.editor.scene) fail(a, "tolerance: no scene is open");
                s.calibration_kind = 2; // the panel shows the form and its results
                start_tolerance(f);
                if (!s.log.empty() && s.log.back().rfind("error:", 0) == 0)
                    fail(a, s.log.back().substr(7)); // "tolerance: KEY: why"
            } else if (const std::string error = set_tolerance_field(s, a.args[0], a.args[1]);
                       !error.empty()) {
                fail(a, "tolerance: " + error);
            }
            break;
        case K::Stop:
            f.worker.stop();
            break;
        case K::PickRay:
            if (a.args.size() == 1) {
                try {
                    pick_index(f, std::uint64_t(std::stod(a.args[0])));
                } catch (const std::exception& e) {
                    fail(a, std::string("pick-ray: ") + e.what());
                }
            } else if (!pick_at(f, float(std::stod(a.args[0])), float(std::stod(a.args[1])))) {
                fail(a, "pick-ray: no ray path near that viewport pixel");
            }
            break;
        case K::Drag:
            if (s.viewport_w <= 0) fail(a, "drag: the viewport shows nothing yet");
            if (drag(a, s)) return true;
            break;
        case K::Resize: {
            const int w = std::stoi(a.args[0]), h = std::stoi(a.args[1]);
            if (waited_ == 0) host.resize(w, h);
            if (int(s.display_w) != w || int(s.display_h) != h) {
                if (++waited_ > kResizeFrameLimit)
                    fail(a, fmt::format("resize: the window stayed {} x {}", int(s.display_w),
                                        int(s.display_h)));
                return true;
            }
            break;
        }
        case K::Screenshot:
            host.screenshot(a.args[0]);
            break;
        case K::WriteJob:
            if (!a.args.empty()) s.cluster.shape.ranks = std::uint32_t(std::stod(a.args[0]));
            if (!write_job(f))
                fail(a, "write-job: " + (s.log.empty() ? std::string() : s.log.back()));
            break;
        case K::Follow:
            follow_folder(s, a.args[0]);
            if (s.follow.dir.empty()) fail(a, "follow: " + s.follow.error);
            break;
        case K::WaitFollow: {
            if (s.follow.dir.empty()) fail(a, "wait-follow: no folder is followed");
            const std::size_t rows = s.follow.search ? s.follow.search->rows.candidates.size() : 0;
            const bool enough = !a.args.empty() && double(rows) >= std::stod(a.args[0]);
            if (!followed_search_ended(s.follow) && !enough) {
                if (++waited_ > kIdleFrameLimit)
                    fail(a, "wait-follow: the followed search did not end" +
                                (s.follow.error.empty() ? std::string() : ": " + s.follow.error));
                return true;
            }
            break;
        }
        case K::ApplyBest:
            try {
                apply_followed_best(s);
            } catch (const std::exception& e) {
                fail(a, std::string("apply-best: ") + e.what());
            }
            break;
        case K::ExportCad:
            if (waited_ == 0) {
                s.cad.dir = a.args[0];
                s.cad.thickness_mm = a.args.size() > 1 ? std::stod(a.args[1]) : 0.0;
                s.cad.bend_radius_mm = a.args.size() > 2 ? std::stod(a.args[2]) : 0.0;
                if (!start_cad_export(s)) fail(a, "export-cad: " + s.cad.error);
            }
            if (poll_cad_export(s)) {
                if (++waited_ > kIdleFrameLimit) fail(a, "export-cad: the export did not end");
                return true;
            }
            if (!s.cad.error.empty()) fail(a, "export-cad: " + s.cad.error);
            break;
        case K::Quit:
            quit_ = true;
            break;
        }
        waited_ = idle_frames_ = 0;
        ++next_;
    }
    return false;
}

} // namespace fird::ui
