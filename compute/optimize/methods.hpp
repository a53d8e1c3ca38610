// The search methods (fird optimize --method). Each drives an Objective; a method ends by
// returning why it stopped, or by letting the Objective's SearchStopped through.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <nlopt.hpp>

#include "optimize/flat_directions.hpp"
#include "optimize/objective.hpp"

namespace fird {

// The paper's stepped search (§5): every lattice point in odometer order (the last
// parameter fastest, each from its min up by its step), infeasible ones skipped.
StopReason run_grid(Objective& objective);

// One NLopt run over the free parameters (the others held at x0's values).
struct NloptRun {
    nlopt::algorithm algorithm = nlopt::LN_BOBYQA;
    std::vector<double> x0;            // every parameter, in the space's order
    std::vector<bool> free;            // which ones the method moves
    std::vector<double> initial_step;  // per parameter (local methods)
    std::vector<double> xtol;          // per parameter
    std::vector<double> lo, hi;        // per parameter; empty: the space's box
    std::uint64_t max_evaluations = 0; // this run's budget (0: as many as remain)
    std::uint64_t seed = 1;            // the stochastic methods' (CRS2) generator
};
StopReason run_nlopt(Objective& objective, const NloptRun& run);

// The lattice points one step from `centre` inside the box, with up to `together` free
// parameters stepped at once: each free parameter's two neighbours, then (together >= 2)
// every pair stepped together, then (>= 3) every triple, in the order the compass search
// polls them.
std::vector<std::vector<double>> lattice_neighbours(const ParameterSpace& space,
                                                    const std::vector<double>& centre,
                                                    const std::vector<bool>& free,
                                                    std::size_t together);

// How many parameters auto's lattice search steps together at most, for this many free
// parameters (its neighbourhood: what the lattice verdict reports as polled or not).
std::size_t lattice_moves_together(std::size_t free_parameters);

// Compass search on the step lattice from x0 (snapped): poll every free parameter's two
// neighbours one step away, and where none improves, the steps of two parameters at once,
// then of three (up to `together`); move to the best that improves, stop when none does.
StopReason run_lattice_descent(Objective& objective, const std::vector<double>& x0,
                               const std::vector<bool>& free, std::size_t together);

// The confirm stage's noise (auto): its best's l2, the l2 between two traces of that best
// with independent rays at the stage's fidelity, and the most l2 noise alone explains.
struct ConfirmNoise {
    double l2_lm = 0.0;
    double noise_l2_lm = 0.0;
    double limit_lm = 0.0;
};

// The noise in a stage's l2 at x (whose l2 there is `l2_lm`): two traces of x at the
// current stage's fidelity, with its rays and with an independent stream.
ConfirmNoise stage_noise(Objective& objective, const std::vector<double>& x, double l2_lm);

// The multi-fidelity default (docs/optimization.md): few rays on a coarse far field for
// the early, coarse candidates, more as the search narrows, then the step lattice.
// `confirm` receives the confirm stage's noise once measured.
StopReason run_auto(Objective& objective, const std::vector<Fidelity>& stages,
                    std::optional<ConfirmNoise>& confirm);

// Below the step (--refine): BOBYQA within one step of the lattice point `centre` at the
// current stage's fidelity, the flat directions' parameters held.
StopReason run_sub_step(Objective& objective, const std::vector<double>& centre,
                        const std::vector<FlatDirection>& flat);

// The whole refine below the step, in the current stage (the lattice stage's fidelity and
// rays): run_sub_step from the lattice stage's best; where that ends above `noise`'s
// limit, again from the next lattice points of its neighbourhood (see
// method_sub_step.cpp), the stage's best over all of them kept. `lattice_stage` indexes
// the stage whose candidates the lattice verdict judged. `report` is filled as it goes
// (a search stopped inside it still says where it started).
void run_refine(Objective& objective, std::uint32_t lattice_stage, const ConfirmNoise& noise,
                const std::vector<FlatDirection>& flat, RefineReport& report);

// More free parameters than this and auto searches in runs of Levenberg-Marquardt and
// CMA-ES (run_auto_population) instead of DIRECT and the lattice: DIRECT's budget grows as
// 12 m (m + 1) and a lattice neighbourhood with pairs of steps as 2 m^2, both out of reach
// at tens of heights (docs/optimization.md).
constexpr std::size_t kPopulationAbove = 6;

// A population search's first spread, a fraction of each parameter's box: a quarter, as the
// NLopt methods' first step (CMA-ES wants the optimum within about two of them of the start).
constexpr double kPopulationSigma0 = 0.25;

// auto's runs at most beyond a handful of parameters, while the polished best is above the
// noise: Levenberg-Marquardt's and CMA-ES's, methods of two kinds (kCmaesFirstUpTo: which
// runs first).
constexpr std::uint32_t kPopulationRuns = 4;
// Of which Levenberg-Marquardt's beyond kCmaesFirstUpTo parameters (with coarse stages; one
// without), each with its own rays in the coarse stages: on the 36-height freeform, one to
// three such runs end within
// 1.07 x the noise floor for five search seeds of six (docs/optimization.md: 1400-2900
// candidates a run, 5-7 minutes beside other work here), where CMA-ES's runs end 1.15-1.8 x.
constexpr std::uint32_t kLevenbergRuns = 3;

// Up to this many free parameters auto's runs are CMA-ES's, each with the generator's next
// stream, and one Levenberg-Marquardt run last; beyond, kLevenbergRuns Levenberg-Marquardt
// runs first and CMA-ES's after. Measured (docs/optimization.md, the real-target table): at
// 8 and 16 heights, a profile's Levenberg-Marquardt run descends from the paraboloid into
// the box's floor, a near-flat bowl (the batwing's 16-height profile 38.6 cd, efficiency
// 0.28), where CMA-ES's spread finds a better basin on all four targets (32.6 cd, 0.47);
// after a CMA-ES run above the noise (the road luminaire's 8-height profile, 58.6 cd), a
// Levenberg-Marquardt run from the start ended at 57.8-60.9 cd in three tries, a second
// CMA-ES run at 55.1 and 57.8. At 36 and 100 heights CMA-ES's covariance, which needs on
// the order of n^2 generations, is still learning when its budget ends (the 36-height
// freeform 1.15-1.8 x the noise floor against Levenberg-Marquardt's 1.07 x; every bspline
// row of the real-target table).
constexpr std::size_t kCmaesFirstUpTo = 16;

// Beyond kCmaesFirstUpTo parameters, where the last Levenberg-Marquardt run's polish ends
// above the noise, long steps from the best polish of the runs: every parameter alone moved
// by 1, 2, 4 and 8 sixteenths of its box either way, traced together at the polish's
// fidelity; the best, where it beats the polished best, is polished again; up to this many
// rounds. The polish's model is local: on the 36-height freeform (search seed 2) every run
// ended 1.27 x the noise floor with a corner height 6.7 mm under the target's, and that
// height alone 4.7 mm higher, polished again, ended 1.18 x (docs/optimization.md).
constexpr std::uint32_t kLongStepRounds = 3;
constexpr double kLongStepsOfBox[] = {1.0 / 16, 2.0 / 16, 4.0 / 16, 8.0 / 16};

// pagmo2's CMA-ES or xNES (method_population.cpp), driven one generation at a time so that
// each generation is traced as one batch. The run's state (mean, covariance, step size,
// generator) lives between calls: auto continues one run through its stages.
class PopulationSearch {
  public:
    // From x0 (snapped to the lattice), a first spread of `sigma0` of each parameter's box.
    // `report` is kept up to date as generations complete. `run` picks the generator's
    // stream: 0 for a search's first run, 1, 2, ... for auto's restarts.
    PopulationSearch(Objective& objective, SearchMethod algorithm, const std::vector<double>& x0,
                     double sigma0, PopulationReport& report, std::uint32_t run = 0);
    ~PopulationSearch();
    PopulationSearch(const PopulationSearch&) = delete;
    PopulationSearch& operator=(const PopulationSearch&) = delete;
    // Generations in the objective's current stage until they converge (every parameter's
    // spread within a generation at most one step), or until `max_evaluations` candidates
    // of this stage (0: the search's budget alone). Throws SearchStopped.
    StopReason run_stage(std::uint64_t max_evaluations);

  private:
    struct State;
    std::unique_ptr<State> state_;
};

// In which order Levenberg-Marquardt frees a height grid's cosine modes: by degree (the
// piston and tilts first, the finest last) or all at once.
enum class ModeOrder { ByDegree, AllAtOnce };

// Levenberg-Marquardt on the far field from x0 (clamped into the box) at the current
// stage's fidelity (method_levenberg.cpp): a Jacobian of the far field by central
// differences of two lattice steps, on a coarser far field first, then the stage's; a
// freed height grid in its cosine modes, freed in `order`. Ends when no damped step gains
// or moves. Throws SearchStopped.
StopReason run_levenberg(Objective& objective, const std::vector<double>& x0,
                         LevenbergReport& report, ModeOrder order = ModeOrder::ByDegree);

// auto beyond kPopulationAbove free parameters: runs from the start, each with its own
// polish (Levenberg-Marquardt at the last stage's fidelity, a height grid's modes freed by
// degree), while the polished best is above what noise explains (stage_noise) and the budget
// holds another run, up to kPopulationRuns in all. A Levenberg-Marquardt run: a height grid's
// modes freed by degree, judged on the scene's far-field grid at the coarse stages' rays, a
// run after its first with the coarse stages' rays of other streams. A CMA-ES run: through
// the stages (few rays on a coarse far field first, the scene's last, each stage its own
// common random numbers), each with the generator's next stream. Up to kCmaesFirstUpTo
// parameters CMA-ES's runs first and one Levenberg-Marquardt run last; beyond, kLevenbergRuns
// Levenberg-Marquardt runs (one with a single stage) first, the last polish followed by long
// steps (kLongStepRounds) from the best of them, then CMA-ES's. With
// `retrace_start` the start is traced again first thing in the first polish (a tailored start,
// an answer in itself: the search then never ends above it at that fidelity, whatever the
// coarse stage's noise did).
StopReason run_auto_population(Objective& objective, const std::vector<Fidelity>& stages,
                               PopulationReport& report, LevenbergReport& polish,
                               bool retrace_start = false);

} // namespace fird
