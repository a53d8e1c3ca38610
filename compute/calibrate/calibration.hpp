// Calibration before a search (the paper's §5.1): how many rays are enough (Table 1: the
// l2 of independent simulations of the desired reflector against rays), and the
// smallest step worth taking per parameter (the semivariogram of l2 along it, Figure 8).
// Both evaluate through the seam (Evaluator): pipelines and buffers are made once per
// ray count, each run or point draws fresh rays.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibrate/semivariogram.hpp"
#include "model/scene.hpp"
#include "optimize/search_types.hpp"
#include "vk/context.hpp"

namespace fird {

struct RaysTableOptions {
    std::vector<std::uint64_t> counts{1000, 10000, 100000, 1000000, 10000000};
    std::uint32_t runs = 100;
    std::uint64_t desired_rays = 0; // the desired far field's (0: 10 x the largest count)
    std::uint64_t seed = 1;
};

struct RaysRow {
    std::uint64_t rays = 0;
    std::uint32_t runs = 0;
    double mean_l2 = 0.0, var_l2 = 0.0;
    double predicted_l2 = 0.0; // Monte Carlo noise alone, from the desired histogram
    double time_s = 0.0;       // all runs at this count
};

struct RaysTable {
    std::vector<RaysRow> rows;
    std::uint64_t desired_rays = 0; // 0: a photometric target (no noise of its own)
    std::string desired;            // what the desired far field is
    double slope = 0.0;             // of log mean l2 against log rays (-0.5: noise only)
    double time_s = 0.0;
};

// Called after each run: (count index, run index, its l2).
using RunCallback = std::function<void(std::size_t, std::uint32_t, double)>;

RaysTable calibrate_rays(const vk::Context& ctx, const Scene& scene,
                         const RaysTableOptions& options, const SearchControl* control = nullptr,
                         const RunCallback& on_run = {});

struct SemivariogramOptions {
    std::vector<std::string> parameters; // empty: every parameter of [reflector.optimize]
    std::uint32_t points = 101;          // K regularly spaced values across the bounds
    std::uint64_t rays = 1000000;
    std::uint64_t seed = 1;
    std::uint32_t noise_runs = 8; // independent traces of the desired reflector: the noise
};

struct ParameterSemivariogram {
    std::string parameter;
    std::vector<double> x, l2; // the series (l2 NaN where the value is infeasible)
    EmpiricalSemivariogram empirical;
    std::vector<VariogramFit> fits; // spherical, exponential, gaussian
    VariogramFit model;             // the best of them
    double recommended_step = 0.0;  // the paper's lower bound: the range
    std::optional<double> resolvable_step;
    double time_s = 0.0;
};

struct SemivariogramResult {
    std::vector<ParameterSemivariogram> parameters;
    std::uint64_t rays = 0;
    std::uint32_t points = 0;
    std::string desired;
    // Variance of l2 over noise_runs independent traces of the desired reflector at `rays`:
    // the noise a step's difference must stand above, measured rather than fitted.
    double noise_variance_l2 = 0.0;
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

// Which step is written back: the paper's lower bound (the range), or the smallest step
// that stands above the noise (where the range measures the width of the error's basin
// rather than the reach of its noise, as in docs/calibration.md).
enum class StepRule { Range, Resolvable };

// The step written back for a parameter: the range (never below the resolvable step), or
// the resolvable step; rounded up to two significant digits; 0 where there is none.
double calibrated_step(const ParameterSemivariogram& p, StepRule rule = StepRule::Range);

// The scene with [reflector.optimize] steps set to the calibrated ones (scene_to_toml); a
// parameter without one keeps its step.
Scene scene_with_steps(const Scene& scene, const SemivariogramResult& result,
                       StepRule rule = StepRule::Range);

} // namespace fird
