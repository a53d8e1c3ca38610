// The press's constraints in a search: a candidate that breaks one is infeasible exactly as
// one that cuts the source (counted, never traced), the reason names the constraint, the
// result says whether it holds the optimum, and a limit nothing in the box meets is refused
// before any trace. The mirror's slope is analytic: atan(hypot(sx, sy)) everywhere.
#include <cmath>
#include <numbers>

#include "optimize/objective.hpp"
#include "optimize/parameter_space.hpp"
#include "optimize/press_constraints.hpp"
#include "search_fixture.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

double mirror_slope_deg(double sx, double sy) {
    return std::atan(std::hypot(sx, sy)) * kDeg;
}

TEST(PressConstraints, ACandidateBreakingOneIsInfeasibleNamingIt) {
    Scene s = scene("mirror_search.toml");
    s.reflector.constraints.max_slope_deg = 8.0;
    ReflectorDesc steep = s.reflector;
    steep.parameters["sx"] = 0.15;
    steep.parameters["sy"] = -0.1;
    const Feasibility f = candidate_feasibility(s, steep);
    EXPECT_FALSE(f.feasible);
    EXPECT_EQ(f.constraint, "max_slope_deg");
    EXPECT_NE(f.reason.find("[reflector.constraints] max_slope_deg"), std::string::npos)
        << f.reason;
    // Broken by (10.2 - 8) / 8 of the limit: the penalty's scale.
    EXPECT_NEAR(f.violation, (mirror_slope_deg(0.15, -0.1) - 8.0) / 8.0, 1e-9);
    ReflectorDesc gentle = steep;
    gentle.parameters["sx"] = 0.1;
    gentle.parameters["sy"] = -0.05;
    EXPECT_TRUE(candidate_feasibility(s, gentle).feasible);
}

// Every corner of the box (and its start and centre) is steeper than 5 degrees: refused in
// one line naming the key, without a Vulkan device, before any trace.
TEST(PressConstraints, ALimitNothingInTheBoxMeetsIsRefused) {
    Scene s = scene("mirror_search.toml");
    s.reflector.optimize = {{"sx", {0.1, 0.3, 0.05}}, {"sy", {0.1, 0.3, 0.05}}};
    s.reflector.constraints.max_slope_deg = 5.0;
    try {
        refuse_unmeetable_constraints(s, parameter_space(s));
        ADD_FAILURE() << "refused nothing";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("[reflector.constraints] max_slope_deg"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    // Loosened past the gentlest corner (0.1, 0.1: 8.05 degrees), it stands.
    s.reflector.constraints.max_slope_deg = 8.1;
    EXPECT_NO_THROW(refuse_unmeetable_constraints(s, parameter_space(s)));
}

// An infeasible candidate scores above every far field the source's flux can make, in the
// scene's metric: under candela_l2 (weights up to 1 / (4 pi omega) of the polar cells), the
// worst far field - all the flux in one polar cell - lies sqrt(weight) F from an empty one,
// far beyond the flux F itself (the lumen bound), and the penalty must stay above it.
TEST_F(VulkanTest, AnInfeasibleCandidateScoresAboveAnyFarFieldInTheSearchsMetric) {
    for (const FarFieldMetric metric : {FarFieldMetric::L2, FarFieldMetric::CandelaL2}) {
        Scene s = scene("mirror_search.toml");
        s.optimize.metric = metric;
        const Fidelity fid = scene_fidelity(s);
        const std::size_t cells = std::size_t(fid.farfield_w) * fid.farfield_h;
        // A desired far field of half the flux spread evenly.
        const FarField desired{fid.farfield_w, fid.farfield_h,
                               std::vector<double>(cells, 0.5 * s.source.flux_lm / double(cells))};
        Objective f(ctx(), s, parameter_space(s), desired, SearchSettings{}, nullptr, {}, {});
        f.begin_stage("s", fid);
        FarField worst{fid.farfield_w, fid.farfield_h, std::vector<double>(cells, 0.0)};
        worst.lm[0] = s.source.flux_lm; // a cell of the first (polar) row
        const FarField empty{fid.farfield_w, fid.farfield_h, std::vector<double>(cells, 0.0)};
        const double penalty = f.penalty(Feasibility{.feasible = false});
        EXPECT_GT(penalty, farfield_distance(worst, desired, metric)) << metric_name(metric);
        EXPECT_GT(penalty, farfield_distance(empty, desired, metric)) << metric_name(metric);
    }
}

using PressSearch = VulkanTest;

// The grid over the mirror's 13 x 13 lattice with the slope held to 8 degrees: exactly the
// lattice points steeper than that are infeasible and untraced, the target (10.2 degrees)
// is out of reach, and the limit holds the optimum: a point one step away breaks it.
TEST_F(PressSearch, TheGridNeverTracesASteeperCandidateAndTheLimitIsActiveAtItsBest) {
    Scene s = scene("mirror_search.toml");
    s.reflector.constraints.max_slope_deg = 8.0;
    s.trace.rays = 5000;
    // The search itself refuses the unmeetable limit before its first trace.
    Scene unmeetable = s;
    unmeetable.reflector.optimize = {{"sx", {0.1, 0.3, 0.05}}, {"sy", {0.1, 0.3, 0.05}}};
    unmeetable.reflector.constraints.max_slope_deg = 5.0;
    EXPECT_THROW((void)search(ctx(), unmeetable, SearchMethod::Grid), std::invalid_argument);
    const SearchResult r = search(ctx(), s, SearchMethod::Grid).result;
    ASSERT_EQ(r.history.size(), 169u);
    std::uint64_t steep = 0;
    for (const Candidate& c : r.history) {
        const bool too_steep = mirror_slope_deg(c.x[0], c.x[1]) > 8.0;
        EXPECT_EQ(c.feasible, !too_steep) << c.x[0] << "," << c.x[1];
        if (too_steep) {
            ++steep;
            EXPECT_TRUE(std::isnan(c.l2_lm));
        }
    }
    EXPECT_EQ(r.infeasible, steep);
    // Only the lattice points within tan 8 deg = 0.1405 of the origin meet it: i^2 + j^2 <= 7
    // in steps of 0.05, 21 of the 169.
    EXPECT_EQ(steep, 169u - 21u);
    ASSERT_TRUE(r.best);
    const std::vector<double>& best = r.history[*r.best].x;
    EXPECT_LE(mirror_slope_deg(best[0], best[1]), 8.0);
    ASSERT_EQ(r.constraints.size(), 1u);
    const ConstraintAtOptimum& c = r.constraints[0];
    EXPECT_EQ(c.name, "max_slope_deg");
    EXPECT_TRUE(c.met);
    EXPECT_NEAR(c.value, mirror_slope_deg(best[0], best[1]), 1e-9);
    EXPECT_EQ(c.limit, 8.0);
    EXPECT_TRUE(c.active) << "best " << best[0] << "," << best[1];
    EXPECT_FALSE(c.active_by.empty());
}

} // namespace
} // namespace fird::test
