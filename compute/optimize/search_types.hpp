// Plain data of a reflector search: its settings, its candidates and its result, shared
// by the methods, the history file, the reports and the workbench.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "evaluation/evaluator.hpp"
#include "model/scene.hpp"
#include "optimize/flat_directions.hpp"
#include "optimize/press_constraints.hpp"
#include "photometry/beam_metrics.hpp"

namespace fird {

enum class StopReason { None, Threshold, Converged, MaxEvaluations, Exhausted, Interrupted };
const char* stop_reason_name(StopReason reason);

// A batch of one stage's points to trace (Objective::evaluate_all's), handed to
// DistributedTrace. `trace_here` traces a share of them in this process, as the search
// would alone (the stage's evaluator, optimize/point_trace.hpp).
struct StageBatch {
    const Fidelity& fidelity;
    const FarField& desired; // on the scene's grid; the same for the whole search
    std::span<const std::vector<double>> points;
    std::function<std::vector<CandidateResult>(std::span<const std::vector<double>>)> trace_here;
};

// Traces a stage's batches across processes (fird optimize under mpirun:
// compute/distributed). `trace` answers each point's l2_lm, farfield_lm and wall_ms, in the
// points' order, whichever process traced it. Empty: every point is traced here.
struct DistributedTrace {
    std::size_t processes = 1; // evaluate_all hands over a device batch per process
    std::function<std::vector<CandidateResult>(const StageBatch&)> trace;
};

// The scene's [optimize] with the command line's overrides applied.
struct SearchSettings {
    SearchMethod method = SearchMethod::Auto;
    std::vector<std::uint64_t> rays; // per stage (see OptimizeSettings::rays); never empty
    double threshold_lm = 0.0;
    std::uint64_t max_evaluations = 100000;
    std::uint64_t seed = 1; // the search's rays derive from it (one stream per stage)
    // Below the step: after a lattice method (auto, grid), BOBYQA within one step of the
    // best lattice point at the last stage's fidelity (fird optimize --refine).
    bool refine = false;
    // The tracer every candidate, the final evaluation and the noise floor go through (fird
    // optimize --backend): the fast path, or the CPU reference (a search judged wholly
    // by another tracer, at the reference's speed).
    Backend backend = Backend::Fast;
    // Where batches of candidates are traced: here, or across the ranks of an MPI job.
    DistributedTrace distributed;
};

// The scene's [optimize] resolved against its [trace] (the defaults filled in).
SearchSettings search_settings(const Scene& scene);

// Stops (or pauses) a running search from another thread or a signal handler.
struct SearchControl {
    std::atomic<bool> stop{false};
    std::atomic<bool> pause{false};
    // A line the signal handler writes at once when asked to stop, and sets noted: under
    // mpirun a rank's death brings SIGTERM and then, within milliseconds, SIGKILL, too soon
    // for the search to say why it ends (set while rank 0 waits on other ranks).
    std::atomic<const char*> stop_note{nullptr};
    std::atomic<bool> noted{false};
};

struct Candidate {
    std::uint64_t index = 0;
    std::uint32_t stage = 0;
    std::vector<double> x; // every optimized parameter, in the space's order
    bool feasible = true;
    double l2_lm = 0.0; // NaN when infeasible (never traced)
    // Its bending energy with an [optimize] smoothness weight (else 0), NaN when infeasible.
    double smoothness = 0.0;
    // What the search minimises: l2_lm + the weight x smoothness (l2_lm without a weight);
    // NaN until the objective sets it, so an unscored candidate is never a best.
    double score = std::numeric_limits<double>::quiet_NaN();
    double ms = 0.0;       // wall time of its evaluation
    bool replayed = false; // read from the history of a resumed search, not traced
    // A population search's generation (from 1; its start, traced alone, has none), for the
    // progress chart; not in history.csv.
    std::optional<std::uint32_t> generation;
};

// l2_lm + smoothness x the weight of `optimize`; l2_lm itself without a weight (to the bit).
inline double candidate_score(double l2_lm, double smoothness, const OptimizeSettings& optimize) {
    return optimize.smoothness > 0.0 ? l2_lm + optimize.smoothness * smoothness : l2_lm;
}

struct StageSummary {
    std::string name;
    Fidelity fidelity;
    std::uint64_t evaluations = 0;
    std::uint64_t infeasible = 0;
    std::optional<std::uint64_t> best; // index of its best feasible candidate (by score)
    double best_l2_lm = 0.0;
    double best_score = 0.0;
    double traced_ms = 0.0; // wall time of its traced (not replayed) candidates
    std::uint64_t traced = 0;
};

// Whether the search ended on the best lattice point of its neighbourhood: the lattice
// points one step away from the lattice stage's best, alone or two parameters at once
// (inside the box), looked up among that stage's candidates (same rays, so compared
// without noise between them).
struct LatticeCheck {
    std::vector<double> x;        // the lattice stage's best
    std::string stage;            // the stage it was judged in
    std::uint64_t neighbours = 0; // inside the box
    std::uint64_t polled = 0;     // traced in that stage
    std::uint64_t better = 0;     // polled and lower l2 than x (a search that moved on)
    std::vector<std::vector<double>> not_polled;
    // `auto`'s confirm stage: its best's l2, the l2 between two independent traces of it at
    // that stage's fidelity, and the largest l2 that noise alone explains (pairs of steps are
    // skipped only at or below it).
    std::optional<double> confirm_l2_lm, confirm_noise_l2_lm, confirm_noise_limit_lm;
    std::string verdict; // one line: the best lattice point, or why it cannot be said
};

// The refine below the step (--refine): where it started, and why it started again.
struct RefineReport {
    // The lattice points its BOBYQA runs began at: first the lattice's best, then the
    // neighbours it started again from (see method_sub_step.cpp).
    std::vector<std::vector<double>> starts;
    // Its noise: the l2 between two independent traces of the lattice's best at the
    // refine's fidelity and the most l2 noise alone explains (auto's confirm stage's).
    double noise_l2_lm = 0.0;
    double noise_limit_lm = 0.0;
    std::string verdict; // one line: ended at the noise, or started again from where
};

// A population search (--method cmaes or xnes, or auto's choice beyond a handful of
// parameters): pagmo2's algorithm, a generation traced as one batch.
struct PopulationReport {
    std::string algorithm;         // "cmaes" or "xnes"
    std::uint64_t size = 0;        // candidates per generation
    std::uint64_t generations = 0; // completed
    double sigma0 = 0.0;           // the first generation's spread, a fraction of each box
    std::uint32_t seed = 0;        // pagmo's generator, derived from the search's seed
    std::vector<double> spread;    // the last generation's range per parameter, in steps
    // The heights sampled as a grid's cosine modes (height_modes.hpp): how many, and the
    // grid ("6 x 6"); 0 and "" where each parameter is sampled as it is.
    std::size_t modes = 0;
    std::string modes_grid;
    std::string verdict; // one line: why it ended
    // auto's runs: Levenberg-Marquardt from the start (again with other coarse rays), then
    // CMA-ES with the generator's next stream: what each found before and after its
    // polish, and the l2 noise alone explains there.
    struct Run {
        std::string method;            // "levenberg" or "cmaes"
        std::uint32_t seed = 0;        // CMA-ES's generator (0 for levenberg)
        std::uint64_t generations = 0; // CMA-ES's
        std::uint64_t candidates = 0;  // of its stages, the polish's included
        double before_polish = 0.0;    // its best at the last stage's fidelity before the polish
        double polished = 0.0;         // the best after the polish
        double noise_limit = 0.0;      // stage_noise's limit at the polished best
        std::uint32_t long_steps = 0;  // long steps that gained, each polished again
    };
    std::vector<Run> runs;
};

// Levenberg-Marquardt on the far field (--method levenberg, or auto's polish after a
// population search; method_levenberg.cpp).
struct LevenbergReport {
    std::size_t modes = 0;        // coordinates that are a height grid's modes (0: none)
    std::size_t degree = 0;       // the finest mode degree (kx + ky) freed
    std::uint64_t iterations = 0; // damped steps tried (each a batch of damping values)
    std::uint64_t jacobians = 0;  // Jacobians traced (2 candidates per free coordinate each)
    std::vector<std::string> model_grids; // the far-field grids its model used, "90x45", ...
    std::string verdict;                  // one line: why it ended
};

// Where a search began (fird optimize --start): the scene's reflector, or the profile
// tailored to the desired far field (optimize/search_start.hpp) and what its making chose.
struct StartReport {
    std::string kind = "scene";               // "scene" or "tailored"
    std::map<std::string, double> parameters; // the start's optimized parameters
    // Tailored: the edge ray kept, the source angle (from the nadir) meeting the rim, the
    // share of the source's flux within that cone, and whether the curve reached the rim.
    std::string edge_ray;
    double rim_polar_deg = 0.0;
    double source_share = 0.0;
    bool reaches_rim = true;
    double target_share_left_out = 0.0; // the target's share below the horizon, not mapped
    std::vector<std::string> clamped;   // heights the tailoring put outside their bounds
    // Each edge ray tried: its metric on the quick trace, or why it has no answer.
    std::map<std::string, double> quick_metric;
    // With an [optimize] smoothness weight, what chose between them: the metric plus the
    // weight x the profile's bending energy (the search's own score); empty without one.
    std::map<std::string, double> quick_score;
    std::map<std::string, std::string> refused;
    // Tailored: the wall time of its making (the desired far field, the source's polar
    // distribution, the solves and their quick traces), before the search's own time_s.
    double time_s = 0.0;
};

struct SearchResult {
    std::string method;
    std::string backend; // "gpu" (the fast path) or "cpu" (the reference), backend_name()
    std::vector<std::string> names; // the optimized parameters
    // Each parameter's box ([reflector.optimize] min, max), in the names' order.
    std::vector<std::pair<double, double>> bounds;
    std::vector<Candidate> history;
    std::vector<StageSummary> stages;
    std::uint64_t infeasible = 0;
    // The best candidate of the last stage that has one (auto beyond a handful of
    // parameters: of the stages at that one's very fidelity, its runs' polishes).
    std::optional<std::uint64_t> best;
    std::map<std::string, double> best_parameters;
    double best_l2_lm = 0.0;
    std::optional<double> start_l2_lm; // the start (StartReport), scene fidelity
    StartReport start;
    std::optional<double> final_l2_lm;       // the best, fresh rays, scene fidelity
    std::optional<double> noise_floor_l2_lm; // two independent traces of the best
    std::optional<double> surface_rms_mm;    // best against a target reflector, over the holder
    // [optimize] smoothness: its weight, and the bending energy (press_measures.hpp) of the
    // scene's reflector and of the best, as the search measured it; unset without a weight.
    double smoothness_weight = 0.0;
    std::optional<double> start_bending_energy, best_bending_energy;
    double best_score = 0.0; // what the search minimised at the best (best_l2_lm without a weight)
    std::string metric = "l2"; // what every l2 above measures (farfield.hpp)
    std::string metric_unit = "lm";
    // The best's far field (fresh rays) and the desired one as a data sheet states them.
    std::optional<Photometrics> photometrics, desired_photometrics;
    std::vector<FlatDirection> flat_directions;
    std::optional<LatticeCheck> lattice;          // lattice methods (auto, grid)
    std::optional<RefineReport> refine;           // --refine
    std::optional<PopulationReport> population;   // cmaes, xnes (and auto beyond a handful)
    std::optional<LevenbergReport> levenberg;     // levenberg (and auto's polish after cmaes)
    std::vector<ConstraintAtOptimum> constraints; // [reflector.constraints] at the best
    std::string desired;                          // what the desired far field is
    StopReason stopped = StopReason::None;
    double time_s = 0.0;
    std::uint64_t grid_size = 0; // the lattice's size (the grid method's work)
};

// Called after every candidate (traced or replayed), with the stage it belongs to.
using CandidateCallback = std::function<void(const Candidate&, const StageSummary&)>;

} // namespace fird
