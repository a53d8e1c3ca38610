// What the workbench keeps between runs, in the user's config directory
// ($XDG_CONFIG_HOME/fird, else ~/.config/fird): the window size and the recent scenes
// (settings.txt), and Dear ImGui's panel layout (workbench.ini).
#pragma once

#include <string>
#include <vector>

namespace fird::ui {

struct Settings {
    int window_w = 1440, window_h = 900;
    std::vector<std::string> recent;
};

std::string config_directory(); // empty when neither variable is set
Settings load_settings();       // defaults where the file is missing or unreadable
void save_settings(const Settings& settings);

} // namespace fird::ui
