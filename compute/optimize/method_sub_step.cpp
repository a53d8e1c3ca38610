// Below the step (fird optimize --refine): the lattice's answer is a lattice point, and a
// target between lattice points is at best half a step away from it in every parameter.
// BOBYQA from that point, inside one step of it (the lattice search compared every point
// one step away, so a minimum near it lies within the box they span), at the same rays as
// the lattice stage (common random numbers: the start scores exactly as it did).
//
// Where correlated parameters trade against each other (the paraboloid's focus against
// its vertex), the l2 has a flat valley across several lattice cells, and the lattice's
// best may sit in one cell of it while the minimum lies in the next: the refine from the
// best then stops above the noise (Model A's off-lattice target: 1.10 x the noise floor,
// 0.77 mm RMS off, where the refine from the second-best lattice point reaches 1.01 x).
// So when the first refine ends above what noise alone leaves, it starts again from the
// neighbours that the lattice told apart from its best by less than that best misses
// a perfect fit: those whose l2 exceeds the best's by less than the best's exceeds the
// noise limit. Order (lowest l2 first) and the stage's common rays keep the comparison
// free of noise between the runs; it stops as soon as one ends at the noise.
#include <algorithm>
#include <map>

#include <fmt/format.h>

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

void run_refine(Objective& f, std::uint32_t lattice_stage, const ConfirmNoise& noise,
                const std::vector<FlatDirection>& flat, RefineReport& report) {
    const ParameterSpace& space = f.space();
    const StageSummary& judged = f.stages().at(lattice_stage);
    if (!judged.best) return;
    const Candidate best = f.history()[*judged.best];
    report.noise_l2_lm = noise.noise_l2_lm;
    report.noise_limit_lm = noise.limit_lm;
    report.starts = {best.x};
    (void)run_sub_step(f, best.x, flat);
    const double first_l2 = f.stage_best() ? f.stage_best()->l2_lm : best.l2_lm;
    // The verdicts name the search's metric and its unit.
    const char* l2 = metric_name(f.scene().optimize.metric);
    const char* lm = metric_unit(f.scene().optimize.metric);
    // At the noise the l2 has nothing left to gain; with a smoothness weight the score may
    // (a smoother shape at the same l2), so the neighbours are still tried.
    if (first_l2 <= noise.limit_lm && !(f.scene().optimize.smoothness > 0.0)) {
        report.verdict = fmt::format("the refine from the lattice's best ended at {0} {2:.6g} {1}, "
                                     "what noise alone leaves (limit {3:.6g} {1})",
                                     l2, lm, first_l2, noise.limit_lm);
        return;
    }
    // The lattice's best misses a perfect fit by `excess` (l2 above the noise limit);
    // a neighbour closer to it than that was not told apart from it by the lattice.
    const double excess = best.l2_lm - noise.limit_lm;
    std::map<std::vector<double>, double> traced;
    for (const Candidate& c : f.history())
        if (c.stage == lattice_stage && c.feasible) traced[c.x] = c.score;
    std::vector<std::pair<double, std::vector<double>>> near;
    for (const auto& y : lattice_neighbours(space, best.x, std::vector<bool>(space.size(), true),
                                            lattice_moves_together(space.size()))) {
        const auto it = traced.find(y);
        if (it != traced.end() && it->second - best.score < excess)
            near.emplace_back(it->second, y);
    }
    std::stable_sort(near.begin(), near.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    // At most one further start per parameter: the refine then costs at most m + 1 times
    // the single one, however poorly the lattice's best fits.
    if (near.size() > space.size()) near.resize(space.size());
    std::size_t best_start = 0;
    double best_l2 = first_l2;
    double best_score = f.stage_best() ? f.stage_best()->score : best.score;
    for (const auto& [score, y] : near) {
        report.starts.push_back(y);
        (void)run_sub_step(f, y, flat);
        if (f.stage_best() && f.stage_best()->score < best_score) {
            best_score = f.stage_best()->score;
            best_l2 = f.stage_best()->l2_lm;
            best_start = report.starts.size() - 1;
        }
        if (best_l2 <= noise.limit_lm && !(f.scene().optimize.smoothness > 0.0)) break;
    }
    if (near.empty())
        report.verdict = fmt::format(
            "the refine from the lattice's best ended at {0} {2:.6g} {1}, above what noise alone "
            "leaves (limit {3:.6g} {1}); no neighbour's {0} lies within {4:.6g} {1} (the best's "
            "excess over the limit) of the best's, so it was not started again",
            l2, lm, first_l2, noise.limit_lm, excess);
    else
        report.verdict = fmt::format(
            "the refine from the lattice's best ended at {0} {2:.6g} {1}, above what noise alone "
            "leaves (limit {3:.6g} {1}); started again from {4} neighbour(s) whose {0} lies within "
            "{5:.6g} {1} (the best's excess over the limit) of the best's: the lowest, {0} {6:.6g} "
            "{1}, from {7}",
            l2, lm, first_l2, noise.limit_lm, report.starts.size() - 1, excess, best_l2,
            space.text(report.starts[best_start]));
}

} // namespace fird
