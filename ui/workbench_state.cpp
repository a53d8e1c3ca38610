#include "workbench_state.hpp"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "io/scene_file.hpp"
#include "panels.hpp"
#include "photometry/photometry_file.hpp"
#include "run_directory.hpp"

namespace fird::ui {

void add_log(WorkbenchState& s, std::string line) {
    s.log.push_back(std::move(line));
    while (s.log.size() > 500)
        s.log.pop_front();
}

bool open_scene(WorkbenchState& s, const std::string& given) {
    // Kept absolute: the recent list must work from any working directory.
    const std::string path = std::filesystem::absolute(given).lexically_normal().string();
    try {
        Scene scene = load_scene(path);
        s.editor.parameters = scene.reflector.parameters;
        // A free control height (a bspline's or a profile's h_<k>, a point group) needs no
        // value in the scene: its slider starts at the height itself, so the surface shown
        // is the file's (a row, column or ring group keeps its heights until moved).
        const BSplineDesc& grid = scene.reflector.bspline;
        for (const auto& [name, range] : scene.reflector.optimize)
            if (const auto g = grid.groups.find(name);
                g != grid.groups.end() && g->second.kind == ControlGroup::Kind::Point)
                s.editor.parameters.emplace(
                    name, grid.heights_mm[std::size_t(g->second.j) * grid.nx + g->second.i]);
        s.editor.scene = std::move(scene);
        s.editor.path = path;
        s.editor.error.clear();
        s.editor.dirty = true;
        s.viewport.camera_set = false;
        s.viewport.stale_generation = s.viewport.shown_generation;
        s.viewport.picked_ray.reset();
        std::erase(s.recent, path);
        s.recent.insert(s.recent.begin(), path);
        if (s.recent.size() > 10) s.recent.resize(10);
        add_log(s, "opened " + path);
        return true;
    } catch (const std::exception& e) {
        s.editor.error = e.what();
        add_log(s, std::string("error: ") + e.what());
        return false;
    }
}

bool set_source(WorkbenchState& s, const SourceDesc& source) {
    if (!s.editor.scene) return false;
    // Checked as a scene file is (every key's rule, the footprint, the clearance from the
    // reflector): the edited scene written out and read back.
    Scene edited = edited_scene(s);
    edited.source = source;
    try {
        const Scene checked = parse_scene(scene_to_toml(edited), s.editor.path);
        s.editor.scene->source = checked.source;
        s.editor.error.clear();
        add_log(s, fmt::format("source: {}{} at [{}, {}, {}] mm, {:.4g} lm",
                               source_type_name(checked.source.kind),
                               checked.source.file.empty() ? "" : " " + checked.source.file,
                               checked.source.center_mm.x, checked.source.center_mm.y,
                               checked.source.center_mm.z, checked.source.flux_lm));
        s.editor.dirty = true;
        s.viewport.picked_ray.reset(); // a ray of the old source's rayset
        return true;
    } catch (const std::exception& e) {
        // The reason from its key on: the line is of the scene as written out, not the file.
        const std::string what = e.what();
        const auto key = what.find("[source]");
        s.editor.error = key == std::string::npos ? what : what.substr(key);
        return false;
    }
}

SourceKind file_source_kind(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".tm25ray" || ext == ".ray" || ext == ".npy" || ext == ".csv"
               ? SourceKind::RayFile
               : SourceKind::Photometric;
}

bool set_ray_file_source(WorkbenchState& s, const std::string& path) {
    if (!s.editor.scene) {
        add_log(s, "error: " + path + ": open a scene first, then drop a ray file on it");
        return false;
    }
    s.editor.emitter_file = path;
    // Through the Source panel's own edit (its file's flux, checked as a scene file is).
    if (const std::string error = set_source_field(s, "file", path); !error.empty()) {
        add_log(s, "error: " + error);
        return false;
    }
    return true;
}

bool set_finish(WorkbenchState& s, const MaterialDesc& material, DirectLight direct) {
    if (!s.editor.scene) return false;
    Scene edited = edited_scene(s);
    edited.reflector.material = material;
    edited.trace.direct = direct;
    try {
        const Scene checked = parse_scene(scene_to_toml(edited), s.editor.path);
        s.editor.scene->reflector.material = checked.reflector.material;
        s.editor.scene->trace.direct = checked.trace.direct;
        s.editor.error.clear();
        const MaterialDesc& m = checked.reflector.material;
        add_log(s,
                fmt::format("material: reflectance {:.3g}, {} lobe of {:.3g} deg; direct light "
                            "{}",
                            m.reflectance, m.lobe == SpreadLobe::Phong ? "phong" : "gaussian",
                            m.spread_deg,
                            checked.trace.direct == DirectLight::Include ? "binned" : "left out"));
        s.editor.dirty = true;
        return true;
    } catch (const std::exception& e) {
        // The reason from its key on (the line is of the scene as written out).
        const std::string what = e.what();
        std::size_t key = what.find("[reflector.material]");
        if (key == std::string::npos) key = what.find("[trace]");
        s.editor.error = key == std::string::npos ? what : what.substr(key);
        return false;
    }
}

bool set_photometric_target(WorkbenchState& s, const std::string& path) {
    if (!s.editor.scene) {
        add_log(s, "error: " + path + ": open a scene first, then drop a luminaire file on it");
        return false;
    }
    try {
        (void)read_photometry(path); // refuse a broken file before it becomes the target
    } catch (const std::exception& e) {
        s.editor.error = e.what();
        add_log(s, std::string("error: ") + e.what());
        return false;
    }
    TargetDesc& t = s.editor.scene->target;
    t = TargetDesc{.kind = TargetDesc::Kind::Photometric,
                   .file = std::filesystem::absolute(path).string(),
                   .resolved_path = std::filesystem::absolute(path).string()};
    s.editor.error.clear();
    s.editor.dirty = true;
    add_log(s, "target: " + path);
    return true;
}

std::string new_run_folder(WorkbenchState& s, const std::string& job) {
    try {
        const std::string stem = std::filesystem::path(s.editor.path).stem().string();
        return new_run_directory(s.runs_dir.empty() ? runs_directory() : s.runs_dir,
                                 stem.empty() ? "scene" : stem, job);
    } catch (const std::exception& e) {
        add_log(s, std::string("error: ") + e.what());
        return {};
    }
}

bool open_file(WorkbenchState& s, const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".ies" || ext == ".ldt") return set_photometric_target(s, path);
    if (file_source_kind(path) == SourceKind::RayFile) return set_ray_file_source(s, path);
    return open_scene(s, path);
}

std::string target_description(const Scene& scene) {
    const TargetDesc& t = scene.target;
    switch (t.kind) {
    case TargetDesc::Kind::None:
        return "none";
    case TargetDesc::Kind::Photometric:
        return std::filesystem::path(t.file).filename().string() +
               (t.absolute ? " (its own flux)" : " (scaled to the source's flux)");
    case TargetDesc::Kind::Reflector:
        break;
    }
    std::string text = "the reflector with";
    for (const auto& [name, value] : t.parameters)
        text += fmt::format(" {} = {:g}", name, value);
    return text;
}

Scene edited_scene(const WorkbenchState& s) {
    Scene scene = *s.editor.scene;
    for (const auto& [k, v] : s.editor.parameters)
        scene.reflector.parameters[k] = v;
    return scene;
}

} // namespace fird::ui
