// The press's measures against closed forms: a paraboloid's slope and radius of curvature
// at its apex and rim, a plane's tilt, zero curvature, area and rim walls, a cup's depth,
// Model A's rim walls; the sampling error each extreme reports bounds what a finer grid
// finds; the constraints are met or broken by their measures.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "model/press_measures.hpp"

namespace fird {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

Surface surface(Family family, std::map<std::string, double> parameters, const Holder& holder) {
    ReflectorDesc r;
    r.family = family;
    r.parameters = std::move(parameters);
    return Surface::make(r, holder);
}

// Model B's cup (a 4, b 3, p 4, h 6 about (5, -5) in its holder) with its floor at z0.
Surface model_b_cup(double z0) {
    const Holder h{{0.0, -10.0, -6.0}, {10.0, 0.0, 0.0}};
    return surface(
        Family::Cup,
        {{"a", 4.0}, {"b", 3.0}, {"p", 4.0}, {"h", 6.0}, {"z0", z0}, {"cx", 5.0}, {"cy", -5.0}}, h);
}

// A paraboloid of revolution z = z0 + r^2 / (4 f), its apex at the holder's centre and
// unclamped everywhere: slope atan(r / 2f); principal curvatures (1/2f) / (1 + (r/2f)^2)^(3/2)
// along the meridian and (1/2f) / (1 + (r/2f)^2)^(1/2) around it, so the smallest radius
// is 2f at the apex.
TEST(PressMeasures, AParaboloidsSlopeAndRadiusAtItsApexAndRimAreTheClosedForms) {
    const double f = 10.0;
    const Holder h{{-10.0, -10.0, -20.0}, {10.0, 10.0, 0.0}};
    const Surface s = surface(Family::Paraboloid,
                              {{"fx", f}, {"fy", f}, {"z0", -10.0}, {"cx", 0.0}, {"cy", 0.0}}, h);
    const PressMeasures m = press_measures(s, 201, 201, {.maps = true});
    ASSERT_TRUE(m.any_unclamped);
    // The steepest point is a corner (r = 10 sqrt 2), a sample: the slope there is exact to
    // the rounding of atan (the gradient is the family's analytic one).
    EXPECT_NEAR(m.max_slope_deg, std::atan(10.0 * std::sqrt(2.0) / (2.0 * f)) * kDeg, 1e-9);
    EXPECT_DOUBLE_EQ(std::abs(m.max_slope_at_mm.x), 10.0);
    EXPECT_DOUBLE_EQ(std::abs(m.max_slope_at_mm.y), 10.0);
    // The gradient is linear in x and y, so central differences of it are exact but for
    // rounding (1e-16 |g| / step with step 1e-3 mm: 1e-13 per mm); 1e-9 mm bounds that.
    EXPECT_NEAR(m.min_radius_mm, 2.0 * f, 1e-9);
    EXPECT_NEAR(m.min_radius_at_mm.x, 0.0, 1e-12);
    EXPECT_NEAR(m.min_radius_at_mm.y, 0.0, 1e-12);
    // The rim's middle (10, 0): slope atan(1/2), the larger curvature the one around the
    // axis. The maps are floats: 1e-6 relative bounds their rounding.
    const std::size_t rim = std::size_t(100) * 201 + 200;
    EXPECT_NEAR(m.maps.slope_deg[rim], std::atan(0.5) * kDeg, 1e-6 * 30.0);
    const double q = 10.0 / (2.0 * f);
    EXPECT_NEAR(m.maps.curvature_per_mm[rim], (1.0 / (2.0 * f)) / std::sqrt(1.0 + q * q), 1e-7);
    // The apex: flat, curvature 1/2f.
    const std::size_t apex = std::size_t(100) * 201 + 100;
    EXPECT_EQ(m.maps.slope_deg[apex], 0.0f);
    EXPECT_NEAR(m.maps.curvature_per_mm[apex], 1.0 / (2.0 * f), 1e-7);
    // Unclamped and below the holder's top everywhere: each side of the rim is one wall,
    // the side's whole length, as tall as the top above the side's lowest point (its middle,
    // z = -10 + 100 / 40).
    ASSERT_EQ(m.rim_walls.size(), 4u);
    for (const RimWall& w : m.rim_walls) {
        EXPECT_NEAR(w.length_mm, 20.0, 1e-12) << w.side;
        EXPECT_NEAR(w.height_mm, 10.0 - 2.5, 1e-12) << w.side;
    }
}

// A tilted plane: the same slope everywhere, no curvature, the depth its rise across the
// holder, the area the rectangle's over the cosine of the tilt (exact under the trapezoid
// rule, the integrand being constant).
TEST(PressMeasures, APlanesTiltAreaAndDepthAreExactAndItHasNoCurvature) {
    const Holder h{{0.0, 0.0, -20.0}, {10.0, 10.0, 0.0}};
    const Surface s = surface(
        Family::Plane, {{"z0", -10.0}, {"sx", 0.3}, {"sy", -0.4}, {"cx", 5.0}, {"cy", 5.0}}, h);
    const PressMeasures m = press_measures(s);
    EXPECT_NEAR(m.max_slope_deg, std::atan(0.5) * kDeg, 1e-12);
    EXPECT_EQ(m.slope_error_deg, 0.0);
    EXPECT_TRUE(std::isinf(m.min_radius_mm)) << m.min_radius_mm;
    EXPECT_NEAR(m.depth_mm, 2.0 * (1.5 + 2.0), 1e-12);
    EXPECT_NEAR(m.area_mm2, 100.0 * std::sqrt(1.25), 1e-9);
    EXPECT_NEAR(m.unclamped_area_mm2, m.area_mm2, 1e-9);
    // The y_min side: z = -8 + 0.3 (x - 5), lowest at x = 0: a wall 9.5 mm tall.
    ASSERT_EQ(m.rim_walls.size(), 4u);
    EXPECT_EQ(m.rim_walls[0].side, "y_min");
    EXPECT_NEAR(m.rim_walls[0].height_mm, 9.5, 1e-12);
    EXPECT_NEAR(m.rim_walls[0].length_mm, 10.0, 1e-12);
}

// Model B's cup with its floor lifted: the depth is from the floor z0 to the holder's top,
// where the clamp holds the cup's corners.
TEST(PressMeasures, ACupsDepthIsFromItsFloorToTheClampAtTheTop) {
    const Surface s = model_b_cup(-5.5);
    const PressMeasures m = press_measures(s);
    // The floor (5, -5) is a sample of the 513 x 513 grid and the corners are clamped at 0.
    EXPECT_NEAR(m.depth_mm, 5.5, 1e-12);
    // The flats of the clamp count in the area, not in the unclamped part's.
    EXPECT_GT(m.area_mm2, m.unclamped_area_mm2);
    EXPECT_GE(m.area_mm2, 100.0);
    // The rim's middles rise to z0 + 6 (5/4)^4 > 0 along x and z0 + 6 (5/3)^4 along y:
    // clamped there; the corners too: no wall anywhere.
    EXPECT_TRUE(m.rim_walls.empty());
}

// Differences of the analytic gradient on a cup of power 4 along y = cy, where the only
// curvature is along x: 12 h u^2 / a^4 / (1 + (4 h u^3 / a^4)^2)^(3/2). Each Hessian term
// errs by at most e^2 / 3 times the gradient's third derivative 24 h / a^4 (one-sided at
// the rim; e^2 / 6 inside), e a hundredth of the 0.05 mm step; the curvature takes two of
// them, each divided by a factor of at least 1.
TEST(PressMeasures, TheCurvatureByDifferencesOfTheGradientIsTheClosedForm) {
    const Holder h{{-4.0, -4.0, -10.0}, {4.0, 4.0, 10.0}};
    const double a = 4.0, hh = 2.0;
    const Surface s = surface(
        Family::Cup,
        {{"a", a}, {"b", a}, {"p", 4.0}, {"h", hh}, {"z0", 0.0}, {"cx", 0.0}, {"cy", 0.0}}, h);
    const PressMeasures m = press_measures(s, 161, 161, {.maps = true});
    const double e = 0.01 * 0.05;
    const double truncation = 2.0 * e * e / 3.0 * (24.0 * hh / std::pow(a, 4));
    for (int i = 0; i < 161; i += 8) {
        const double u = -4.0 + 0.05 * i;
        const double slope = 4.0 * hh * u * u * u / std::pow(a, 4);
        const double expect =
            12.0 * hh * u * u / std::pow(a, 4) / std::pow(1.0 + slope * slope, 1.5);
        // Floats in the map: 1e-6 relative.
        EXPECT_NEAR(m.maps.curvature_per_mm[std::size_t(80) * 161 + i], expect,
                    truncation + 1e-6 * expect)
            << u;
    }
}

// Where the extreme lies between samples (a cup's steepest and most curved points are on
// the clamp's crease, nowhere near a sample), a coarse grid's extreme plus its reported
// sampling error still bounds what a grid 16 times finer finds.
TEST(PressMeasures, TheReportedSamplingErrorBoundsWhatAFinerGridFinds) {
    const Surface s = model_b_cup(-6.0);
    const PressMeasures coarse = press_measures(s, 33, 33);
    const PressMeasures fine = press_measures(s, 513, 513);
    EXPECT_GT(coarse.slope_error_deg, 0.0);
    EXPECT_LE(fine.max_slope_deg, coarse.max_slope_deg + coarse.slope_error_deg);
    EXPECT_GE(fine.max_slope_deg, coarse.max_slope_deg - 1e-12); // a finer grid holds the coarse
    EXPECT_LE(1.0 / fine.min_radius_mm, 1.0 / coarse.min_radius_mm + coarse.curvature_error_per_mm);
    // ... and the finer grid's own error is smaller.
    EXPECT_LT(fine.slope_error_deg, coarse.slope_error_deg);
}

// Model A's paraboloid (fx 15, fy 10, z0 -12 under a holder 60 x 40, top at 0): it rises
// through the top before the x sides (z(30, 0) = 3), but at y = +-20 only where
// x^2 / 60 >= 2: a wall |x| < sqrt 120 long on each of those sides, 2 mm tall at x = 0.
// The ends are where the raw height crosses the top, linearly between samples: within a
// step (0.12 mm) of the closed form.
TEST(PressMeasures, ModelAsRimWallsAreWhereTheParaboloidStaysBelowTheTop) {
    const Scene a = load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/model_a.toml");
    ReflectorDesc r = target_reflector(a);
    const PressMeasures m = press_measures(Surface::make(r, a.holder));
    ASSERT_EQ(m.rim_walls.size(), 2u);
    for (const RimWall& w : m.rim_walls) {
        EXPECT_TRUE(w.side == "y_min" || w.side == "y_max") << w.side;
        EXPECT_NEAR(w.length_mm, 2.0 * std::sqrt(120.0), m.dx_mm) << w.side;
        EXPECT_NEAR(w.height_mm, 2.0, 1e-12) << w.side;
        EXPECT_NEAR(w.from_mm.x, -std::sqrt(120.0), m.dx_mm) << w.side;
    }
    // Its apex: the smallest radius, 2 min(fx, fy) = 20 mm (the gradient linear: exact).
    EXPECT_NEAR(m.min_radius_mm, 20.0, 1e-9);
    EXPECT_NEAR(m.depth_mm, 12.0, 1e-12);
}

// Every 8th sample is a subset of the full grid measured as there: its extremes never
// exceed the full grid's, so a limit they break the full grid breaks; and the search's
// checks give the full grid's verdict either way (a limit between the two grids' values
// is met on the coarse grid and decided on the full one).
TEST(PressMeasures, TheStridedGridIsASubsetAndTheSearchsChecksAreTheFullGrids) {
    const Surface s = model_b_cup(-6.0);
    const PressMeasures full = press_measures(s);
    const PressMeasures coarse = press_measures(s, {.stride = 8});
    EXPECT_LE(coarse.max_slope_deg, full.max_slope_deg);
    EXPECT_GE(coarse.min_radius_mm, full.min_radius_mm);
    EXPECT_LE(coarse.depth_mm, full.depth_mm);
    const PressMeasures no_curvature = press_measures(s, {.curvature = false});
    EXPECT_EQ(no_curvature.max_slope_deg, full.max_slope_deg);
    EXPECT_TRUE(std::isnan(no_curvature.min_radius_mm));
    for (const double limit :
         {coarse.max_slope_deg - 0.01, 0.5 * (coarse.max_slope_deg + full.max_slope_deg),
          full.max_slope_deg + 0.01}) {
        const ConstraintsDesc c{.max_slope_deg = limit};
        const auto checks = constraint_checks(s, c);
        ASSERT_EQ(checks.size(), 1u);
        EXPECT_EQ(checks[0].met, full.max_slope_deg <= limit) << limit;
    }
    ASSERT_LT(coarse.max_slope_deg, full.max_slope_deg); // the middle limit is between them
}

TEST(PressMeasures, EachConstraintIsMetOrBrokenByItsMeasure) {
    PressMeasures m;
    m.max_slope_deg = 40.0;
    m.min_radius_mm = 3.0;
    m.depth_mm = 12.0;
    ConstraintsDesc c;
    EXPECT_TRUE(check_constraints(m, c).empty());
    c.max_slope_deg = 45.0;
    c.min_radius_mm = 4.0;
    c.max_depth_mm = 10.0;
    const auto checks = check_constraints(m, c);
    ASSERT_EQ(checks.size(), 3u);
    EXPECT_EQ(checks[0].name, "max_slope_deg");
    EXPECT_TRUE(checks[0].met);
    EXPECT_EQ(checks[0].violation, 0.0);
    EXPECT_EQ(checks[1].name, "min_radius_mm");
    EXPECT_FALSE(checks[1].met);
    EXPECT_DOUBLE_EQ(checks[1].violation, 0.25);
    EXPECT_EQ(checks[2].name, "max_depth_mm");
    EXPECT_FALSE(checks[2].met);
    EXPECT_DOUBLE_EQ(checks[2].violation, 0.2);
    // A plane has no curvature: any radius limit is met.
    m.min_radius_mm = std::numeric_limits<double>::infinity();
    EXPECT_TRUE(check_constraints(m, c)[1].met);
}

// The bending energy of a paraboloid of revolution z = z0 + a r^2 / 2 (a = 1 / 2f):
// principal curvatures a / w^3 (meridian) and a / w (around), w = sqrt(1 + a^2 r^2), over
// the area element w dx dy, so its density per dx dy is a^2 (1 / w^5 + 1 / w). The closed
// form's integral, taken here by Simpson's rule on a far finer grid than the press's, is
// the answer, with no use of the family's code.
double paraboloid_bending_density(double a, double r) {
    const double w = std::sqrt(1.0 + a * a * r * r);
    return a * a * (1.0 / std::pow(w, 5.0) + 1.0 / w);
}

// Unclamped over the whole holder: the press grid's trapezoid sum against Simpson's rule
// on 2000 x 2000 intervals of the closed form. The trapezoid rule's error on the 0.1 mm
// grid is h^2 / 12 times the integrand's second derivatives (~10 a^4 here) over the
// 400 mm^2: about 1e-5 of the total; the Hessian's differences add e^2 (1e-6 mm^2) times
// the third derivatives, far less. 1e-4 of the total bounds both; the search's coarser
// grid (every 4th sample each way, 0.16 mm apart) by (1.6)^2 more.
TEST(PressMeasures, TheBendingEnergyOfAParaboloidIsTheClosedFormsIntegral) {
    const double f = 10.0, a = 1.0 / (2.0 * f);
    const Holder h{{-10.0, -10.0, -20.0}, {10.0, 10.0, 0.0}};
    const Surface s = surface(Family::Paraboloid,
                              {{"fx", f}, {"fy", f}, {"z0", -10.0}, {"cx", 0.0}, {"cy", 0.0}}, h);
    constexpr int n = 2000; // Simpson: even
    const double step = 20.0 / n;
    const auto simpson = [](int i) { return i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0; };
    double expected = 0.0;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            expected +=
                simpson(i) * simpson(j) *
                paraboloid_bending_density(a, std::hypot(-10.0 + i * step, -10.0 + j * step));
    expected *= step * step / 9.0;
    const PressMeasures m = press_measures(s, 201, 201);
    EXPECT_NEAR(m.bending_energy, expected, 1e-4 * expected);
    EXPECT_NEAR(search_bending_energy(s), expected, 3e-4 * expected);
}

// Clamped at the holder's top outside r = R: only the unclamped disc counts (the clamp's
// flat and its kink are the holder's), 2 pi times the integral of r times the density to
// R (Simpson, 1e4 intervals). The grid counts a sample wholly in or out where the circle
// crosses its cell: at most a band one sample wide along the circle, 2 pi R h times the
// density there, which bounds the difference.
TEST(PressMeasures, TheBendingEnergyLeavesOutTheClampsFlat) {
    const double f = 10.0, a = 1.0 / (2.0 * f);
    const Holder h{{-10.0, -10.0, -20.0}, {10.0, 10.0, -8.0}};
    const Surface s = surface(Family::Paraboloid,
                              {{"fx", f}, {"fy", f}, {"z0", -10.0}, {"cx", 0.0}, {"cy", 0.0}}, h);
    const double rim = std::sqrt(2.0 * 4.0 * f); // -10 + R^2 / 4f = -8
    constexpr int n = 10000;
    double expected = 0.0;
    for (int i = 0; i <= n; ++i) {
        const double r = rim * i / n, weight = i == 0 || i == n ? 1.0 : i % 2 ? 4.0 : 2.0;
        expected += weight * 2.0 * std::numbers::pi * r * paraboloid_bending_density(a, r);
    }
    expected *= rim / n / 3.0;
    const PressMeasures m = press_measures(s, 201, 201);
    const double band = 2.0 * std::numbers::pi * rim * m.dx_mm * paraboloid_bending_density(a, rim);
    EXPECT_NEAR(m.bending_energy, expected, band);
}

// A profile whose rim lies below the holder's top turns flat at its radius with a crease
// (its slope jumps to 0): the energy leaves the crease out (press_measures.hpp) and so
// stays what the smooth part has, the same on grids of 201 and 401 samples a side. Read
// on the crease, one sample's differences would add ~(slope jump / e)^2 x a cell, 1e2-1e3
// times the whole; the trapezoid rule's error on the smooth part and the crease's band of
// cells wholly in or out (as at a clamp's edge) stay within 3 %.
TEST(PressMeasures, AProfilesCreaseAtItsRadiusIsLeftOutOfTheBendingEnergy) {
    ReflectorDesc r;
    r.family = Family::Profile;
    r.parameters = {{"z0", -5.0}, {"cx", 0.0}, {"cy", 0.0}, {"radius_mm", 9.0}};
    r.bspline.nx = 6;
    r.bspline.ny = 1;
    r.bspline.heights_mm = {0.0, 0.2, 0.8, 1.8, 3.2, 4.4}; // the rim at -0.6, below the top
    const Holder h{{-10.0, -10.0, -6.0}, {10.0, 10.0, 0.0}};
    const Surface s = Surface::make(r, h);
    const PressMeasures coarse = press_measures(s, 201, 201), fine = press_measures(s, 401, 401);
    EXPECT_TRUE(fine.kink) << "the crease is a kink";
    EXPECT_GT(coarse.bending_energy, 0.0);
    EXPECT_NEAR(coarse.bending_energy, fine.bending_energy, 0.03 * fine.bending_energy);
}

// A tilted plane bends nowhere: its bending energy is the differences' rounding only.
TEST(PressMeasures, APlaneHasNoBendingEnergy) {
    const Holder h{{0.0, 0.0, -20.0}, {10.0, 10.0, 0.0}};
    const Surface s = surface(
        Family::Plane, {{"z0", -10.0}, {"sx", 0.3}, {"sy", -0.4}, {"cx", 5.0}, {"cy", 5.0}}, h);
    // A constant gradient: its differences are 0 to rounding (1e-16 |g| / e, e = 2e-3 mm,
    // squared over 100 mm^2: 1e-22).
    EXPECT_LT(press_measures(s, 51, 51).bending_energy, 1e-18);
}

} // namespace
} // namespace fird
