// Calibration before a search (the paper's §5.1): how many rays are enough (Table 1: the
// l2 of independent simulations of the desired reflector against rays), and the
// smallest step worth taking per parameter (the semivariogram of l2 along it, Figure 8, and
// the step a search resolves on common random numbers). Every prediction is that of the
// scene's sampler: the multinomial formula for independent rays, measured otherwise.
// Both evaluate through the seam (Evaluator): pipelines and buffers are made once per
// ray count, each run or point draws fresh rays.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "calibrate/semivariogram.hpp"
#include "model/scene.hpp"
#include "optimize/search_types.hpp"
#include "vk/context.hpp"

namespace fird {

// Two runs of a Table 1 row, 2k and 2k + 1 (or the last run alone): each one's l2 and, for
// a pair, the l2 between their two far fields (independent traces of one reflector: the
// replicate estimate of the noise).
struct RunPair {
    double first_l2_lm = 0.0;
    std::optional<double> second_l2_lm, between_l2_lm;
};
// Traces the pairs that begin at runs `first_runs` of the row of count index `c`.
using RunPairTracer =
    std::function<std::vector<RunPair>(std::size_t c, std::span<const std::uint32_t> first_runs)>;

// Traces a row's pairs across processes (fird calibrate rays under mpirun:
// compute/distributed): given them, the desired far field and `here`, which traces a share
// in this process; answers them in order, whichever process traced them. Empty: all here.
struct DistributedRuns {
    std::size_t processes = 1;
    std::function<std::vector<RunPair>(std::size_t c, std::span<const std::uint32_t> first_runs,
                                       const FarField& desired, const RunPairTracer& here)>
        trace;
};

struct RaysTableOptions {
    std::vector<std::uint64_t> counts{1000, 10000, 100000, 1000000, 10000000};
    std::uint32_t runs = 100;
    std::uint64_t desired_rays = 0; // the desired far field's (0: 10 x the largest count)
    std::uint64_t seed = 1;
    DistributedRuns distributed;
};

// The pairs beginning at `first_runs` of row `c`, traced with `evaluator` (at that row's
// fidelity, the desired far field set) as calibrate_rays traces them.
std::vector<RunPair> trace_run_pairs(Evaluator& evaluator, const Scene& scene,
                                     const RaysTableOptions& options, std::size_t c,
                                     std::span<const std::uint32_t> first_runs);

struct RaysRow {
    std::uint64_t rays = 0;
    std::uint32_t runs = 0;
    double mean_l2 = 0.0, var_l2 = 0.0;
    // The l2 Monte Carlo noise alone gives with the scene's sampler: multinomial_l2 for
    // the `random` sampler, replicate_l2 for any other (RaysTable::prediction says which).
    double predicted_l2 = 0.0;
    // Independent rays (multinomial cells, from the desired histogram):
    // flux sqrt(sum p (1 - p) (1/n + 1/N)). An upper bound for a stratified sampler.
    double multinomial_l2 = 0.0;
    // Measured: sqrt(V_n + V_N), V the mean squared l2 of a far field to its expectation,
    // each half the mean squared l2 between two independent traces of the same reflector
    // (the runs taken in pairs at n, two traces of the desired at N); NaN with one run.
    double replicate_l2 = 0.0;
    std::uint32_t replicate_pairs = 0; // pairs of runs behind replicate_l2
    double time_s = 0.0;               // all runs at this count
};

// Which prediction Table 1 shows: derived for independent rays, measured for the others.
enum class NoisePrediction { Multinomial, Replicate };
const char* noise_prediction_name(NoisePrediction p);

struct RaysTable {
    std::vector<RaysRow> rows;
    std::uint64_t desired_rays = 0;                // 0: a photometric target (no noise of its own)
    std::string desired;                           // what the desired far field is
    SamplerKind sampler = SamplerKind::Stratified; // the scene's: every trace uses it
    NoisePrediction prediction = NoisePrediction::Replicate; // behind predicted_l2
    double slope = 0.0; // of log mean l2 against log rays (-0.5: noise only)
    // What every l2 measures (the scene's [optimize] metric): the `_lm` columns of
    // calibration.csv are in its unit.
    FarFieldMetric metric = FarFieldMetric::L2;
    double time_s = 0.0;
};

// The prediction that fits a sampler: the multinomial formula holds for independent rays
// only; a stratified (or Sobol) sampler's noise is measured.
NoisePrediction noise_prediction_for(SamplerKind sampler);
// Its description in the outputs, e.g. "noise alone, stratified sampler: measured from
// replicate traces".
std::string noise_prediction_label(SamplerKind sampler);

// Called after each run: (count index, run index, its l2).
using RunCallback = std::function<void(std::size_t, std::uint32_t, double)>;

RaysTable calibrate_rays(const vk::Context& ctx, const Scene& scene,
                         const RaysTableOptions& options, const SearchControl* control = nullptr,
                         const RunCallback& on_run = {});

// Which step is written back: the smallest step a search resolves (two points a step
// apart ordered correctly 95 % of the time on common random numbers; the default, since
// on the paper's models the range is the width of the error's basin rather than the reach
// of its noise: docs/calibration.md), or the paper's lower bound (the range).
enum class StepRule { Resolvable, Range };
const char* step_rule_name(StepRule rule);

// One point of a semivariogram's series: the desired reflector with parameter `parameter`
// (of [reflector.optimize]) at `x`, traced with its own rays (`seed`).
struct SeriesPoint {
    std::string parameter;
    double x = 0.0;
    std::uint64_t seed = 0;
};
// Traces points of a series (each's l2 to the desired far field).
using SeriesTracer = std::function<std::vector<double>(std::span<const SeriesPoint>)>;
// Traces a series' points across processes (fird calibrate semivariogram under mpirun:
// compute/distributed), as DistributedRuns does a row's pairs. Empty: all here.
struct DistributedSeries {
    std::size_t processes = 1;
    std::function<std::vector<double>(std::span<const SeriesPoint>, const FarField& desired,
                                      const SeriesTracer& here)>
        trace;
};

// The points traced with `evaluator` (at the semivariogram's fidelity, the desired far field
// set) as calibrate_semivariogram traces them.
std::vector<double> trace_series_points(Evaluator& evaluator, const Scene& scene,
                                        std::span<const SeriesPoint> points);

struct SemivariogramOptions {
    std::vector<std::string> parameters; // empty: every parameter of [reflector.optimize]
    std::uint32_t points = 101;          // K regularly spaced values across the bounds
    std::uint64_t rays = 1000000;
    std::uint64_t seed = 1;
    // Raysets of the noise: the desired reflector traced with each (the fresh-ray noise),
    // and the resolvable step's common-random-number differences measured on each.
    std::uint32_t noise_runs = 8;
    StepRule step_rule = StepRule::Resolvable; // the step the result writes back
    // The series' points shared among processes; the noise replicates and the resolvable
    // step's probes stay in this one.
    DistributedSeries distributed;
};

struct ParameterSemivariogram {
    std::string parameter;
    std::vector<double> x, l2; // the series (l2 NaN where the value is infeasible)
    EmpiricalSemivariogram empirical;
    std::vector<VariogramFit> fits; // spherical, exponential, gaussian
    VariogramFit model;             // the best of them
    double recommended_step = 0.0;  // the paper's lower bound: the range
    std::optional<double> resolvable_step;
    // How the resolvable step was found: the lags probed around the desired reflector, each
    // with its signal and the spread of its common-random-number differences.
    std::vector<ResolutionProbe> resolution;
    double time_s = 0.0;
};

struct SemivariogramResult {
    std::vector<ParameterSemivariogram> parameters;
    std::uint64_t rays = 0;
    std::uint32_t points = 0;
    std::string desired;
    // Variance of l2 over noise_runs independent traces of the desired reflector at `rays`:
    // the fresh-ray noise of each point of the series, measured rather than fitted.
    double noise_variance_l2 = 0.0;
    std::uint32_t noise_runs = 0;
    StepRule step_rule = StepRule::Resolvable;
    FarFieldMetric metric = FarFieldMetric::L2; // as RaysTable::metric
    double time_s = 0.0;
};

// Called after each point: (parameter index, point index, its l2).
using PointCallback = std::function<void(std::size_t, std::uint32_t, double)>;

SemivariogramResult calibrate_semivariogram(const vk::Context& ctx, const Scene& scene,
                                            const SemivariogramOptions& options,
                                            const SearchControl* control = nullptr,
                                            const PointCallback& on_point = {});

// The reflector calibration measures around: the target reflector, or for a photometric
// target the scene's own.
ReflectorDesc desired_reflector(const Scene& scene);

// The step written back for a parameter: the resolvable step, or the range (never below
// the resolvable step); rounded up to two significant digits; 0 where there is none.
double calibrated_step(const ParameterSemivariogram& p, StepRule rule = StepRule::Resolvable);

// The scene with [reflector.optimize] steps set to the calibrated ones under the result's
// rule (scene_to_toml); a parameter without one keeps its step.
Scene scene_with_steps(const Scene& scene, const SemivariogramResult& result);

} // namespace fird
