// Population search on pagmo2 (2.18): its CMA-ES (Hansen) and xNES (Glasmachers et al.),
// not written here, through FIRD's module libfird_pagmo.so (pagmo_generations.hpp), loaded
// the first time a population search runs. Each generation is traced as one batch through
// Objective::evaluate_all, with the stage's rays (common random numbers within the stage).
//
// pagmo 2.18's cmaes and xnes take no batch evaluator (pagmo::bfe: only gaco, maco, nsga2,
// nspso and pso_gen do); they ask the problem for one fitness after another inside
// evolve(). So each generation runs twice: first on copies of the algorithm and the
// population (the same generator state, the same memory), with a problem that only notes
// the points asked for; those points are traced together; then the algorithm itself evolves
// the generation, asking for the same points (its sampling does not depend on the values it
// is given until the generation is complete), now answered from the stage's memo. The
// algorithms keep their state between calls (memory = true, one generation per evolve), so
// a search stopped between generations and resumed replays to the very same state.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <set>

#include <fmt/format.h>

#include "io/program_files.hpp"
#include "methods.hpp"
#include "optimize/height_modes.hpp"
#include "optimize/pagmo_generations.hpp"
#include "optimize/search.hpp"

namespace fird {

namespace {

// The population generator's stream (search.cpp's streams: stages from 0, the final and
// noise runs at 1000 and 1001, the stage noise pair at 1002, the tailored start's quick
// trace at 1004).
constexpr std::uint64_t kPopulationStream = 1003;
// auto's restarts: run r (from 1) draws its generator from stream kRestartStreams + r, and
// its Levenberg-Marquardt run r (from 0; the first with the stages' own rays) its stage s's
// rays from kRestartRayStreams + r S + s (S stages).
constexpr std::uint64_t kRestartStreams = 1100;
constexpr std::uint64_t kRestartRayStreams = 1200;

// A generation that asks only for candidates the stage has traced already adds nothing; this
// many in a row and the search has converged onto lattice points it knows.
constexpr unsigned kIdleGenerations = 10;

// What a fitness call does right now (the module's problem calls lattice_fitness).
struct Generation {
    enum class Mode { Ask, Answer } mode = Mode::Ask;
    Objective* objective = nullptr;
    std::vector<std::vector<double>> asked; // Ask: the snapped points, in pagmo's order
};

// The fitness pagmo asks for. pagmo works in the sample coordinates (height_modes.hpp: a
// freed height grid's cosine modes, or the parameters themselves); a point it proposes is
// mapped to parameters and judged at their nearest lattice point inside the box, as the
// lattice methods judge theirs.
// CMA-ES and xNES sample outside the box (pagmo's own clamping, force_bounds, would bias
// the covariance): such a point scores its lattice point's value grown by its squared
// distance outside, in box widths, so that the search is drawn back rather than left to
// drift where every point scores alike.
double lattice_fitness(Generation& generation, const SampleCoordinates& coordinates,
                       const std::vector<double>& c) {
    const std::vector<double> x = coordinates.parameters(c);
    Objective& f = *generation.objective;
    const ParameterSpace& space = f.space();
    const std::vector<double> snapped = space.snap(x);
    if (generation.mode == Generation::Mode::Ask) {
        generation.asked.push_back(snapped);
        return 0.0;
    }
    double outside = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        const double width = std::max(space.hi[k] - space.lo[k], space.step[k]);
        const double d = (x[k] - std::clamp(x[k], space.lo[k], space.hi[k])) / width;
        outside += d * d;
    }
    return f(snapped) * (1.0 + outside);
}

// The module's table, loaded on first use.
const PagmoGenerations& pagmo_generations() {
    return program_module_table<PagmoGenerations>(kPagmoModuleFile, kPagmoModuleSymbol);
}

// Hansen's default population size, 4 + floor(3 ln n): 6 for two parameters, 14 for 36
// (one submission of the fast path's batch, FastTracer::kMaxBatchCandidates = 16). pagmo's
// CMA-ES needs at least 5.
std::uint64_t population_size(std::size_t n) {
    return std::max<std::uint64_t>(5, 4 + std::uint64_t(std::floor(3.0 * std::log(double(n)))));
}

} // namespace

struct PopulationSearch::State {
    Objective* objective;
    PopulationReport* report;
    Generation generation;
    const PagmoGenerations* pagmo;
    // The module's run (algorithm and population), destroyed by the module.
    std::unique_ptr<void, void (*)(void*)> run{nullptr, nullptr};
    unsigned idle = 0;
};

PopulationSearch::PopulationSearch(Objective& f, SearchMethod method, const std::vector<double>& x0,
                                   double sigma0, PopulationReport& report, std::uint32_t run) {
    const ParameterSpace& space = f.space();
    const std::uint64_t avoid = streams_avoid(f.scene());
    const auto seed = std::uint32_t(stream_seed(
        f.settings().seed, run == 0 ? kPopulationStream : kRestartStreams + run, avoid));
    state_ = std::unique_ptr<State>(new State{
        .objective = &f, .report = &report, .generation = {}, .pagmo = &pagmo_generations()});
    state_->generation.objective = &f;
    const std::vector<double> start = space.snap(x0);
    auto coordinates = std::make_shared<const SampleCoordinates>(
        sample_coordinates(f.scene().reflector, space, start, f.scene().optimize.height_sampling));
    PagmoRunSpec spec{.xnes = method == SearchMethod::Xnes,
                      .sigma0 = sigma0,
                      .seed = seed,
                      .lo = coordinates->lo,
                      .hi = coordinates->hi};
    Generation* generation = &state_->generation;
    state_->run = {state_->pagmo->create(spec,
                                         [generation, coordinates](const std::vector<double>& c) {
                                             return lattice_fitness(*generation, *coordinates, c);
                                         }),
                   state_->pagmo->destroy};
    const std::uint64_t size = population_size(space.size());
    std::vector<PopulationReport::Run> runs = std::move(report.runs); // the runs before
    report = {.algorithm = method_name(method == SearchMethod::Xnes ? SearchMethod::Xnes
                                                                    : SearchMethod::Cmaes),
              .size = size,
              .sigma0 = sigma0,
              .seed = seed,
              .modes = coordinates->modes,
              .modes_grid = coordinates->grid,
              .runs = std::move(runs)};
    // The first generation's mean is the start (coordinates 0 of the modes): the whole
    // population there, traced once.
    state_->generation.mode = Generation::Mode::Answer;
    const double l2 = f(start);
    const std::vector<double> at_start =
        coordinates->transform.empty() ? start : std::vector<double>(start.size(), 0.0);
    for (std::uint64_t i = 0; i < size; ++i)
        state_->pagmo->push_back(state_->run.get(), at_start, l2);
}

PopulationSearch::~PopulationSearch() = default;

void require_population_module() {
    (void)pagmo_generations();
}

StopReason PopulationSearch::run_stage(std::uint64_t max_evaluations) {
    State& s = *state_;
    Objective& f = *s.objective;
    const ParameterSpace& space = f.space();
    const std::uint64_t first = f.evaluations();
    while (true) {
        if (max_evaluations && f.evaluations() - first >= max_evaluations) {
            s.report->verdict =
                fmt::format("the stage's budget of {} candidates was used up", max_evaluations);
            return StopReason::MaxEvaluations;
        }
        // The generation's points: the same generation on copies, only noted.
        s.generation.mode = Generation::Mode::Ask;
        s.generation.asked.clear();
        s.pagmo->evolve_copy(s.run.get());
        const std::vector<std::vector<double>> points = std::move(s.generation.asked);
        // One batch (Objective::evaluate_all: FastTracer::kMaxBatchCandidates a submission),
        // each point recorded in pagmo's order; a stop (budget, threshold, interruption)
        // comes out of here, between generations as far as pagmo is concerned.
        const std::uint64_t before = f.evaluations();
        // Its candidates carry its number (the progress chart's generation bands).
        f.set_generation(std::uint32_t(s.report->generations + 1));
        try {
            (void)f.evaluate_all(points);
        } catch (const SearchStopped& stop) {
            f.set_generation(std::nullopt);
            s.report->verdict =
                fmt::format("stopped ({}) in generation {}", stop_reason_name(stop.reason),
                            s.report->generations + 1);
            throw;
        } catch (...) {
            f.set_generation(std::nullopt);
            throw;
        }
        f.set_generation(std::nullopt);
        // The generation itself, every point answered from the stage's memo.
        s.generation.mode = Generation::Mode::Answer;
        s.pagmo->evolve(s.run.get());
        ++s.report->generations;
        s.report->spread.assign(space.size(), 0.0);
        bool within_a_step = !points.empty();
        for (std::size_t k = 0; k < space.size(); ++k) {
            double lo = HUGE_VAL, hi = -HUGE_VAL;
            for (const auto& x : points)
                lo = std::min(lo, x[k]), hi = std::max(hi, x[k]);
            s.report->spread[k] = points.empty() ? 0.0 : (hi - lo) / space.step[k];
            within_a_step = within_a_step && s.report->spread[k] <= 1.0 + 1e-9;
        }
        if (within_a_step) {
            s.report->verdict = fmt::format(
                "converged: generation {}'s {} candidates lie within one step of each other in "
                "every parameter",
                s.report->generations, points.size());
            return StopReason::Converged;
        }
        s.idle = f.evaluations() == before ? s.idle + 1 : 0;
        if (s.idle >= kIdleGenerations) {
            s.report->verdict = fmt::format(
                "converged: {} generations in a row asked only for lattice points already "
                "traced in this stage",
                kIdleGenerations);
            return StopReason::Converged;
        }
    }
}

namespace {

// A stage of auto's run `number` (from 0): the first run's stages by their names, the later
// runs' with the run's number ("explore 2", "polish 2", ...).
std::string run_stage_name(const char* name, std::uint32_t number) {
    return number == 0 ? name : fmt::format("{} {}", name, number + 1);
}

// A Levenberg-Marquardt run's stages before its polish, from the start: the height grid's
// modes freed by degree on the first stage's coarse far field, the broad shape first, then
// all at once on the others'. Which basin it ends in is decided by its path through the
// coarse stages' noise (on the 36-height freeform from its flat start, one search seed of
// six ended with two corner heights 7-8 mm off), so a run after the first (`again` > 0)
// draws the coarse stages' rays from a stream of its own (the polish keeps the scene's rays,
// so that the runs' bests compare). Returns the best point.
std::vector<double> levenberg_descent(Objective& f, const std::vector<Fidelity>& stages,
                                      std::uint32_t number, std::uint32_t again) {
    std::vector<double> x = f.space().start;
    for (std::size_t s = 0; s + 1 < stages.size(); ++s) {
        // Its steps judged on the scene's far-field grid at the stage's rays (its model takes
        // coarser cells): on the explore stage's coarse grid alone, the 36-height freeform
        // ended 2.4 x that grid's floor for one seed of five.
        Fidelity fidelity = stages[s];
        fidelity.farfield_w = stages.back().farfield_w;
        fidelity.farfield_h = stages.back().farfield_h;
        if (again > 0)
            fidelity.seed =
                stream_seed(f.settings().seed, kRestartRayStreams + again * stages.size() + s,
                            streams_avoid(f.scene()));
        f.begin_stage(run_stage_name(s == 0 ? "explore" : "refine", number), fidelity);
        LevenbergReport stage_report;
        (void)run_levenberg(f, x, stage_report,
                            s == 0 ? ModeOrder::ByDegree : ModeOrder::AllAtOnce);
        if (const Candidate* b = f.stage_best()) x = b->x;
    }
    return x;
}

// A CMA-ES run through every stage, from the start: `record` gets its generator and
// generations, and its best before the polish. Returns the best point.
std::vector<double> cmaes_stages(Objective& f, const std::vector<Fidelity>& stages,
                                 std::uint32_t number, PopulationReport& report,
                                 PopulationReport::Run& record) {
    const std::size_t n = f.space().size();
    std::vector<double> x = f.space().start;
    std::unique_ptr<PopulationSearch> search;
    for (std::size_t s = 0; s < stages.size(); ++s) {
        const bool last = s + 1 == stages.size();
        f.begin_stage(run_stage_name(s == 0 ? "explore" : "refine", number), stages[s]);
        // The run begins in the first stage from the scene's start, a quarter of each box
        // wide (as the NLopt methods' first step), and carries its mean, covariance and step
        // size into the next stages, where only the rays change.
        if (!search)
            search = std::make_unique<PopulationSearch>(f, SearchMethod::Cmaes, f.space().start,
                                                        kPopulationSigma0, report, number);
        // The coarse stages are cheap but noisy: each may use 30 (n + 1) candidates (1110 for
        // 36 heights, about 80 generations of 14) before the next takes over; the last
        // 40 (n + 1), enough to settle in a basin (measured on the 36-height freeform:
        // docs/optimization.md), which the polish then descends far faster than CMA-ES, whose
        // covariance needs on the order of n^2 generations to learn the valley.
        (void)search->run_stage((last ? 40 : 30) * (n + 1));
    }
    record.seed = report.seed;
    record.generations = report.generations;
    if (const Candidate* b = f.stage_best()) {
        x = b->x;
        record.before_polish = b->score;
    }
    return x;
}

// From the polish's best while it is above the noise (stage_noise), up to kLongStepRounds
// rounds: every parameter alone moved by each of kLongStepsOfBox either way (onto its
// lattice, inside its box), all traced together at the polish's fidelity and rays; the best
// of them, where it beats the stage's best, polished again (Levenberg-Marquardt, modes by
// degree). The polish's model is local, and a parameter the other parameters have made up
// for (a corner height the rest of the surface has bent around) lies past a ridge it does
// not see. Returns the rounds that gained; `polish` becomes the last polish's report.
std::uint32_t long_steps(Objective& f, LevenbergReport& polish) {
    const ParameterSpace& space = f.space();
    std::uint32_t gained = 0;
    for (std::uint32_t round = 0; round < kLongStepRounds; ++round) {
        const Candidate* best = f.stage_best();
        if (!best || best->l2_lm <= stage_noise(f, best->x, best->l2_lm).limit_lm) break;
        const std::vector<double> from = best->x;
        const double score = best->score;
        std::vector<std::vector<double>> points;
        std::set<std::vector<double>> seen{from};
        for (std::size_t k = 0; k < space.size(); ++k)
            for (const double share : kLongStepsOfBox)
                for (const double sign : {1.0, -1.0}) {
                    // Only parameter k moves (the others keep the polish's continuous values).
                    std::vector<double> y = from;
                    y[k] = std::clamp(from[k] + sign * share * (space.hi[k] - space.lo[k]),
                                      space.lo[k], space.hi[k]);
                    y[k] = space.snap(y)[k];
                    if (seen.insert(y).second) points.push_back(std::move(y));
                }
        // A round the budget cannot hold is not begun: the run then ends whole, its report
        // kept, rather than stopped inside it.
        if (points.empty() || points.size() > f.remaining()) break;
        const std::vector<double> scores = f.evaluate_all(points);
        const auto k = std::size_t(std::min_element(scores.begin(), scores.end()) - scores.begin());
        if (!(scores[k] < score)) break;
        LevenbergReport again;
        (void)run_levenberg(f, points[k], again, ModeOrder::ByDegree);
        polish = again;
        ++gained;
    }
    return gained;
}

} // namespace

StopReason run_auto_population(Objective& f, const std::vector<Fidelity>& stages,
                               PopulationReport& report, LevenbergReport& polish,
                               bool retrace_start) {
    const std::size_t n = f.space().size();
    std::optional<double> best_polished;
    std::optional<std::vector<double>> best_polished_x;
    // Beyond kCmaesFirstUpTo parameters, Levenberg-Marquardt's runs first (numbers [0,
    // levenberg_runs)), CMA-ES's after; up to it, CMA-ES's first and one Levenberg-Marquardt
    // run last. Levenberg-Marquardt starts again only with coarse stages to draw other rays
    // for: with the scene's stage alone, another run would repeat the first candidate for
    // candidate.
    const bool cmaes_first = n <= kCmaesFirstUpTo;
    const std::uint32_t levenberg_runs = cmaes_first || stages.size() == 1 ? 1 : kLevenbergRuns;
    const std::uint32_t first_levenberg = cmaes_first ? kPopulationRuns - 1 : 0;
    const auto is_levenberg = [&](std::uint32_t number) {
        return number >= first_levenberg && number < first_levenberg + levenberg_runs;
    };
    std::uint32_t number = 0;
    try {
        for (; number < kPopulationRuns; ++number) {
            const std::uint64_t first = f.evaluations();
            const bool levenberg = is_levenberg(number);
            PopulationReport::Run record{.method = levenberg ? "levenberg" : "cmaes"};
            std::vector<double> x =
                levenberg ? levenberg_descent(f, stages, number, number - first_levenberg)
                          : cmaes_stages(f, stages, number, report, record);
            // The polish, at the last stage's fidelity and rays, from the run's best so far
            // (a tailored start traced there first: the search then never ends above it), the
            // modes freed by degree again: the coarse stages' noise can leave the broad shape
            // off (on the 36-height freeform, the whole grid 2 mm low for two search seeds of
            // six), which every mode at once did not mend (1.26 and 1.5 x the noise floor),
            // nor the piston and tilts first and then all (1.24 and 1.71 x); freed by degree
            // at these rays, 1.15 and 1.18 x.
            f.begin_stage(run_stage_name("polish", number), stages.back());
            const std::uint64_t polish_first = f.evaluations();
            if (retrace_start && number == 0) (void)f(f.space().snap(f.space().start));
            if (levenberg) record.before_polish = f(x);
            LevenbergReport this_polish;
            (void)run_levenberg(f, x, this_polish, ModeOrder::ByDegree);
            // Long steps after the last Levenberg-Marquardt run beyond kCmaesFirstUpTo, from
            // the best polish of all of them (an earlier run's best traced again here: the
            // polishes share their rays, so it scores the same): after every run they cost
            // as much as the run again where they gain (the 36-height freeform, seed 2: 2400
            // candidates on three rounds after each run, 1.28 -> 1.08 lm), and the search's
            // 20 minutes hold them once.
            const std::uint64_t long_steps_first = f.evaluations();
            if (levenberg && !cmaes_first && !is_levenberg(number + 1)) {
                const Candidate* own = f.stage_best();
                if (best_polished_x && (!own || *best_polished < own->score))
                    (void)f(*best_polished_x);
                record.long_steps = long_steps(f, this_polish);
            }
            const std::uint64_t long_steps_candidates = f.evaluations() - long_steps_first;
            const Candidate* polished = f.stage_best();
            record.candidates = f.evaluations() - first;
            record.polished = polished ? polished->score : 0.0;
            if (polished && (!best_polished || polished->score < *best_polished)) {
                best_polished = polished->score;
                best_polished_x = polished->x;
                polish = this_polish;
            }
            // At the noise: done. Else again, where the budget holds another run like this one.
            bool again = false;
            if (polished) {
                const ConfirmNoise noise = stage_noise(f, polished->x, polished->l2_lm);
                record.noise_limit = noise.limit_lm;
                again = polished->l2_lm > noise.limit_lm;
            }
            report.runs.push_back(record);
            if (!again) {
                report.verdict = fmt::format("run {} ({}) polished to what noise explains",
                                             number + 1, record.method);
                return StopReason::Converged;
            }
            if (number + 1 == kPopulationRuns) {
                report.verdict = fmt::format("{} runs, the best {:.4g} above what noise explains",
                                             report.runs.size(), *best_polished);
                return StopReason::Converged;
            }
            // How long the next run will be, about: a CMA-ES run its stages' budgets (30 (n + 1)
            // each, 40 (n + 1) the last) and a polish, so at least those and at least as long as
            // this run; a Levenberg-Marquardt run after another as long as that one; after a
            // CMA-ES run, a descent from the start at the coarse stages' rays and a polish like
            // this run's, so twice this polish (a CMA-ES run's length would leave half the
            // budget unused: the road luminaire's 8-height profile stopped at 795 of 1500). The
            // long steps are no part of a run's length: they come once.
            const std::uint64_t cmaes = (30 * (stages.size() - 1) + 40) * (n + 1);
            const std::uint64_t this_polish_candidates =
                f.evaluations() - polish_first - long_steps_candidates;
            const std::uint64_t next =
                !is_levenberg(number + 1)
                    ? std::max<std::uint64_t>(record.candidates - long_steps_candidates, cmaes)
                : levenberg ? record.candidates
                            : 2 * this_polish_candidates;
            if (f.remaining() < next) {
                report.verdict =
                    fmt::format("{} runs, the best {:.4g} above what noise explains; the budget "
                                "left ({}) holds no other run (about {} candidates)",
                                report.runs.size(), *best_polished, f.remaining(), next);
                return StopReason::MaxEvaluations;
            }
        }
    } catch (const SearchStopped& stop) {
        // A run cut short (the budget, a threshold, Ctrl-C): the report says which, not the
        // verdict of its last completed stage.
        report.verdict = fmt::format(
            "run {} ({}) stopped ({}) in its stage {}, after {} complete run{}", number + 1,
            is_levenberg(number) ? "levenberg" : "cmaes", stop_reason_name(stop.reason),
            f.stages().back().name, report.runs.size(), report.runs.size() == 1 ? "" : "s");
        throw;
    }
    return StopReason::Converged;
}

} // namespace fird
