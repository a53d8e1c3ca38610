// Population searches on pagmo2 (--method cmaes, xnes; auto beyond six free parameters):
// they recover the analytic optimum of the mirror search; a generation is traced as one
// batch with each candidate's l2 the one it has traced alone; the same seed gives the same
// history and another seed another; a search interrupted mid-generation and resumed ends
// where the uninterrupted one does; auto chooses CMA-ES only beyond six free parameters.
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>

#include "evaluation/evaluator.hpp"
#include "io/scene_file.hpp"
#include "model/surface.hpp"
#include "optimize/methods.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/search.hpp"
#include "search_fixture.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

class Population : public VulkanTest, public ::testing::WithParamInterface<SearchMethod> {};

// The mirror's l2 falls smoothly towards the target's slopes (on the lattice) from anywhere
// in the box: the population ends within one step of them in every parameter, at the noise.
TEST_P(Population, RecoversTheMirrorsSlopesWithinOneStep) {
    const Scene s = scene("mirror_search.toml");
    const SearchResult r = search(ctx(), s, GetParam()).result;
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

// Nine free heights (more than six): auto's first run is Levenberg-Marquardt (explore at
// the first ray count with the grid's modes freed by degree, polish at the scene's), with
// no lattice verdict; on this target it polishes to the noise, so no CMA-ES run follows.
// The plane's three (its slopes and height) stay with DIRECT and the lattice.
TEST_F(PopulationRules, AutoSearchesWithLevenbergBeyondSixFreeParameters) {
    Scene s = scene("freeform_search.toml");
    ASSERT_EQ(parameter_space(s).size(), 9u);
    s.optimize.max_evaluations = 3000;
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population && r.levenberg);
    ASSERT_EQ(r.population->runs.size(), 1u) << r.population->verdict;
    EXPECT_EQ(r.population->runs[0].method, "levenberg");
    EXPECT_EQ(r.stopped, StopReason::Converged);
    ASSERT_EQ(r.stages.size(), 2u);
    EXPECT_EQ(r.stages[0].name, "explore");
    EXPECT_EQ(r.stages[1].name, "polish");
    EXPECT_EQ(r.stages[0].fidelity.rays, 5000u);
    EXPECT_EQ(r.stages[1].fidelity.rays, 20000u);
    // The 3 x 3 grid's nine modes, the finest of degree 2 + 2.
    EXPECT_EQ(r.levenberg->modes, 9u);
    EXPECT_EQ(r.levenberg->degree, 4u);
    EXPECT_EQ(r.population->runs[0].polished, r.stages[1].best_score);
    EXPECT_LE(r.population->runs[0].polished, r.population->runs[0].before_polish);
    EXPECT_LE(r.population->runs[0].polished, r.population->runs[0].noise_limit);
    EXPECT_FALSE(r.lattice);
    ASSERT_TRUE(r.best && r.start_l2_lm && r.final_l2_lm && r.noise_floor_l2_lm);
    EXPECT_LT(r.best_l2_lm, *r.start_l2_lm);
    // At the noise (1.2: as RecoversTheSmallFreeformToTheNoise).
    EXPECT_LE(*r.final_l2_lm, 1.2 * *r.noise_floor_l2_lm);

    Scene six = scene("mirror_search.toml");
    six.reflector.optimize["z0"] = {-4.0, 0.0, 0.5};
    six.optimize.max_evaluations = 30;
    ASSERT_LE(parameter_space(six).size(), kPopulationAbove);
    const SearchResult lattice = search(ctx(), six, SearchMethod::Auto).result;
    EXPECT_FALSE(lattice.population);
    EXPECT_EQ(lattice.stages[0].name, "explore");
}

// Heights held within a millimetre of the flat start, where the target tilts by 8 mm across
// the holder: no run can polish the far field down to what noise explains, so auto starts
// again while the budget holds another run: Levenberg-Marquardt with the coarse stage's
// rays of another stream (kLevenbergRuns in all), then CMA-ES with the generator's next
// stream; the search's best is the best polish of all of them (each polished at the
// scene's rays, the same rays: comparable).
Scene freeform_the_box_cannot_reach(const Scene& freeform) {
    Scene s = freeform;
    for (auto& [name, range] : s.reflector.optimize) // h_<i>_<j>, as heights_mm frees them
        range = {-7.0, -5.0, 0.5};
    for (auto& [name, h] : s.target.parameters) // h_<i>_<j>: -10, -6, -2 along x
        h = -10.0 + 4.0 * double(name[2] - '0');
    return s;
}

TEST_F(PopulationRules, AutoStartsAgainWhileThePolishedBestIsAboveTheNoise) {
    Scene s = freeform_the_box_cannot_reach(scene("freeform_search.toml"));
    s.optimize.max_evaluations = 6000;
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population && r.levenberg && r.best);
    const auto& runs = r.population->runs;
    // The budget holds every run here: the Levenberg-Marquardt runs, then a CMA-ES one.
    ASSERT_EQ(runs.size(), std::size_t(kPopulationRuns)) << r.population->verdict;
    static_assert(kLevenbergRuns < kPopulationRuns);
    std::uint64_t candidates = 0;
    for (std::size_t k = 0; k < runs.size(); ++k) {
        candidates += runs[k].candidates;
        EXPECT_GT(runs[k].noise_limit, 0.0) << k;
        EXPECT_EQ(runs[k].method, k < kLevenbergRuns ? "levenberg" : "cmaes") << k;
        if (k + 1 < runs.size()) {
            EXPECT_GT(runs[k].polished, runs[k].noise_limit) << k;
        }
    }
    // Every candidate belongs to a reported run.
    EXPECT_EQ(candidates, r.history.size()) << r.population->verdict;
    // Stage names carry the run: explore, refine, polish, explore 2, ...
    const auto named = [&](const std::string& name) {
        return std::find_if(r.stages.begin(), r.stages.end(),
                            [&](const StageSummary& st) { return st.name == name; });
    };
    ASSERT_NE(named("explore"), r.stages.end());
    ASSERT_NE(named("explore 2"), r.stages.end());
    ASSERT_NE(named("polish 2"), r.stages.end());
    // A second Levenberg-Marquardt run: its coarse stage's rays another stream's, at the
    // same count and grid; its polish the scene's rays, as the first's.
    Fidelity other = named("explore 2")->fidelity;
    EXPECT_NE(other.seed, named("explore")->fidelity.seed);
    other.seed = named("explore")->fidelity.seed;
    EXPECT_EQ(other, named("explore")->fidelity);
    EXPECT_EQ(named("polish 2")->fidelity, named("polish")->fidelity);
    ASSERT_NE(named("explore 3"), r.stages.end());
    EXPECT_NE(named("explore 3")->fidelity.seed, named("explore 2")->fidelity.seed);
    EXPECT_NE(named("explore 3")->fidelity.seed, named("explore")->fidelity.seed);
    // Other rays, another path: the runs' coarse stages end at other points.
    ASSERT_TRUE(named("explore 2")->best && named("explore")->best);
    EXPECT_NE(r.history[*named("explore 2")->best].x, r.history[*named("explore")->best].x);
    // The CMA-ES run's coarse stage: the first run's rays (the stages' own streams; its far
    // field the stage's coarse grid, where Levenberg-Marquardt judges on the scene's).
    const std::string cmaes_explore = "explore " + std::to_string(kLevenbergRuns + 1);
    ASSERT_NE(named(cmaes_explore), r.stages.end());
    EXPECT_EQ(named(cmaes_explore)->fidelity.seed, named("explore")->fidelity.seed);
    EXPECT_EQ(named(cmaes_explore)->fidelity.rays, named("explore")->fidelity.rays);
    EXPECT_EQ(r.population->algorithm, "cmaes");
    EXPECT_EQ(r.population->size, 10u); // 4 + floor(3 ln 9)
    // The best: the lowest score of the stages at the scene's fidelity (the polishes'),
    // whichever run.
    ASSERT_NE(named("polish"), r.stages.end());
    const Fidelity scene_fidelity = named("polish")->fidelity;
    double lowest = HUGE_VAL;
    for (const StageSummary& st : r.stages)
        if (st.best && st.fidelity == scene_fidelity) lowest = std::min(lowest, st.best_score);
    EXPECT_EQ(r.best_score, lowest);
    double polished = HUGE_VAL;
    for (const auto& run : runs)
        polished = std::min(polished, run.polished);
    EXPECT_EQ(r.best_score, polished);
}

// With one stage (one ray count) there are no coarse rays to draw again: a second
// Levenberg-Marquardt run would repeat the first, so CMA-ES follows it.
TEST_F(PopulationRules, AutoWithOneStageFollowsLevenbergWithCmaes) {
    Scene s = freeform_the_box_cannot_reach(scene("freeform_search.toml"));
    s.optimize.rays = {20000};
    s.optimize.max_evaluations = 1500;
    const SearchResult r = search(ctx(), s, SearchMethod::Auto).result;
    ASSERT_TRUE(r.population);
    const auto& runs = r.population->runs;
    ASSERT_GE(runs.size(), 2u) << r.population->verdict;
    EXPECT_EQ(runs[0].method, "levenberg");
    for (std::size_t k = 1; k < runs.size(); ++k)
        EXPECT_EQ(runs[k].method, "cmaes") << k;
}

// Ctrl-C in the middle of auto's second Levenberg-Marquardt run (its coarse stage, whose
// rays are another stream's): resumed from that history, the search replays the recorded
// candidates and ends exactly where the uninterrupted one does.
TEST_F(PopulationRules, AutoInterruptedInItsSecondRunAndResumedEndsWhereTheUninterruptedOneDoes) {
    Scene s = freeform_the_box_cannot_reach(scene("freeform_search.toml"));
    s.optimize.max_evaluations = 6000;
    const auto whole = search(ctx(), s, SearchMethod::Auto).result;
    std::optional<std::uint64_t> cut_at;
    for (const Candidate& c : whole.history)
        if (whole.stages[c.stage].name == "explore 2") {
            cut_at = c.index + 40; // within its first Jacobian's batch or just after
            break;
        }
    ASSERT_TRUE(cut_at);
    ASSERT_LT(*cut_at, whole.history.size());
    ASSERT_EQ(whole.stages[whole.history[*cut_at].stage].name, "explore 2");
    SearchControl control;
    const auto cut = search(ctx(), s, SearchMethod::Auto, &control, {},
                            [&](const Candidate& c, const StageSummary&) {
                                if (c.index == *cut_at) control.stop = true;
                            })
                         .result;
    EXPECT_EQ(cut.stopped, StopReason::Interrupted);
    ASSERT_GT(cut.history.size(), *cut_at);
    const auto resumed = search(ctx(), s, SearchMethod::Auto, nullptr, cut.history).result;
    expect_resumed_is_whole(resumed, whole, cut.history.size());
    ASSERT_TRUE(resumed.population && whole.population);
    ASSERT_EQ(resumed.population->runs.size(), whole.population->runs.size());
    for (std::size_t k = 0; k < whole.population->runs.size(); ++k)
        EXPECT_EQ(resumed.population->runs[k].polished, whole.population->runs[k].polished) << k;
    EXPECT_EQ(resumed.best_score, whole.best_score);
}

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
    ASSERT_GE(r.stages.size(), 2u);
    EXPECT_EQ(r.stages[1].name, "polish");
    EXPECT_EQ(r.start.kind, "tailored");
    EXPECT_EQ(r.start.parameters, space.named(start));
    ASSERT_TRUE(r.start_l2_lm);
    EXPECT_EQ(r.history.front().x, start);
    const auto polish = std::find_if(r.history.begin(), r.history.end(),
                                     [](const Candidate& c) { return c.stage == 1; });
    ASSERT_NE(polish, r.history.end());
    EXPECT_EQ(polish->x, start);
    ASSERT_TRUE(r.best);
    EXPECT_LE(r.best_l2_lm, polish->l2_lm);
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
