// Where the workbench writes a search's or a calibration's files: a new folder per run
// under the user's data directory ($XDG_DATA_HOME/fird/runs, else
// ~/.local/share/fird/runs), named after the scene and the job, never one that exists.
#pragma once

#include <string>

namespace fird::ui {

// The folder runs go under (empty when neither variable is set: then the working
// directory's fird_runs/).
std::string runs_directory();

// Creates and returns a folder `base/STEM-JOB-N` with the first N (from 1) not taken:
// creation is the test, so two runs (or two workbenches) never share a folder. Throws
// std::runtime_error naming the folder when it cannot be created.
std::string new_run_directory(const std::string& base, const std::string& stem,
                              const std::string& job);

} // namespace fird::ui
