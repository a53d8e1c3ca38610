// Below the step (fird optimize --refine): the lattice's answer is a lattice point, and a
// target between lattice points is at best half a step away from it in every parameter.
// BOBYQA from that point, inside one step of it (the lattice search compared every point
// one step away, so the optimum it missed lies within the box they span), at the same
// rays as the lattice stage (common random numbers: the start scores exactly as it did).
#include <algorithm>

#include "methods.hpp"

namespace fird {

StopReason run_sub_step(Objective& f, const std::vector<double>& centre,
                        const std::vector<FlatDirection>& flat) {
    const ParameterSpace& space = f.space();
    const std::size_t n = space.size();
    NloptRun run{.algorithm = nlopt::LN_BOBYQA, .x0 = centre, .free = std::vector<bool>(n, true)};
    for (std::size_t k = 0; k < n; ++k) {
        // A flat direction's parameter stays: moving it leaves the surface unchanged.
        for (const FlatDirection& d : flat)
            if (d.held == space.names[k]) run.free[k] = false;
        run.lo.push_back(std::max(space.lo[k], centre[k] - space.step[k]));
        run.hi.push_back(std::min(space.hi[k], centre[k] + space.step[k]));
        run.initial_step.push_back(0.5 * space.step[k]);
        // A twentieth of a step: finer than the parameters are worth (the height field's
        // texels and the noise blur the l2 below that), coarse enough to stop.
        run.xtol.push_back(space.step[k] / 20.0);
    }
    const std::size_t m = std::size_t(std::count(run.free.begin(), run.free.end(), true));
    // BOBYQA's model needs 2m + 1 points before its first step; the rest is the same
    // budget as auto's continuous refine stages per parameter.
    run.max_evaluations = 2 * m + 1 + 10 * (m + 1);
    return run_nlopt(f, run);
}

} // namespace fird
