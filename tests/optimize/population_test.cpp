// Population searches on pagmo2 (--method cmaes, xnes; auto beyond six free parameters):
// they recover the analytic optimum of the mirror search; a generation is traced as one
// batch with each candidate's l2 the one it has traced alone; the same seed gives the same
// history and another seed another; a search interrupted mid-generation and resumed ends
// where the uninterrupted one does; auto searches with these runs only beyond six free
// parameters, CMA-ES's first up to sixteen and Levenberg-Marquardt's first beyond.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <optional>
#include <set>
#include <string>

#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "model/press_measures.hpp"
#include "model/surface.hpp"
#include "optimize/methods.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search.hpp"
#include "search_fixture.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

class Population : public VulkanTest, public ::testing::WithParamInterface<SearchMethod> {};

// Whether a shared library whose file name contains `name` is mapped into this process.
bool mapped(const std::string& name) {
    std::ifstream maps("/proc/self/maps");
    for (std::string line; std::getline(maps, line);)
        if (line.find(name) != std::string::npos) return true;
    return false;
}

// The mirror's l2 falls smoothly towards the target's slopes (on the lattice) from anywhere
// in the box: the population ends within one step of them in every parameter, at the noise.
// pagmo is loaded by the search itself, through FIRD's module (io/program_files.hpp), and
// not before: checked where this test is the process's first (as ctest runs each test in a
// process of its own; a binary run whole may have searched before), after it has created
// its device and parsed its scene.
TEST_P(Population, RecoversTheMirrorsSlopesWithinOneStep) {
    const Scene s = scene("mirror_search.toml");
    (void)ctx();
    const ::testing::UnitTest& tests = *::testing::UnitTest::GetInstance();
    if (tests.successful_test_count() + tests.failed_test_count() + tests.skipped_test_count() ==
        0) {
        EXPECT_FALSE(mapped("libpagmo.so"));
        EXPECT_FALSE(mapped("libfird_pagmo.so"));
    }
    const SearchResult r = search(ctx(), s, GetParam()).result;
    EXPECT_TRUE(mapped("libfird_pagmo.so"));
    EXPECT_TRUE(mapped("libpagmo.so"));
    ASSERT_TRUE(r.best);
    ASSERT_TRUE(r.population);
    EXPECT_EQ(r.population->algorithm, method_name(GetParam()));
    EXPECT_EQ(r.stopped, StopReason::Converged) << r.population->verdict;
    for (const auto& [k, range] : s.reflector.optimize)
        EXPECT_LE(std::abs(r.best_parameters.at(k) - s.target.parameters.at(k)),
                  range.step * (1 + 1e-9))
            << k << " = " << r.best_parameters.at(k);
    // Converged: the last generation within one step of itself in every parameter.
    for (double spread : r.population->spread)
        EXPECT_LE(spread, 1.0 + 1e-9);
    ASSERT_TRUE(r.final_l2_lm && r.noise_floor_l2_lm && r.start_l2_lm);
    EXPECT_LT(*r.final_l2_lm, 0.5 * *r.start_l2_lm);
    // Every candidate is a lattice point inside the box.
    const ParameterSpace space = parameter_space(s);
    for (const Candidate& c : r.history)
        EXPECT_EQ(c.x, space.snap(c.x)) << c.index;
    EXPECT_FALSE(r.lattice); // no lattice verdict: the population judged its own end
}

INSTANTIATE_TEST_SUITE_P(Methods, Population,
                         ::testing::Values(SearchMethod::Cmaes, SearchMethod::Xnes),
                         [](const auto& p) { return std::string(method_name(p.param)); });

using PopulationRules = VulkanTest;

// Each generation is one batch: the device's submission count, read as each candidate is
// recorded, takes no more distinct values over the traced candidates than there are
// generations (and the start, traced alone). One trace per candidate would give one per
// candidate. And a batch changes no l2: each is the one the candidate gets traced alone with
// the same rays (the same float, as the grid's batch test has it).
TEST_F(PopulationRules, AGenerationIsTracedAsOneBatchWithTheSingleEvaluationsL2) {
    Scene s = scene("mirror_search.toml");
    s.trace.rays = 5000;
    // A fine lattice (121 values a slope), so that a generation's samples are seldom one
    // lattice point twice, and a budget that ends the search before it converges.
    for (auto& [name, range] : s.reflector.optimize)
        range.step = 0.005;
    s.optimize.max_evaluations = 60;
    std::set<std::uint64_t> seen;
    std::uint64_t traced = 0;
    const SearchOutcome out = search(ctx(), s, SearchMethod::Cmaes, nullptr, {},
                                     [&](const Candidate& c, const StageSummary&) {
                                         if (!c.feasible) return;
                                         ++traced;
                                         seen.insert(ctx().submissions());
                                     });
    const SearchResult& r = out.result;
    ASSERT_TRUE(r.population);
    EXPECT_EQ(r.population->size, 6u);   // 4 + floor(3 ln 2)
    EXPECT_EQ(traced, r.history.size()); // all feasible: the plane stays below the source
    EXPECT_EQ(r.stopped, StopReason::MaxEvaluations);
    EXPECT_EQ(r.history.size(), 60u);
    EXPECT_NE(r.population->verdict.find("stopped (max_evaluations) in generation"),
              std::string::npos)
        << r.population->verdict;
    // 59 candidates after the start in about ten generations of 6; a generation cut by the
    // budget is traced but not completed.
    EXPECT_LE(seen.size(), r.population->generations + 2);
    EXPECT_LT(seen.size(), traced / 3) << "one submission per candidate would be " << traced;
    Evaluator single(ctx(), s, r.stages[0].fidelity);
    single.set_desired(out.desired.farfield);
    const ParameterSpace space = parameter_space(s);
    for (const Candidate& c : r.history) {
        if (!c.feasible) continue;
        EXPECT_EQ(c.l2_lm, *single.evaluate(space.reflector(s.reflector, c.x)).l2_lm) << c.index;
    }
}

TEST_F(PopulationRules, SameSeedSameHistoryAndAnotherSeedAnother) {
    Scene s = scene("mirror_search.toml");
    s.optimize.max_evaluations = 60;
    const auto a = search(ctx(), s, SearchMethod::Cmaes).result;
    const auto b = search(ctx(), s, SearchMethod::Cmaes).result;
    ASSERT_EQ(a.history.size(), b.history.size());
    for (std::size_t i = 0; i < a.history.size(); ++i) {
        EXPECT_EQ(a.history[i].x, b.history[i].x) << i;
        EXPECT_EQ(a.history[i].l2_lm, b.history[i].l2_lm) << i;
    }
    ASSERT_TRUE(a.population && b.population);
    EXPECT_EQ(a.population->seed, b.population->seed);
    Scene other = s;
    other.trace.seed = 99;
    const auto c = search(ctx(), other, SearchMethod::Cmaes).result;
    ASSERT_TRUE(c.population);
    EXPECT_NE(c.population->seed, a.population->seed);
    // The start is the same lattice point; the first generation's samples are not.
    ASSERT_GT(c.history.size(), 1u);
    EXPECT_NE(c.history[1].x, a.history[1].x);
}

// pagmo's xNES keeps its own start in one dimension (the origin, unit spread), so with one
// free parameter it would ignore the search's start: refused before any trace, naming why.
TEST_F(PopulationRules, XnesWithOneFreeParameterIsRefused) {
    Scene s = scene("mirror_search.toml");
    while (s.reflector.optimize.size() > 1)
        s.reflector.optimize.erase(std::prev(s.reflector.optimize.end()));
    try {
        (void)search(ctx(), s, SearchMethod::Xnes);
        FAIL() << "xnes ran with one free parameter";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("xnes needs two free parameters"), std::string::npos)
            << e.what();
    }
}

// Ctrl-C after candidate 15 (the middle of the third generation of 6): resumed from that
// history, the search replays the recorded candidates and ends exactly where the
// uninterrupted one does (pagmo's state is rebuilt from the seed and the replayed l2s).
TEST_F(PopulationRules, InterruptedMidGenerationAndResumedEndsWhereTheUninterruptedOneDoes) {
    Scene s = scene("mirror_search.toml");
    s.optimize.max_evaluations = 80;
    const auto whole = search(ctx(), s, SearchMethod::Cmaes).result;
    SearchControl control;
    const auto cut = search(ctx(), s, SearchMethod::Cmaes, &control, {},
                            [&](const Candidate& c, const StageSummary&) {
                                if (c.index == 15) control.stop = true;
                            })
                         .result;
    EXPECT_EQ(cut.stopped, StopReason::Interrupted);
    ASSERT_EQ(cut.history.size(), 16u);
    const auto resumed = search(ctx(), s, SearchMethod::Cmaes, nullptr, cut.history).result;
    expect_resumed_is_whole(resumed, whole, 16);
    ASSERT_TRUE(resumed.population && whole.population);
    EXPECT_EQ(resumed.population->generations, whole.population->generations);
}

// The stage of `r` named `name` (r.stages.end() if none).
std::vector<StageSummary>::const_iterator named(const SearchResult& r, const std::string& name) {
    return std::find_if(r.stages.begin(), r.stages.end(),
                        [&](const StageSummary& st) { return st.name == name; });
}

// auto's one run ended at the noise: its polish is the stage `polish`'s best, no worse than
// before it and within the noise limit; no lattice verdict; the search's final l2 within
// 1.2 x its noise floor (as RecoversTheSmallFreeformToTheNoise).
void expect_one_run_polished_to_the_noise(const SearchResult& r, std::size_t polish) {
    ASSERT_TRUE(r.population);
    ASSERT_EQ(r.population->runs.size(), 1u) << r.population->verdict;
    EXPECT_EQ(r.stopped, StopReason::Converged);
    ASSERT_LT(polish, r.stages.size());
    EXPECT_EQ(r.stages[polish].name, "polish");
    const auto& run = r.population->runs[0];
    EXPECT_EQ(run.polished, r.stages[polish].best_score);
    EXPECT_LE(run.polished, run.before_polish);
    EXPECT_LE(run.polished, run.noise_limit);
    EXPECT_FALSE(r.lattice);
    ASSERT_TRUE(r.best && r.start_l2_lm && r.final_l2_lm && r.noise_floor_l2_lm);
    EXPECT_LT(r.best_l2_lm, *r.start_l2_lm);
    EXPECT_LE(*r.final_l2_lm, 1.2 * *r.noise_floor_l2_lm);
}

// Nine free heights (more than six, up to kCmaesFirstUpTo): auto's first run is CMA-ES's
// through the stages (explore at the first ray count, refine at the scene's), then its
// polish, with no lattice verdict; on this target it polishes to the noise, so no other run
// follows. The plane's three (its slopes and height) stay with DIRECT and the lattice.
TEST_F(PopulationRules, AutoUpToSixteenFreeParametersRunsCmaesFirst) {
    Scene s = scene("freeform_search.toml");
    ASSERT_EQ(parameter_space(s).size(), 9u);
    static_assert(9 <= kCmaesFirstUpTo);
    s.optimize.max_evaluations = 3000;
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population && r.levenberg);
    expect_one_run_polished_to_the_noise(r, 2);
    EXPECT_EQ(r.population->runs[0].method, "cmaes");
    EXPECT_EQ(r.population->algorithm, "cmaes");
    EXPECT_EQ(r.population->size, 10u); // 4 + floor(3 ln 9)
    EXPECT_GT(r.population->runs[0].generations, 0u);
    ASSERT_EQ(r.stages.size(), 3u);
    EXPECT_EQ(r.stages[0].name, "explore");
    EXPECT_EQ(r.stages[1].name, "refine");
    EXPECT_EQ(r.stages[0].fidelity.rays, 5000u);
    EXPECT_EQ(r.stages[1].fidelity.rays, 20000u);
    EXPECT_EQ(r.stages[2].fidelity, r.stages[1].fidelity);
    // The coarse stages' budget, 30 (n + 1) candidates (a generation may run over by all
    // but one of its own), the start traced first.
    EXPECT_LE(r.stages[0].evaluations, 1u + 300u + r.population->size - 1u);

    Scene six = scene("mirror_search.toml");
    six.reflector.optimize["z0"] = {-4.0, 0.0, 0.5};
    six.optimize.max_evaluations = 30;
    ASSERT_LE(parameter_space(six).size(), kPopulationAbove);
    const SearchResult lattice = search(ctx(), six, SearchMethod::Auto).result;
    EXPECT_FALSE(lattice.population);
    EXPECT_EQ(lattice.stages[0].name, "explore");
}

// 25 free heights (beyond kCmaesFirstUpTo): auto's first run is Levenberg-Marquardt's
// (explore at the first ray count with the grid's modes freed by degree, polish at the
// scene's); on this target it polishes to the noise, so no CMA-ES run follows.
TEST_F(PopulationRules, AutoBeyondSixteenFreeParametersRunsLevenbergFirst) {
    Scene s = scene("freeform_search_5x5.toml");
    ASSERT_EQ(parameter_space(s).size(), 25u);
    static_assert(25 > kCmaesFirstUpTo);
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population && r.levenberg);
    expect_one_run_polished_to_the_noise(r, 1);
    EXPECT_EQ(r.population->runs[0].method, "levenberg");
    ASSERT_EQ(r.stages.size(), 2u);
    EXPECT_EQ(r.stages[0].name, "explore");
    EXPECT_EQ(r.stages[0].fidelity.rays, 5000u);
    EXPECT_EQ(r.stages[1].fidelity.rays, 20000u);
    // The 5 x 5 grid's 25 modes, the finest of degree 4 + 4.
    EXPECT_EQ(r.levenberg->modes, 25u);
    EXPECT_EQ(r.levenberg->degree, 8u);
}

// Heights held within a millimetre of the flat start, where the target tilts by 8 mm across
// the holder (-10 mm on the first column of the grid, -2 on the last): no run can polish
// the far field down to what noise explains, so auto starts again while the budget holds
// another run. The search's best is the best polish of all of them (each polished at the
// scene's rays, the same rays: comparable).
Scene freeform_the_box_cannot_reach(const Scene& freeform) {
    Scene s = freeform;
    const int last = int(s.reflector.bspline.nx) - 1;
    for (auto& [name, range] : s.reflector.optimize) // h_<i>_<j>, as heights_mm frees them
        range = {-7.0, -5.0, 0.5};
    for (auto& [name, h] : s.target.parameters) // h_<i>_<j>
        h = -10.0 + 8.0 * double(name[2] - '0') / last;
    return s;
}

// The order of auto's runs by the number of free parameters (kCmaesFirstUpTo): up to it
// CMA-ES's, then one Levenberg-Marquardt run; beyond, kLevenbergRuns Levenberg-Marquardt runs
// (one with a single stage), then CMA-ES's. kPopulationRuns in all where the budget holds them.
std::vector<std::string> auto_runs(std::size_t n, std::size_t stages) {
    std::vector<std::string> runs(kPopulationRuns, "cmaes");
    if (n <= kCmaesFirstUpTo)
        runs.back() = "levenberg";
    else
        for (std::uint32_t k = 0; k < (stages > 1 ? kLevenbergRuns : 1); ++k)
            runs[k] = "levenberg";
    return runs;
}

// Beyond kCmaesFirstUpTo parameters, the last Levenberg-Marquardt run's polish, above the
// noise, is followed by long steps: rounds of candidates, each the round's start (the stage's
// best) with one parameter alone moved by a share of its box either way (kLongStepsOfBox,
// onto its lattice), every parameter moved in every round; a round whose best beats its
// start is polished again (Levenberg-Marquardt: its candidates move many heights at once)
// and the next round starts from the stage's new best. Read from the history alone, the
// rounds and their gains agree with the report of run `run_index` (its polish `polish_name`).
void expect_long_steps(const SearchResult& r, const Scene& s, std::size_t run_index,
                       const std::string& polish_name) {
    const ParameterSpace space = parameter_space(s);
    const std::size_t n = space.size();
    ASSERT_LT(run_index, r.population->runs.size());
    const auto& run = r.population->runs[run_index];
    ASSERT_EQ(run.method, "levenberg");
    ASSERT_GT(run.polished, run.noise_limit);
    const auto polish = named(r, polish_name);
    ASSERT_NE(polish, r.stages.end());
    const auto stage = std::size_t(polish - r.stages.begin());
    EXPECT_EQ(run.polished, polish->best_score);
    // The values a long step gives parameter k from x (either way, each share of its box).
    const auto long_steps_of = [&](const std::vector<double>& x, std::size_t k) {
        std::set<double> to;
        for (const double share : kLongStepsOfBox)
            for (const double sign : {1.0, -1.0}) {
                std::vector<double> y = x;
                y[k] = std::clamp(x[k] + sign * share * (space.hi[k] - space.lo[k]), space.lo[k],
                                  space.hi[k]);
                if (const double v = space.snap(y)[k]; v != x[k]) to.insert(v);
            }
        return to;
    };
    // The one parameter c moves from x by a long step, if it does.
    const auto long_step = [&](const std::vector<double>& x,
                               const Candidate& c) -> std::optional<std::size_t> {
        std::optional<std::size_t> moved;
        for (std::size_t k = 0; k < n; ++k)
            if (c.x[k] != x[k]) {
                if (moved || !long_steps_of(x, k).count(c.x[k])) return std::nullopt;
                moved = k;
            }
        return moved;
    };
    struct Round {
        std::vector<double> from;
        double from_score = 0.0;
        double best = HUGE_VAL;
        std::size_t candidates = 0;
        std::size_t after = 0; // the polish's candidates after it
        // The stage's points traced by the round's end (a point traced before in the stage
        // is answered from its memo, not traced again).
        std::set<std::vector<double>> traced;
    };
    std::vector<Round> rounds;
    std::optional<std::size_t> best; // the stage's best so far (a history index)
    bool in_round = false;
    std::set<std::vector<double>> traced;
    for (const Candidate& c : r.history) {
        if (c.stage != stage) continue;
        if (in_round) rounds.back().traced = traced;
        traced.insert(c.x);
        if (best) {
            const std::vector<double>& from = in_round ? rounds.back().from : r.history[*best].x;
            if (const auto k = long_step(from, c)) {
                if (!in_round)
                    rounds.push_back({.from = from, .from_score = r.history[*best].score});
                in_round = true;
                ++rounds.back().candidates;
                rounds.back().best = std::min(rounds.back().best, c.score);
            } else {
                in_round = false;
                if (!rounds.empty()) ++rounds.back().after;
            }
        }
        if (c.feasible && (!best || c.score < r.history[*best].score)) best = c.index;
    }
    if (in_round) rounds.back().traced = traced;
    ASSERT_FALSE(rounds.empty()) << "no long steps after a polish above the noise";
    ASSERT_LE(rounds.size(), std::size_t(kLongStepRounds));
    // The rounds start from the best polish of every run: the earlier runs' (all
    // Levenberg-Marquardt's, with the same rays in their polish) traced again here.
    for (std::size_t k = 0; k < run_index; ++k)
        EXPECT_LE(rounds[0].from_score, r.population->runs[k].polished) << k;
    std::uint32_t gained = 0;
    for (std::size_t k = 0; k < rounds.size(); ++k) {
        const Round& round = rounds[k];
        // Every parameter's every long step from the round's start traced by its end.
        for (std::size_t p = 0; p < n; ++p)
            for (const double v : long_steps_of(round.from, p)) {
                std::vector<double> y = round.from;
                y[p] = v;
                EXPECT_TRUE(round.traced.count(y)) << "round " << k << ", parameter " << p;
            }
        EXPECT_LE(round.candidates, n * 2 * std::size(kLongStepsOfBox)) << k;
        const bool gain = round.best < round.from_score;
        gained += gain ? 1u : 0u;
        // Polished again after a gain, and only then; the polish keeps the round's best.
        EXPECT_EQ(round.after > 0, gain) << k;
        if (gain) {
            EXPECT_LE(polish->best_score, round.best) << k;
        } else {
            EXPECT_EQ(k + 1, rounds.size()) << "no round after one that did not gain";
        }
    }
    EXPECT_EQ(run.long_steps, gained);
    // A round follows each gain until kLongStepRounds.
    if (gained < kLongStepRounds) {
        EXPECT_EQ(rounds.size(), gained + 1u);
    }
}

class AutoStartsAgain : public VulkanTest, public ::testing::WithParamInterface<const char*> {};

TEST_P(AutoStartsAgain, WhileThePolishedBestIsAboveTheNoise) {
    Scene s = freeform_the_box_cannot_reach(scene(GetParam()));
    s.optimize.max_evaluations = 12000;
    const std::size_t n = parameter_space(s).size();
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population && r.levenberg && r.best);
    const auto& runs = r.population->runs;
    // The budget holds every run here.
    ASSERT_EQ(runs.size(), std::size_t(kPopulationRuns)) << r.population->verdict;
    static_assert(kLevenbergRuns < kPopulationRuns);
    const std::vector<std::string> order = auto_runs(n, 2);
    std::uint64_t candidates = 0;
    std::vector<std::string> levenberg_explores, cmaes_explores; // their explore stages
    std::set<std::uint32_t> generators;                          // the CMA-ES runs' streams
    for (std::size_t k = 0; k < runs.size(); ++k) {
        candidates += runs[k].candidates;
        EXPECT_GT(runs[k].noise_limit, 0.0) << k;
        EXPECT_EQ(runs[k].method, order[k]) << k;
        if (k + 1 < runs.size()) {
            EXPECT_GT(runs[k].polished, runs[k].noise_limit) << k;
        }
        const std::string explore = k == 0 ? "explore" : "explore " + std::to_string(k + 1);
        ASSERT_NE(named(r, explore), r.stages.end()) << explore;
        ASSERT_NE(named(r, k == 0 ? "polish" : "polish " + std::to_string(k + 1)), r.stages.end())
            << k;
        if (runs[k].method == "levenberg") {
            levenberg_explores.push_back(explore);
        } else {
            cmaes_explores.push_back(explore);
            generators.insert(runs[k].seed);
        }
    }
    // Every candidate belongs to a reported run.
    EXPECT_EQ(candidates, r.history.size()) << r.population->verdict;
    ASSERT_FALSE(levenberg_explores.empty());
    ASSERT_FALSE(cmaes_explores.empty());
    // Each CMA-ES run its own generator; their coarse stages the scene's first rays.
    EXPECT_EQ(generators.size(), cmaes_explores.size());
    const std::uint64_t coarse_seed = r.stages[0].fidelity.seed;
    for (const std::string& explore : cmaes_explores)
        EXPECT_EQ(named(r, explore)->fidelity.seed, coarse_seed) << explore;
    // Levenberg-Marquardt's first run: those rays too, at the same count (its far field the
    // scene's grid, where CMA-ES's is the stage's coarse one).
    const auto first = named(r, levenberg_explores[0]);
    EXPECT_EQ(first->fidelity.seed, coarse_seed);
    EXPECT_EQ(first->fidelity.rays, named(r, cmaes_explores[0])->fidelity.rays);
    EXPECT_NE(first->fidelity.farfield_w, named(r, cmaes_explores[0])->fidelity.farfield_w);
    // Its later runs (beyond kCmaesFirstUpTo): their coarse stage's rays other streams', at
    // the same count and grid; other rays, another path: they end at other points.
    for (std::size_t k = 1; k < levenberg_explores.size(); ++k) {
        Fidelity other = named(r, levenberg_explores[k])->fidelity;
        for (std::size_t j = 0; j < k; ++j)
            EXPECT_NE(other.seed, named(r, levenberg_explores[j])->fidelity.seed) << k << j;
        other.seed = first->fidelity.seed;
        EXPECT_EQ(other, first->fidelity) << k;
        ASSERT_TRUE(named(r, levenberg_explores[k])->best && first->best);
        EXPECT_NE(r.history[*named(r, levenberg_explores[k])->best].x, r.history[*first->best].x)
            << k;
    }
    EXPECT_EQ(r.population->algorithm, "cmaes");
    // Every polish at the scene's fidelity, the same rays.
    const Fidelity scene_fidelity = named(r, "polish")->fidelity;
    for (std::size_t k = 1; k < runs.size(); ++k)
        EXPECT_EQ(named(r, "polish " + std::to_string(k + 1))->fidelity, scene_fidelity) << k;
    // The best: the lowest score of the stages at the scene's fidelity (the polishes', and
    // CMA-ES's last stage), whichever run.
    double lowest = HUGE_VAL;
    for (const StageSummary& st : r.stages)
        if (st.best && st.fidelity == scene_fidelity) lowest = std::min(lowest, st.best_score);
    EXPECT_EQ(r.best_score, lowest);
    double polished = HUGE_VAL;
    for (const auto& run : runs)
        polished = std::min(polished, run.polished);
    EXPECT_EQ(r.best_score, polished);
    // Long steps after the last Levenberg-Marquardt run beyond kCmaesFirstUpTo, none else.
    const auto last_levenberg = std::size_t(
        std::find(order.rbegin(), order.rend(), "levenberg").base() - order.begin() - 1);
    for (std::size_t k = 0; k < runs.size(); ++k)
        if (k != last_levenberg || n <= kCmaesFirstUpTo) {
            EXPECT_EQ(runs[k].long_steps, 0u) << k;
        }
    if (n > kCmaesFirstUpTo)
        expect_long_steps(r, s, last_levenberg, "polish " + std::to_string(last_levenberg + 1));
}

INSTANTIATE_TEST_SUITE_P(ByFreeParameters, AutoStartsAgain,
                         ::testing::Values("freeform_search.toml", "freeform_search_5x5.toml"),
                         [](const auto& p) {
                             return std::string(p.param) == "freeform_search.toml" ? "Nine"
                                                                                   : "TwentyFive";
                         });

// With one stage (one ray count) there are no coarse rays to draw again: a second
// Levenberg-Marquardt run would repeat the first, so there is one. Nine parameters: three
// CMA-ES runs, then it; 25: it, then CMA-ES.
TEST_F(PopulationRules, AutoWithOneStageRunsLevenbergMarquardtOnce) {
    for (const auto& [name, budget] :
         {std::pair{"freeform_search.toml", 3000}, std::pair{"freeform_search_5x5.toml", 2000}}) {
        Scene s = freeform_the_box_cannot_reach(scene(name));
        s.optimize.rays = {20000};
        s.optimize.max_evaluations = std::uint64_t(budget);
        const std::size_t n = parameter_space(s).size();
        const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
        ASSERT_TRUE(r.population) << name;
        const auto& runs = r.population->runs;
        const std::vector<std::string> order = auto_runs(n, 1);
        // Far enough to see the order: every run up to the Levenberg-Marquardt one and
        // one after it, or all of them.
        const auto levenberg =
            std::size_t(std::find(order.begin(), order.end(), "levenberg") - order.begin());
        ASSERT_GE(runs.size(), std::min(levenberg + 2, order.size()))
            << name << ": " << r.population->verdict;
        for (std::size_t k = 0; k < runs.size(); ++k)
            EXPECT_EQ(runs[k].method, order[k]) << name << " " << k;
        EXPECT_EQ(std::count(order.begin(), order.end(), "levenberg"), 1);
    }
}

// Ctrl-C in the middle of a later run of auto (its coarse stage): resumed from that history,
// the search replays the recorded candidates and ends exactly where the uninterrupted one
// does. Nine parameters: in the Levenberg-Marquardt run after three CMA-ES runs; 25: in the
// second Levenberg-Marquardt run, whose coarse rays are another stream's.
struct InterruptedRun {
    const char* scene;
    std::uint64_t max_evaluations;
    std::size_t run; // from 0
};

class AutoInterrupted : public VulkanTest, public ::testing::WithParamInterface<InterruptedRun> {};

TEST_P(AutoInterrupted, InALaterRunAndResumedEndsWhereTheUninterruptedOneDoes) {
    Scene s = freeform_the_box_cannot_reach(scene(GetParam().scene));
    ASSERT_EQ(auto_runs(parameter_space(s).size(), 2)[GetParam().run], "levenberg");
    s.optimize.max_evaluations = GetParam().max_evaluations;
    const std::string stage = "explore " + std::to_string(GetParam().run + 1);
    const auto whole = search(ctx(), s, SearchMethod::Auto).result;
    std::optional<std::uint64_t> cut_at;
    for (const Candidate& c : whole.history)
        if (whole.stages[c.stage].name == stage) {
            cut_at = c.index + 60; // within its first Jacobian's batch or just after
            break;
        }
    ASSERT_TRUE(cut_at) << whole.population->verdict;
    ASSERT_LT(*cut_at, whole.history.size());
    ASSERT_EQ(whole.stages[whole.history[*cut_at].stage].name, stage);
    SearchControl control;
    const auto cut = search(ctx(), s, SearchMethod::Auto, &control, {},
                            [&](const Candidate& c, const StageSummary&) {
                                if (c.index == *cut_at) control.stop = true;
                            })
                         .result;
    EXPECT_EQ(cut.stopped, StopReason::Interrupted);
    ASSERT_GT(cut.history.size(), *cut_at);
    // The report names the run cut short, not its last complete stage's verdict.
    ASSERT_TRUE(cut.population);
    EXPECT_EQ(cut.population->runs.size(), GetParam().run);
    const std::string verdict = "run " + std::to_string(GetParam().run + 1) +
                                " (levenberg) stopped (interrupted) in its stage " + stage;
    EXPECT_EQ(cut.population->verdict.rfind(verdict, 0), 0u) << cut.population->verdict;
    const auto resumed = search(ctx(), s, SearchMethod::Auto, nullptr, cut.history).result;
    expect_resumed_is_whole(resumed, whole, cut.history.size());
    ASSERT_TRUE(resumed.population && whole.population);
    ASSERT_EQ(resumed.population->runs.size(), whole.population->runs.size());
    for (std::size_t k = 0; k < whole.population->runs.size(); ++k)
        EXPECT_EQ(resumed.population->runs[k].polished, whole.population->runs[k].polished) << k;
    EXPECT_EQ(resumed.best_score, whole.best_score);
}

INSTANTIATE_TEST_SUITE_P(ByFreeParameters, AutoInterrupted,
                         ::testing::Values(InterruptedRun{"freeform_search.toml", 6000, 3},
                                           InterruptedRun{"freeform_search_5x5.toml", 2000, 1}),
                         [](const auto& p) {
                             return std::string(p.param.scene) == "freeform_search.toml"
                                        ? "Nine"
                                        : "TwentyFive";
                         });

// A start the request gives, marked tailored (fird optimize --start tailored): the search
// begins there (history row 0), reports it, and auto traces it again first in its polish
// stage, so its best there is never above the start's l2 at that stage's fidelity (the
// coarse stage's noise may carry the search away from it).
TEST_F(PopulationRules, ATailoredStartIsRowZeroAndTracedAgainInThePolish) {
    Scene s = scene("freeform_search.toml");
    s.optimize.max_evaluations = 3000;
    const ParameterSpace space = parameter_space(s);
    std::vector<double> start(space.size());
    for (std::size_t k = 0; k < space.size(); ++k)
        start[k] = 0.5 * (space.lo[k] + space.hi[k]);
    start = space.snap(start);
    SearchRequest request{.settings = search_settings(s), .start = start};
    request.start_report.kind = "tailored";
    const SearchResult r = run_search(ctx(), s, request).result;
    ASSERT_TRUE(r.population);
    const auto polish_stage = named(r, "polish");
    ASSERT_NE(polish_stage, r.stages.end());
    const std::uint32_t polish_index = std::uint32_t(polish_stage - r.stages.begin());
    EXPECT_EQ(r.start.kind, "tailored");
    EXPECT_EQ(r.start.parameters, space.named(start));
    ASSERT_TRUE(r.start_l2_lm);
    EXPECT_EQ(r.history.front().x, start);
    const auto polish = std::find_if(r.history.begin(), r.history.end(),
                                     [&](const Candidate& c) { return c.stage == polish_index; });
    ASSERT_NE(polish, r.history.end());
    EXPECT_EQ(polish->x, start);
    ASSERT_TRUE(r.best);
    EXPECT_LE(r.best_l2_lm, polish->l2_lm);
}

// With a smoothness weight a generation's bending energies are measured on host threads
// while the device traces the batch (Objective::evaluate_all): each recorded energy is the
// candidate's own, measured here one at a time after the search from its parameters
// (press_measures.hpp), to the bit.
TEST_F(PopulationRules, AGenerationsBendingEnergiesAreEachCandidatesMeasuredAlone) {
    Scene s = scene("profile_dish.toml");
    s.trace.rays = 5000;
    s.trace.heightfield_w = s.trace.heightfield_h = 100;
    s.optimize.smoothness = 1.0;
    s.optimize.max_evaluations = 60;
    s.target.kind = TargetDesc::Kind::Reflector;
    s.target.parameters = {{"h_2", 1.0}};
    // Traced in batches (as AGenerationIsTracedAsOneBatch... counts them): the device's
    // submission count takes far fewer values over the candidates than there are candidates.
    std::set<std::uint64_t> submissions;
    std::size_t traced = 0;
    const SearchResult r = search(ctx(), s, SearchMethod::Cmaes, nullptr, {},
                                  [&](const Candidate& c, const StageSummary&) {
                                      if (!c.feasible) return;
                                      ++traced;
                                      submissions.insert(ctx().submissions());
                                  })
                               .result;
    ASSERT_TRUE(r.population);
    ASSERT_GE(r.population->generations, 3u);
    EXPECT_LT(submissions.size(), traced / 3) << "one submission per candidate: " << traced;
    const ParameterSpace space = parameter_space(s);
    std::set<double> energies;
    std::size_t feasible = 0;
    for (const Candidate& c : r.history) {
        if (!c.feasible) continue;
        ++feasible;
        const Scene alone = space.candidate(s, c.x);
        const double energy = search_bending_energy(Surface::make(alone.reflector, alone.holder));
        EXPECT_EQ(c.smoothness, energy) << c.index;
        EXPECT_EQ(c.score, c.l2_lm + s.optimize.smoothness * energy) << c.index;
        energies.insert(energy);
    }
    EXPECT_GT(feasible, 2 * r.population->size);
    EXPECT_GT(energies.size(), r.population->size) << "the candidates' shapes differ";
}

// A freeform start from one number: heights_mm = -6 starts all nine heights there, each
// free parameter h_<i>_<j> starts at it, and the target's heights are the ones it names.
TEST(PopulationModel, HeightsMmFreesEveryControlHeightByName) {
    const Scene s = scene("freeform_search.toml");
    const ParameterSpace space = parameter_space(s);
    const std::vector<std::string> names{"h_0_0", "h_0_1", "h_0_2", "h_1_0", "h_1_1",
                                         "h_1_2", "h_2_0", "h_2_1", "h_2_2"};
    EXPECT_EQ(space.names, names);
    for (double h : s.reflector.bspline.heights_mm)
        EXPECT_EQ(h, -6.0);
    for (std::size_t k = 0; k < space.size(); ++k) {
        EXPECT_EQ(space.start[k], -6.0) << names[k];
        EXPECT_EQ(space.lo[k], -10.0);
        EXPECT_EQ(space.hi[k], -2.0);
        EXPECT_EQ(space.step[k], 0.5);
    }
    // h_2_1 is column 2, row 1: the control height at index 1 * nx + 2 of the grid.
    const ReflectorDesc target = target_reflector(s);
    const std::vector<double> h = bspline_heights(target.bspline, target.parameters);
    EXPECT_EQ(h[1 * 3 + 2], -6.0); // h_2_1
    EXPECT_EQ(h[2 * 3 + 1], -6.5); // h_1_2
    EXPECT_EQ(h[0], -3.0);         // h_0_0
}

} // namespace
} // namespace fird::test
