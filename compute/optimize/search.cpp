#include "search.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <map>
#include <numeric>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "model/press_measures.hpp"
#include "model/surface_distance.hpp"
#include "optimize/methods.hpp"
#include "optimize/objective.hpp"
#include "optimize/press_constraints.hpp"
#include "sampling/philox.hpp"

namespace fird {

namespace {

// Streams of a search's seed (stream_seed): one per stage, then the final and noise runs.
constexpr std::uint64_t kFinalStream = 1000;
constexpr std::uint64_t kNoiseStream = 1001;

// The counter word that keeps a search's stream seeds apart from the ray sampler's blocks
// under the same key (words 2 of those counters are 0, kSampleStream and Sobol's 0x50B01).
constexpr std::uint32_t kStreamSeedDomain = 0x5EED5u;

nlopt::algorithm nlopt_algorithm(SearchMethod m) {
    switch (m) {
    case SearchMethod::Bobyqa:
        return nlopt::LN_BOBYQA;
    case SearchMethod::Sbplx:
        return nlopt::LN_SBPLX;
    case SearchMethod::Cobyla:
        return nlopt::LN_COBYLA;
    case SearchMethod::DirectL:
        return nlopt::GN_DIRECT_L;
    case SearchMethod::Crs2:
        return nlopt::GN_CRS2_LM;
    case SearchMethod::Auto:
    case SearchMethod::Grid:
    case SearchMethod::Cmaes:
    case SearchMethod::Xnes:
    case SearchMethod::Levenberg:
        break;
    }
    throw std::logic_error("not an NLopt method");
}

// One NLopt method alone: from the start, initial steps of a quarter of each range (no
// finer than the step), tolerances of one step, flat directions held.
StopReason run_single(Objective& f, SearchMethod method, const std::vector<FlatDirection>& flat) {
    const ParameterSpace& space = f.space();
    NloptRun run{.algorithm = nlopt_algorithm(method),
                 .x0 = space.start,
                 .free = std::vector<bool>(space.size(), true),
                 .seed = f.settings().seed};
    for (std::size_t k = 0; k < space.size(); ++k) {
        for (const FlatDirection& d : flat)
            if (d.held == space.names[k]) run.free[k] = false;
        run.initial_step.push_back(std::max(space.step[k], 0.25 * (space.hi[k] - space.lo[k])));
        run.xtol.push_back(space.step[k]);
    }
    return run_nlopt(f, run);
}

double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Whether the lattice method's last stage ended on the best point of its neighbourhood, from
// that stage's own candidates (same rays: their order is free of noise between them).
LatticeCheck lattice_check(const Objective& f, const std::optional<ConfirmNoise>& confirm,
                           StopReason stopped) {
    LatticeCheck c;
    const StageSummary& stage = f.stage();
    c.stage = stage.name;
    if (confirm) {
        c.confirm_l2_lm = confirm->l2_lm;
        c.confirm_noise_l2_lm = confirm->noise_l2_lm;
        c.confirm_noise_limit_lm = confirm->limit_lm;
    }
    const Candidate* best = f.stage_best();
    if (stage.name != "confirm" && stage.name != "grid") {
        c.verdict = fmt::format("the search stopped ({}) in its {} stage, before the lattice",
                                stop_reason_name(stopped), stage.name);
        return c;
    }
    if (!best) {
        c.verdict = fmt::format("the {} stage traced no feasible candidate (stopped: {})",
                                stage.name, stop_reason_name(stopped));
        return c;
    }
    const ParameterSpace& space = f.space();
    c.x = best->x;
    const std::uint32_t index = std::uint32_t(f.stages().size() - 1);
    std::map<std::vector<double>, const Candidate*> traced;
    for (const Candidate& h : f.history())
        if (h.stage == index) traced[h.x] = &h;
    const auto neighbours = lattice_neighbours(space, c.x, std::vector<bool>(space.size(), true),
                                               lattice_moves_together(space.size()));
    c.neighbours = neighbours.size();
    std::uint64_t singles_missed = 0;
    const std::size_t singles =
        lattice_neighbours(space, c.x, std::vector<bool>(space.size(), true), 1).size();
    for (std::size_t i = 0; i < neighbours.size(); ++i) {
        const auto it = traced.find(neighbours[i]);
        if (it == traced.end()) {
            c.not_polled.push_back(neighbours[i]);
            singles_missed += i < singles ? 1 : 0;
            continue;
        }
        ++c.polled;
        // An infeasible neighbour is no better: it is never traced (DESIGN.md §2).
        if (it->second->feasible && it->second->score < best->score) ++c.better;
    }
    if (c.better > 0)
        c.verdict = fmt::format("{} of the {} neighbours one step away are lower than {} "
                                "(the search stopped before moving on: {})",
                                c.better, c.neighbours, space.text(c.x), stop_reason_name(stopped));
    else if (c.not_polled.empty())
        c.verdict =
            fmt::format("the best lattice point of its neighbourhood: all {} points one "
                        "step away (alone, or two or three parameters at once) traced in the {} "
                        "stage, none lower",
                        c.neighbours, stage.name);
    else if (confirm && singles_missed == 0 && confirm->l2_lm <= confirm->limit_lm)
        c.verdict = fmt::format(
            "its {0} {2:.6g} {1} is what noise alone leaves at this fidelity (two independent "
            "traces of it differ by {3:.6g} {1}; limit {4:.6g} {1}), so the {5} steps of several "
            "parameters at once were not polled; none of the {6} single steps is lower",
            metric_name(f.scene().optimize.metric), metric_unit(f.scene().optimize.metric),
            confirm->l2_lm, confirm->noise_l2_lm, confirm->limit_lm, c.not_polled.size(), c.polled);
    else
        c.verdict =
            fmt::format("{} of the {} neighbours one step away were not polled "
                        "(stopped: {}); none of the {} polled is lower",
                        c.not_polled.size(), c.neighbours, stop_reason_name(stopped), c.polled);
    return c;
}

} // namespace

namespace {

Fidelity search_final_fidelity(const Scene& scene, const SearchSettings& settings) {
    Fidelity f = scene_fidelity(scene);
    f.seed = stream_seed(settings.seed, kFinalStream, streams_avoid(scene));
    return f;
}

// The scene's reflector traced by `eval`: its far-field flux (none where it cannot be
// traced: it cuts the source).
std::optional<double> scene_start_flux(Evaluator& eval, const Scene& scene,
                                       const ParameterSpace& space) {
    const Scene start = space.candidate(scene, space.start);
    if (!traceable(start, start.reflector).feasible) return std::nullopt;
    if (space.moves_source()) eval.set_source(start.source);
    return eval.evaluate(start.reflector).farfield_lm;
}

DesiredFarField scaled_desired(const vk::Context& ctx, const Scene& scene, double start_flux_lm,
                               Backend backend) {
    if (scene.target.kind == TargetDesc::Kind::Photometric && !scene.target.absolute &&
        !(start_flux_lm > 0.0))
        throw std::invalid_argument(fmt::format(
            "{}: the start reflector sends no light to the far field, so a relative "
            "photometric target has nothing to be scaled to (set [target] absolute = true or "
            "start from another reflector)",
            scene.path));
    return desired_farfield(ctx, scene, start_flux_lm, backend);
}

} // namespace

DesiredFarField search_desired(const vk::Context& ctx, const Scene& scene,
                               const SearchSettings& settings) {
    const ParameterSpace space = parameter_space(scene);
    Evaluator eval(ctx, scene, search_final_fidelity(scene, settings), settings.backend);
    return scaled_desired(ctx, scene, scene_start_flux(eval, scene, space).value_or(0.0),
                          settings.backend);
}

const char* stop_reason_name(StopReason r) {
    switch (r) {
    case StopReason::None:
        return "none";
    case StopReason::Threshold:
        return "threshold";
    case StopReason::Converged:
        return "converged";
    case StopReason::MaxEvaluations:
        return "max_evaluations";
    case StopReason::Exhausted:
        return "exhausted";
    case StopReason::Interrupted:
        return "interrupted";
    }
    return "?";
}

SearchSettings search_settings(const Scene& scene) {
    const OptimizeSettings& o = scene.optimize;
    SearchSettings s{.method = o.method,
                     .rays = o.rays,
                     .threshold_lm = o.threshold_lm,
                     .max_evaluations = o.max_evaluations,
                     .seed = scene.trace.seed};
    if (s.rays.empty()) {
        if (s.method == SearchMethod::Auto)
            for (std::uint64_t n : {100000ull, 1000000ull})
                if (n < scene.trace.rays) s.rays.push_back(n);
        s.rays.push_back(scene.trace.rays);
    }
    return s;
}

// Philox4x32-10 keyed by the seed, counting over the stream: the counter-based generator
// the rays already use (Salmon et al. 2011), so stream k of seed s is the block at counter
// (k, domain, draw) under key s. For one key the counter-to-block map is a bijection, so
// streams of one seed never meet; under different keys the blocks are Philox's
// independent streams, with no algebraic relation between (s, k) and (s', k'). XOR-ing a
// hash of the seed with a hash of the stream instead (as before) is symmetric: seed
// s = c + j at stream k gave what seed c + k gave at stream j. The target's seed is
// stepped over by drawing the next block (draw 1, 2, ...), still a function of (s, k).
std::uint64_t stream_seed(std::uint64_t seed, std::uint64_t stream, std::uint64_t avoid) {
    const std::array<std::uint32_t, 2> key{std::uint32_t(seed), std::uint32_t(seed >> 32)};
    for (std::uint32_t draw = 0;; ++draw) {
        const Philox4 block = philox4x32_10(
            {std::uint32_t(stream), std::uint32_t(stream >> 32), kStreamSeedDomain, draw}, key);
        const std::uint64_t s = (std::uint64_t(block[1]) << 32) | block[0];
        if (s != avoid) return s;
    }
}

std::uint64_t streams_avoid(const Scene& scene) {
    return scene.target.kind == TargetDesc::Kind::Reflector ? scene.target.seed : ~0ull;
}

std::pair<std::uint32_t, std::uint32_t> stage_farfield(std::uint32_t w, std::uint32_t h,
                                                       std::uint64_t rays) {
    const std::uint32_t g = std::gcd(w, h);
    for (std::uint32_t d = 1; d <= g; ++d)
        if (g % d == 0 && std::uint64_t(w / d) * (h / d) * 20 <= rays) return {w / d, h / d};
    return {w / g, h / g};
}

std::vector<Fidelity> search_stages(const Scene& scene, const SearchSettings& settings) {
    const Fidelity base = scene_fidelity(scene);
    const std::uint64_t avoid = streams_avoid(scene);
    const auto stage = [&](std::uint64_t rays, std::size_t k, bool last) {
        Fidelity f = base;
        f.rays = rays;
        f.seed = stream_seed(settings.seed, k, avoid);
        if (!last)
            std::tie(f.farfield_w, f.farfield_h) = stage_farfield(f.farfield_w, f.farfield_h, rays);
        return f;
    };
    std::vector<Fidelity> stages;
    if (settings.method != SearchMethod::Auto) return {stage(settings.rays.back(), 0, true)};
    for (std::size_t k = 0; k < settings.rays.size(); ++k)
        stages.push_back(stage(settings.rays[k], k, k + 1 == settings.rays.size()));
    return stages;
}

bool searches_with_population(const Scene& scene, const SearchSettings& settings) {
    return settings.method == SearchMethod::Cmaes || settings.method == SearchMethod::Xnes ||
           (settings.method == SearchMethod::Auto &&
            parameter_space(scene).size() > kPopulationAbove);
}

SearchOutcome run_search(const vk::Context& ctx, const Scene& scene, const SearchRequest& req) {
    const auto t0 = std::chrono::steady_clock::now();
    if (scene.target.kind == TargetDesc::Kind::None && !req.desired)
        throw std::invalid_argument(
            fmt::format("{}: [target] is missing: a search needs a desired far field (a target "
                        "reflector or an IES / LDT file)",
                        scene.path));
    const SearchSettings& settings = req.settings;
    ParameterSpace space = parameter_space(scene);
    SearchOutcome out;
    SearchResult& r = out.result;
    r.method = method_name(settings.method);
    r.backend = backend_name(settings.backend);
    r.names = space.names;
    r.bounds = space.bounds();
    r.flat_directions = flat_directions(scene.reflector, space.names);
    r.grid_size = space.lattice_size();
    if (settings.refine && settings.method != SearchMethod::Auto &&
        settings.method != SearchMethod::Grid)
        throw std::invalid_argument(fmt::format(
            "refining below the step follows a lattice method (auto or grid), not {}", r.method));
    // pagmo's xNES sets its own start (the origin, unit spread) for one dimension and keeps
    // it across generations (memory on): the search's start and sigma0 would be ignored.
    if (settings.method == SearchMethod::Xnes && space.size() < 2)
        throw std::invalid_argument(
            "xnes needs two free parameters or more (pagmo's xNES ignores the start in one "
            "dimension); use cmaes or bobyqa for one");
    // A press's limit that nothing in the box meets: refused before any trace.
    refuse_unmeetable_constraints(scene, space);
    // Beyond a handful of free parameters auto searches with a population, not the lattice.
    const bool auto_population =
        settings.method == SearchMethod::Auto && searches_with_population(scene, settings);
    if (settings.refine && auto_population)
        throw std::invalid_argument(fmt::format(
            "refining below the step follows the lattice, and with {} free parameters (more "
            "than {}) auto searches with CMA-ES instead",
            space.size(), kPopulationAbove));

    // The scene's reflector at the scene's fidelity, with rays of its own stream (the same
    // stream re-evaluates the best at the end): the flux a relative photometric target is
    // scaled to, once for the whole search, and the start's l2 unless the search starts
    // elsewhere (request.start).
    const std::uint64_t avoid = streams_avoid(scene);
    const Fidelity final_fidelity = search_final_fidelity(scene, settings);
    Evaluator final_eval(ctx, scene, final_fidelity, settings.backend);
    bool scene_start_traced = false;
    if (!req.desired || !req.start) {
        const std::optional<double> flux = scene_start_flux(final_eval, scene, space);
        scene_start_traced = flux.has_value();
        out.desired = req.desired
                          ? *req.desired
                          : scaled_desired(ctx, scene, flux.value_or(0.0), settings.backend);
    } else {
        out.desired = *req.desired;
    }
    if (out.desired.farfield.width != final_fidelity.farfield_w ||
        out.desired.farfield.height != final_fidelity.farfield_h)
        throw std::invalid_argument(fmt::format(
            "{}: the desired far field is {} x {}, the scene's [trace] farfield {} x {}",
            scene.path, out.desired.farfield.width, out.desired.farfield.height,
            final_fidelity.farfield_w, final_fidelity.farfield_h));
    r.desired = out.desired.description;
    r.metric = metric_name(scene.optimize.metric);
    r.metric_unit = metric_unit(scene.optimize.metric);
    r.desired_photometrics = photometrics(out.desired.farfield, scene.source.flux_lm);
    final_eval.set_desired(out.desired.farfield);
    if (req.start) {
        if (req.start->size() != space.size())
            throw std::invalid_argument("the search's start has the wrong number of parameters");
        space.start = *req.start;
        r.start = req.start_report;
    }
    r.start.parameters = space.named(space.start);
    const Scene start_scene = space.candidate(scene, space.start);
    // Traced for its l2 even where it breaks a press's constraint.
    if (traceable(start_scene, start_scene.reflector).feasible) {
        if (!scene_start_traced || req.start) {
            if (space.moves_source()) final_eval.set_source(start_scene.source);
            (void)final_eval.evaluate(start_scene.reflector);
        }
        r.start_l2_lm = final_eval.compare();
    }
    r.smoothness_weight = scene.optimize.smoothness;
    if (r.smoothness_weight > 0.0)
        r.start_bending_energy =
            search_bending_energy(Surface::make(start_scene.reflector, scene.holder));

    Objective f(ctx, scene, space, out.desired.farfield, settings, req.control, req.replay,
                req.on_candidate);
    const std::vector<Fidelity> stages = search_stages(scene, settings);
    std::optional<ConfirmNoise> confirm;
    const auto judge_lattice = [&] {
        if ((settings.method == SearchMethod::Auto && !auto_population) ||
            settings.method == SearchMethod::Grid)
            r.lattice = lattice_check(f, confirm, r.stopped);
    };
    try {
        switch (settings.method) {
        case SearchMethod::Grid:
            f.begin_stage("grid", stages[0]);
            r.stopped = run_grid(f);
            break;
        case SearchMethod::Auto:
            if (auto_population)
                r.stopped = run_auto_population(f, stages, r.population.emplace(),
                                                r.levenberg.emplace(), r.start.kind == "tailored");
            else
                r.stopped = run_auto(f, stages, confirm);
            break;
        case SearchMethod::Cmaes:
        case SearchMethod::Xnes: {
            f.begin_stage(r.method, stages[0]);
            PopulationSearch search(f, settings.method, space.start, kPopulationSigma0,
                                    r.population.emplace());
            r.stopped = search.run_stage(0);
            break;
        }
        case SearchMethod::Levenberg:
            f.begin_stage(r.method, stages[0]);
            r.stopped = run_levenberg(f, space.start, r.levenberg.emplace());
            break;
        default:
            f.begin_stage(r.method, stages[0]);
            r.stopped = run_single(f, settings.method, r.flat_directions);
            break;
        }
        judge_lattice();
        if (settings.refine && r.lattice && !r.lattice->x.empty()) {
            const std::uint32_t judged = std::uint32_t(f.stages().size() - 1);
            f.begin_stage("sub-step", stages.back());
            // The noise at the refine's fidelity: auto's confirm stage measured it at this
            // fidelity (on its best before any pair steps); after the grid it is measured
            // here, on the lattice's best.
            const ConfirmNoise noise =
                confirm ? *confirm : stage_noise(f, r.lattice->x, f.stages()[judged].best_l2_lm);
            // Its own budget used up is no stop of the search's: the lattice's reason stays.
            r.refine.emplace();
            run_refine(f, judged, noise, r.flat_directions, *r.refine);
        }
    } catch (const SearchStopped& s) {
        r.stopped = s.reason;
        if (!r.lattice) judge_lattice();
    }
    r.history = f.history();
    r.stages = f.stages();
    for (const Candidate& c : r.history)
        r.infeasible += c.feasible ? 0 : 1;
    // The best of the last stage that has one; for auto's runs beyond a handful of
    // parameters (each polished at the scene's fidelity with the same rays, a run cut short
    // by the budget or a stop among them), the best of the stages at that very fidelity
    // (a tie to the later), whichever stage the search stopped in.
    const auto take = [&](const StageSummary& s) {
        r.best = s.best;
        r.best_l2_lm = s.best_l2_lm;
        r.best_score = s.best_score;
    };
    for (auto s = r.stages.rbegin(); s != r.stages.rend(); ++s) {
        if (!s->best) continue;
        if (!auto_population) {
            take(*s);
            break;
        }
        if (s->fidelity == stages.back() && (!r.best || s->best_score < r.best_score)) take(*s);
    }
    // Stopped before any stage at the scene's fidelity had a best: the last stage's.
    if (auto_population && !r.best)
        for (auto s = r.stages.rbegin(); s != r.stages.rend(); ++s)
            if (s->best) {
                take(*s);
                break;
            }
    if (r.best) {
        const std::vector<double>& x = r.history[*r.best].x;
        r.best_parameters = space.named(x);
        const Scene best_scene = space.candidate(scene, x);
        const ReflectorDesc& best = best_scene.reflector;
        r.constraints = constraints_at(scene, space, x);
        if (r.smoothness_weight > 0.0) r.best_bending_energy = r.history[*r.best].smoothness;
        if (scene.target.kind == TargetDesc::Kind::Reflector)
            r.surface_rms_mm =
                surface_rms_distance_mm(Surface::make(best, scene.holder),
                                        Surface::make(target_reflector(scene), scene.holder));
        // Fresh rays at the scene's fidelity, and a second independent trace: the l2
        // between those two is what noise alone leaves (skipped when interrupted).
        if (r.stopped != StopReason::Interrupted) {
            if (space.moves_source()) final_eval.set_source(best_scene.source);
            r.final_l2_lm = *final_eval.evaluate(best).l2_lm;
            out.best_farfield = final_eval.farfield();
            r.photometrics = photometrics(*out.best_farfield, scene.source.flux_lm);
            Fidelity noise = final_fidelity;
            noise.seed = stream_seed(settings.seed, kNoiseStream, avoid);
            Evaluator noise_eval(ctx, best_scene, noise, settings.backend);
            (void)noise_eval.evaluate(best);
            r.noise_floor_l2_lm = final_eval.l2_to(noise_eval);
        }
    }
    r.time_s = ms_since(t0) * 1e-3;
    return out;
}

} // namespace fird
