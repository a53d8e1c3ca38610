// The search methods (fird optimize --method). Each drives an Objective; a method ends by
// returning why it stopped, or by letting the Objective's SearchStopped through.
#pragma once

#include <cstdint>
#include <vector>

#include <nlopt.hpp>

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
    std::uint64_t max_evaluations = 0; // this run's budget (0: as many as remain)
    std::uint64_t seed = 1;            // the stochastic methods' (CRS2) generator
};
StopReason run_nlopt(Objective& objective, const NloptRun& run);

// Compass search on the step lattice from x0 (snapped): poll every free parameter's two
// neighbours one step away (and, with `diagonal`, where none improves, every pair of
// parameters stepped together), move to the best that improves, stop when none does.
StopReason run_lattice_descent(Objective& objective, const std::vector<double>& x0,
                               const std::vector<bool>& free, bool diagonal);

// The multi-fidelity default (docs/optimization.md): few rays on a coarse far field for
// the early, coarse candidates, more as the search narrows, then the step lattice.
StopReason run_auto(Objective& objective, const std::vector<Fidelity>& stages);

} // namespace fird
