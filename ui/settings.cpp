#include "settings.hpp"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fird::ui {

std::string config_directory() {
    namespace fs = std::filesystem;
    if (const char* x = std::getenv("XDG_CONFIG_HOME"); x && *x)
        return (fs::path(x) / "fird").string();
    if (const char* h = std::getenv("HOME"); h && *h)
        return (fs::path(h) / ".config" / "fird").string();
    return {};
}

Settings load_settings() {
    Settings s;
    const std::string dir = config_directory();
    if (dir.empty()) return s;
    std::ifstream in(std::filesystem::path(dir) / "settings.txt");
    for (std::string line; std::getline(in, line);) {
        const auto eq = line.find('=');
        if (eq == std::string::npos) continue;
        const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
        try {
            if (key == "window_w") s.window_w = std::clamp(std::stoi(value), 320, 16384);
            if (key == "window_h") s.window_h = std::clamp(std::stoi(value), 240, 16384);
            if (key == "layout_left") s.layout.left = std::stod(value);
            if (key == "layout_right") s.layout.right = std::stod(value);
            if (key == "layout_row") s.layout.row = std::stod(value);
        } catch (const std::exception&) {
        } // a damaged line keeps its default
        // Only absolute paths that still exist: a relative one depended on the folder the
        // workbench ran from, a dead one would fail when picked.
        std::error_code ec;
        if (key == "recent" && s.recent.size() < 10 && std::filesystem::path(value).is_absolute() &&
            std::filesystem::is_regular_file(value, ec))
            s.recent.push_back(value);
        if (key == "runs_dir") s.runs_dir = value;
    }
    s.layout = clamped(s.layout);
    return s;
}

void save_settings(const Settings& s) {
    const std::string dir = config_directory();
    if (dir.empty()) return;
    try {
        create_output_directory(dir);
        std::string text = "window_w=" + std::to_string(s.window_w) +
                           "\nwindow_h=" + std::to_string(s.window_h) + "\n";
        text += fmt::format("layout_left={}\nlayout_right={}\nlayout_row={}\n", s.layout.left,
                            s.layout.right, s.layout.row);
        if (!s.runs_dir.empty()) text += "runs_dir=" + s.runs_dir + "\n";
        for (const std::string& r : s.recent)
            text += "recent=" + r + "\n";
        write_text_file((std::filesystem::path(dir) / "settings.txt").string(), text);
    } catch (const std::exception&) {
        // Settings are a convenience: an unwritable config directory is not an error.
    }
}

} // namespace fird::ui
