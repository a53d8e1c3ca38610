// What a search leaves behind: its JSON object (DESIGN.md §5 keys for fird optimize), the
// progress picture (Figure 13's story: best l2 and each parameter's path against the
// evaluations), best.toml, and the best reflector's far-field pictures and files.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "optimize/search.hpp"
#include "plot/chart.hpp"

namespace fird {

nlohmann::json search_json(const SearchResult& result);

void write_progress_png(const std::string& path, const SearchResult& result);

// The progress picture's charts: every candidate's l2 by stage with each stage's best so
// far, and each parameter's path (its axis the parameter's box, so it reads from the first
// evaluation). progress.png draws them; the workbench draws the same charts at panel size.
struct ProgressCharts {
    plot::Chart l2;
    std::vector<plot::Chart> parameters;
};
ProgressCharts progress_charts(const SearchResult& result);

// The scene with the best parameters, traceable as it is from any directory (file paths
// made absolute).
std::string best_scene_toml(const Scene& scene, const SearchResult& result);

// progress.png, best.toml, search.json, and (when the best was re-traced) the far-field,
// target and difference pictures, .npy files and farfield.ies / .ldt.
void write_search_outputs(const std::string& directory, const Scene& scene,
                          const SearchOutcome& outcome);

} // namespace fird
