// Plain data of a reflector search: its settings, its candidates and its result, shared
// by the methods, the history file, the reports and the workbench.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "evaluation/evaluator.hpp"
#include "model/scene.hpp"
#include "optimize/flat_directions.hpp"

namespace fird {

enum class StopReason { None, Threshold, Converged, MaxEvaluations, Exhausted, Interrupted };
const char* stop_reason_name(StopReason reason);

// The scene's [optimize] with the command line's overrides applied.
struct SearchSettings {
    SearchMethod method = SearchMethod::Auto;
    std::vector<std::uint64_t> rays; // per stage (see OptimizeSettings::rays); never empty
    double threshold_lm = 0.0;
    std::uint64_t max_evaluations = 100000;
    std::uint64_t seed = 1; // the search's rays derive from it (one stream per stage)
};

// The scene's [optimize] resolved against its [trace] (the defaults filled in).
SearchSettings search_settings(const Scene& scene);

// Stops (or pauses) a running search from another thread or a signal handler.
struct SearchControl {
    std::atomic<bool> stop{false};
    std::atomic<bool> pause{false};
};

struct Candidate {
    std::uint64_t index = 0;
    std::uint32_t stage = 0;
    std::vector<double> x; // every optimized parameter, in the space's order
    bool feasible = true;
    double l2_lm = 0.0;    // NaN when infeasible (never traced)
    double ms = 0.0;       // wall time of its evaluation
    bool replayed = false; // read from the history of a resumed search, not traced
};

struct StageSummary {
    std::string name;
    Fidelity fidelity;
    std::uint64_t evaluations = 0;
    std::uint64_t infeasible = 0;
    std::optional<std::uint64_t> best; // index of its best feasible candidate
    double best_l2_lm = 0.0;
    double traced_ms = 0.0; // wall time of its traced (not replayed) candidates
    std::uint64_t traced = 0;
};

struct SearchResult {
    std::string method;
    std::vector<std::string> names; // the optimized parameters
    std::vector<Candidate> history;
    std::vector<StageSummary> stages;
    std::uint64_t infeasible = 0;
    std::optional<std::uint64_t> best; // the best candidate of the last stage that has one
    std::map<std::string, double> best_parameters;
    double best_l2_lm = 0.0;
    std::optional<double> start_l2_lm;       // the scene's reflector, scene fidelity
    std::optional<double> final_l2_lm;       // the best, fresh rays, scene fidelity
    std::optional<double> noise_floor_l2_lm; // two independent traces of the best
    std::optional<double> surface_rms_mm;    // best against a target reflector, over the holder
    std::vector<FlatDirection> flat_directions;
    std::string desired; // what the desired far field is
    StopReason stopped = StopReason::None;
    double time_s = 0.0;
    std::uint64_t grid_size = 0; // the lattice's size (the grid method's work)
};

// Called after every candidate (traced or replayed), with the stage it belongs to.
using CandidateCallback = std::function<void(const Candidate&, const StageSummary&)>;

} // namespace fird
