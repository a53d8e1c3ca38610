#include <algorithm>
#include <cmath>
#include <exception>

#include "methods.hpp"

namespace fird {

namespace {

struct Wrapper {
    Objective* objective;
    const NloptRun* run;
    std::vector<std::size_t> free; // indices of the free parameters
    nlopt::opt* opt;
    std::optional<StopReason> stopped;
    std::exception_ptr error;
};

// NLopt's C code calls this; nothing may propagate through it, so the search's stop and
// any error are kept and NLopt is told to stop.
double call(unsigned n, const double* u, double* /*grad*/, void* data) {
    auto& w = *static_cast<Wrapper*>(data);
    const ParameterSpace& space = w.objective->space();
    std::vector<double> x = w.run->x0;
    for (unsigned k = 0; k < n; ++k) {
        const std::size_t i = w.free[k];
        x[i] = std::clamp(u[k], space.lo[i], space.hi[i]); // COBYLA may step outside
    }
    try {
        return (*w.objective)(x);
    } catch (const SearchStopped& s) {
        w.stopped = s.reason;
    } catch (...) {
        w.error = std::current_exception();
    }
    w.opt->force_stop();
    return HUGE_VAL;
}

} // namespace

StopReason run_nlopt(Objective& objective, const NloptRun& run) {
    const ParameterSpace& space = objective.space();
    Wrapper w{.objective = &objective, .run = &run};
    for (std::size_t i = 0; i < space.size(); ++i)
        if (run.free[i]) w.free.push_back(i);
    if (w.free.empty()) return StopReason::Converged;
    const unsigned n = unsigned(w.free.size());
    nlopt::opt opt(run.algorithm, n);
    w.opt = &opt;
    std::vector<double> lo, hi, x, step, xtol;
    for (std::size_t i : w.free) {
        lo.push_back(run.lo.empty() ? space.lo[i] : run.lo[i]);
        hi.push_back(run.hi.empty() ? space.hi[i] : run.hi[i]);
        x.push_back(std::clamp(run.x0[i], lo.back(), hi.back()));
        // BOBYQA's first trust region must fit the box twice over (NLopt refuses a larger
        // one): a coarse calibrated step on narrow bounds starts at half the span instead.
        step.push_back(std::min(run.initial_step[i], 0.49 * (hi.back() - lo.back())));
        xtol.push_back(run.xtol[i]);
    }
    opt.set_lower_bounds(lo);
    opt.set_upper_bounds(hi);
    opt.set_xtol_abs(xtol);
    if (run.algorithm == nlopt::LN_BOBYQA || run.algorithm == nlopt::LN_SBPLX ||
        run.algorithm == nlopt::LN_COBYLA)
        opt.set_initial_step(step);
    const std::uint64_t budget = run.max_evaluations
                                     ? std::min(run.max_evaluations, objective.remaining())
                                     : objective.remaining();
    // NLopt counts its own calls; the Objective enforces the search's limit exactly.
    opt.set_maxeval(int(std::min<std::uint64_t>(budget, 1u << 30)));
    opt.set_min_objective(call, &w);
    nlopt::srand(run.seed); // CRS2's random population: the same seed, the same search
    double best = 0.0;
    nlopt::result result = nlopt::FAILURE;
    try {
        result = opt.optimize(x, best);
    } catch (const nlopt::forced_stop&) {
    } catch (const nlopt::roundoff_limited&) {
        result = nlopt::ROUNDOFF_LIMITED;
    }
    if (w.error) std::rethrow_exception(w.error);
    if (w.stopped) throw SearchStopped{*w.stopped};
    // A run that used its whole budget did not converge (in `auto`, the next stage
    // takes over; alone, the search's limit was reached).
    return result == nlopt::MAXEVAL_REACHED ? StopReason::MaxEvaluations : StopReason::Converged;
}

} // namespace fird
