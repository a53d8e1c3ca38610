// The multi-fidelity default. Stage k traces stages[k] (more rays, a finer far field as
// the search narrows; common random numbers within each stage):
//   explore  (first)            DIRECT over the whole box: global, because the l2
//                               landscape has several basins a few steps wide and is flat
//                               between them (local methods from the start stall in the
//                               nearest; DIRECT-L, locally biased, did too on Model A);
//   refine   (middle stages)    BOBYQA from the best so far, steps of two lattice steps;
//   lattice  (the last of those) the best snapped to the step lattice, moved along any
//                               flat direction to each lattice value of its held
//                               parameter, then a compass search on the lattice (pairs
//                               of parameters stepped together where single steps fail);
//   confirm  (last: the scene's rays and grid) the compass search again, from there, with
//                               pairs of steps as well unless its l2 is what noise alone
//                               leaves at this fidelity (measured: two traces of its best
//                               with independent rays).
// The continuous stages hold each flat direction's parameter fixed; the lattice stages
// move every parameter (a strict descent cannot wander along a flat direction).
#include <algorithm>
#include <cmath>

#include "methods.hpp"
#include "optimize/flat_directions.hpp"

namespace fird {

namespace {

std::vector<double> best_x(const Objective& f, const std::vector<double>& fallback) {
    const Candidate* b = f.stage_best();
    return b ? b->x : fallback;
}

// The lattice points where the continuous best's surface lies (moved along each flat
// direction to every lattice value of the held parameter), then snapped.
std::vector<std::vector<double>> lattice_entries(const Objective& f, const std::vector<double>& x,
                                                 const std::vector<FlatDirection>& flat) {
    const ParameterSpace& space = f.space();
    std::vector<std::vector<double>> entries{space.snap(x)};
    for (const FlatDirection& d : flat) {
        const auto held = std::find(space.names.begin(), space.names.end(), d.held);
        if (held == space.names.end()) continue;
        const std::size_t h = std::size_t(held - space.names.begin());
        std::map<std::string, double> p = f.scene().reflector.parameters;
        for (const auto& [k, v] : space.named(x))
            p[k] = v;
        for (std::uint64_t i = 0; i < space.lattice_counts()[h]; ++i) {
            const auto moved = move_along(d, f.scene().reflector.family, p,
                                          space.lo[h] + double(i) * space.step[h]);
            if (!moved) continue;
            std::vector<double> y(space.size());
            bool inside = true;
            for (std::size_t k = 0; k < space.size(); ++k) {
                y[k] = moved->at(space.names[k]);
                inside = inside && y[k] >= space.lo[k] - 0.5 * space.step[k] &&
                         y[k] <= space.hi[k] + 0.5 * space.step[k];
            }
            y = space.snap(y);
            if (inside && std::find(entries.begin(), entries.end(), y) == entries.end())
                entries.push_back(y);
        }
    }
    return entries;
}

} // namespace

StopReason run_auto(Objective& f, const std::vector<Fidelity>& stages,
                    std::optional<ConfirmNoise>& confirm) {
    const ParameterSpace& space = f.space();
    const std::size_t n = space.size();
    const auto flat = flat_directions(f.scene().reflector, space.names);
    std::vector<bool> continuous(n, true), all(n, true);
    const std::size_t together = lattice_moves_together(n);
    for (const FlatDirection& d : flat)
        for (std::size_t k = 0; k < n; ++k)
            if (space.names[k] == d.held) continuous[k] = false;

    std::vector<double> x = space.start;
    for (std::size_t s = 0; s + 1 < stages.size(); ++s) {
        f.begin_stage(s == 0 ? "explore" : "refine", stages[s]);
        NloptRun run{
            .algorithm = s == 0 ? nlopt::GN_DIRECT : nlopt::LN_BOBYQA, .x0 = x, .free = continuous};
        for (std::size_t k = 0; k < n; ++k) {
            run.initial_step.push_back(2.0 * space.step[k]);
            run.xtol.push_back(space.step[k] * (s == 0 ? 2.0 : 1.0));
        }
        const std::size_t m = std::size_t(std::count(continuous.begin(), continuous.end(), true));
        // Budgets measured on Models A, B and C (docs/optimization.md): DIRECT needs about
        // 12 m (m + 1) coarse candidates to visit every basin of m free parameters.
        run.max_evaluations = s == 0 ? 12 * m * (m + 1) : 10 * (m + 1);
        (void)run_nlopt(f, run);
        x = best_x(f, x);
    }
    if (stages.size() >= 2) {
        f.begin_stage("lattice", stages[stages.size() - 2]);
        std::vector<double> entry = space.snap(x);
        double entry_l2 = HUGE_VAL;
        const auto entries = lattice_entries(f, x, flat);
        const std::vector<double> l2s = f.evaluate_all(entries); // several per submission
        for (std::size_t k = 0; k < entries.size(); ++k)
            if (l2s[k] < entry_l2) entry = entries[k], entry_l2 = l2s[k];
        (void)run_lattice_descent(f, entry, all, together);
        x = best_x(f, entry);
    }
    f.begin_stage("confirm", stages.back());
    const StopReason single = run_lattice_descent(f, x, all, 1);
    // The scene's far field can tell apart what the lattice stage's coarser one could not
    // (a beam a step off focus lands in the same coarse cells): unless the confirmed l2 is
    // what noise alone leaves, its neighbourhood is polled again with pairs of steps too
    // (x and the single steps are answered from the stage's memo).
    const Candidate* confirmed = f.stage_best();
    if (!confirmed) return single;
    const std::vector<double> best = confirmed->x;
    const double best_l2 = confirmed->l2_lm;
    confirm = stage_noise(f, best, best_l2);
    // At the noise, pairs of steps cannot lower the l2; with a smoothness weight they may
    // still lower the score (a smoother shape at the same l2), so they are polled.
    if (best_l2 <= confirm->limit_lm && !(f.scene().optimize.smoothness > 0.0)) return single;
    return run_lattice_descent(f, best, all, together);
}

} // namespace fird
