// A search's --out folder read from outside, while the search runs or after it ended: what
// `fird follow` prints and what the workbench's optimize panel shows for a search started
// elsewhere (a job it wrote for a cluster, or any `fird optimize --out`). Read-only: the
// running search's files are never touched.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "model/scene.hpp"
#include "optimize/history_csv.hpp"
#include "optimize/search_types.hpp"

namespace fird {

// What search.json states once the search has ended.
struct SearchEnd {
    std::uint64_t evaluations = 0; // its history's rows
    std::string stopped;           // stop_reason_name
    double time_s = 0.0;
    std::optional<double> start_l2, final_l2, noise_floor_l2; // at the scene's rays
    std::optional<std::uint64_t> best_evaluation;
    std::map<std::string, double> best_parameters;
};

struct FollowedSearch {
    std::string dir;
    // How it began (options.json): its method, the scene it searches (as recorded, its
    // files found from where the scene was), the parameters and their boxes.
    std::string method;
    Scene scene;
    std::vector<std::string> names;
    std::vector<std::pair<double, double>> bounds;
    std::uint64_t max_evaluations = 0;
    // Its whole rows so far (history.csv) and, once it has ended, search.json's account.
    HistoryRows rows;
    std::optional<SearchEnd> end;
};

// Whether a search has begun in `dir` (its options.json is there): a job folder written
// for a cluster has none until the job starts.
bool search_began(const std::string& dir);

// Reads how the search in `dir` began, then its rows and end (refresh_search_folder).
// Throws std::runtime_error naming the file (and key or line) when `dir` holds no search
// or a file in it is not a search's.
FollowedSearch read_search_folder(const std::string& dir);
// Reads the rows written since and the end if it has come (the scene is not read again).
// search.json is its end only where it accounts for every row read: one left by an
// interrupted run that a resumed search continues (its rows beyond it) is not.
void refresh_search_folder(FollowedSearch& search);

// The search so far as a result: what progress.png and the workbench's charts draw from
// (method, parameters, history, stages; once it has ended, what search.json states of its
// stop, time, best and metric at the scene's rays).
SearchResult followed_result(const FollowedSearch& search);

// fird follow's --json and follow.json: {"dir", "scene", "method", "metric", "metric_unit",
// "parameters", "evaluations", "infeasible", "stages": [{"stage", "rays", "farfield",
// "evaluations", "infeasible", "best_l2"}], "best": {"evaluation", "stage", "l2", "score",
// "parameters"} or null, "ended", and once ended "stopped", "time_s", "start_l2",
// "final_l2", "noise_floor_l2", "best_parameters"}.
nlohmann::json followed_search_json(const FollowedSearch& search);

// The best feasible candidate of the latest stage that has one, by score (a search's own
// rule for its result: a later stage's metric is at more rays, not comparable with an
// earlier one's); null before there is one.
const Candidate* latest_stage_best(const std::vector<Candidate>& history);

} // namespace fird
