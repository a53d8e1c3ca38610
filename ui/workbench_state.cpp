#include "workbench_state.hpp"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>

#include "io/scene_file.hpp"
#include "photometry/photometry_file.hpp"

namespace fird::ui {

void add_log(WorkbenchState& s, std::string line) {
    s.log.push_back(std::move(line));
    while (s.log.size() > 500)
        s.log.pop_front();
}

bool open_scene(WorkbenchState& s, const std::string& path) {
    try {
        Scene scene = load_scene(path);
        s.editor.parameters = scene.reflector.parameters;
        s.editor.scene = std::move(scene);
        s.editor.path = path;
        s.editor.error.clear();
        s.editor.dirty = true;
        s.viewport.camera_set = false;
        s.viewport.stale_generation = s.viewport.shown_generation;
        s.viewport.picked_path.reset();
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
    s.editor.dirty = true;
    add_log(s, "target: " + path);
    return true;
}

Scene edited_scene(const WorkbenchState& s) {
    Scene scene = *s.editor.scene;
    for (const auto& [k, v] : s.editor.parameters)
        scene.reflector.parameters[k] = v;
    return scene;
}

} // namespace fird::ui
