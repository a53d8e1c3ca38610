// What the workbench keeps between runs, in the user's config directory
// ($XDG_CONFIG_HOME/fird, else ~/.config/fird), in settings.txt: the window size, the
// panel layout's splits (clamped on load: no saved layout can put a panel off-screen) and
// the recent scenes (absolute; those no longer there are dropped on load), the runs folder.
#pragma once

#include <string>
#include <vector>

#include "layout.hpp"

namespace fird::ui {

struct Settings {
    int window_w = 1440, window_h = 900;
    Layout layout;
    std::string runs_dir; // where searches and calibrations write (empty: the default)
    std::vector<std::string> recent;
};

std::string config_directory(); // empty when neither variable is set
Settings load_settings();       // defaults where the file is missing or unreadable
void save_settings(const Settings& settings);

} // namespace fird::ui
