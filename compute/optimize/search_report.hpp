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
// One line on a population search: "cmaes of 14, 357 generations, heights sampled as the
// 6 x 6 grid's cosine modes" (the CLI's summary and the workbench's optimize panel).
std::string population_summary(const PopulationReport& population);
// One line on a Levenberg-Marquardt run (--method levenberg, auto's polish): its Jacobians,
// steps and model grids, and why it ended.
std::string levenberg_summary(const LevenbergReport& levenberg);

// Where the search began: {"kind", "parameters"} and, for a tailored start, what its making
// chose and took ("edge_ray", "rim_polar_deg", "source_share", "reaches_rim",
// "target_share_left_out", "clamped", "quick_metric", "refused", "time_s"). options.json
// records it so --resume starts from the same point; start_report_from_json reads it back.
nlohmann::json start_report_json(const StartReport& start);

// options.json of a search's --out folder, as it begins: its settings (method, rays,
// threshold_lm, max_evaluations, seed, refine, backend), the scene's text and where the
// scene was (scene_path: its files are found from there), and its start. What --resume
// continues from (the command adds what the result depends on) and fird follow reads.
nlohmann::json search_options_json(const SearchSettings& settings, const Scene& scene,
                                   const StartReport& start);
StartReport start_report_from_json(const nlohmann::json& j);

void write_progress_png(const std::string& path, const SearchResult& result);

// The progress picture's charts: every candidate's l2 by stage with each stage's best so
// far, and each parameter's path (its axis the parameter's box, so it reads from the first
// evaluation). progress.png draws them; the workbench draws the same charts at panel size.
struct ProgressCharts {
    plot::Chart l2;
    std::vector<plot::Chart> parameters;
};
ProgressCharts progress_charts(const SearchResult& result);

// A start other than the scene's, for a profile: z(r) of the scene's start, the search's
// start and the best along +x from the axis (profiles.png).
plot::Chart start_profiles_chart(const Scene& scene, const SearchResult& result);

// The scene with the best parameters, traceable as it is from any directory (file paths
// made absolute).
std::string best_scene_toml(const Scene& scene, const SearchResult& result);

// progress.png, best.toml, search.json, and (when the best was re-traced) the far-field,
// target and difference pictures, .npy files and farfield.ies / .ldt.
void write_search_outputs(const std::string& directory, const Scene& scene,
                          const SearchOutcome& outcome);

} // namespace fird
