// Reflector families: analytic gradients against finite differences, and the height
// ranges the reference tracer relies on must contain every value in their box.
#include <random>

#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "model/surface.hpp"

namespace fird {
namespace {

const std::string kScenes = std::string(FIRD_SOURCE_DIR) + "/scenes/";

class SurfaceFamily : public ::testing::TestWithParam<std::string> {};

TEST_P(SurfaceFamily, GradientMatchesFiniteDifferencesAndBoundsContainTheSurface) {
    const Scene s = load_scene(kScenes + GetParam());
    const Surface f = Surface::make(s.reflector, s.holder);
    const Holder& h = s.holder;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(h.min_mm.x, h.max_mm.x), uy(h.min_mm.y, h.max_mm.y);
    for (int k = 0; k < 2000; ++k) {
        const double x = ux(rng), y = uy(rng);
        constexpr double e = 1e-6;
        const double gx = (f.raw(x + e, y) - f.raw(x - e, y)) / (2 * e);
        const double gy = (f.raw(x, y + e) - f.raw(x, y - e)) / (2 * e);
        const glm::dvec2 g = f.raw_gradient(x, y);
        ASSERT_NEAR(g.x, gx, 1e-5 * (1 + std::abs(gx))) << x << "," << y;
        ASSERT_NEAR(g.y, gy, 1e-5 * (1 + std::abs(gy))) << x << "," << y;

        double x0 = ux(rng), x1 = ux(rng), y0 = uy(rng), y1 = uy(rng);
        if (x0 > x1) std::swap(x0, x1);
        if (y0 > y1) std::swap(y0, y1);
        const HeightRange r = f.bounds(x0, x1, y0, y1);
        for (int m = 0; m < 20; ++m) {
            const double px = x0 + (x1 - x0) * m / 19.0;
            for (int n = 0; n < 20; ++n) {
                const double z = f.height(px, y0 + (y1 - y0) * n / 19.0);
                ASSERT_GE(z, r.lo - 1e-12);
                ASSERT_LE(z, r.hi + 1e-12);
            }
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Families, SurfaceFamily,
                         ::testing::Values("model_a.toml", "model_b.toml", "model_c.toml",
                                           "test/flat_mirror.toml", "test/bspline_dish.toml",
                                           "test/profile_dish.toml"));

TEST(Surface, ClampPlateausAreFlatAndWithinTheHolder) {
    const Scene s = load_scene(kScenes + "model_a.toml");
    const Surface f = Surface::make(s.reflector, s.holder);
    EXPECT_DOUBLE_EQ(f.height(29.9, 19.9), 0.0);
    EXPECT_EQ(f.gradient(29.9, 19.9), glm::dvec2(0.0));
    EXPECT_DOUBLE_EQ(f.height(0.0, 0.0), -10.0);
}

TEST(Surface, BSplineGroupsMoveTheirControlHeights) {
    BSplineDesc b{.nx = 5, .ny = 4, .heights_mm = std::vector<double>(20, -1.0)};
    b.groups["rim"] = {ControlGroup::Kind::Ring, 0, 0};
    b.groups["c"] = {ControlGroup::Kind::Point, 2, 1};
    const auto h = bspline_heights(b, {{"rim", -0.5}, {"c", -3.0}});
    EXPECT_EQ(h[0], -0.5);         // corner: ring 0
    EXPECT_EQ(h[1 * 5 + 1], -1.0); // inner
    EXPECT_EQ(h[1 * 5 + 2], -3.0); // the point group
    EXPECT_EQ(h[3 * 5 + 4], -0.5);
}

// The profile family against its definition: the spline passes through every height at
// its radius in every direction (f(r_k) = h_k, solved exactly, so to rounding), is level on
// the axis (f'(0) = 0) and beyond radius_mm, its height there the last one's, and its
// second derivative vanishes at the last knot (the natural end) - checked by differences
// of the exact function, not of the spline's own formulas.
TEST(Surface, AProfilePassesThroughItsHeightsLevelOnItsAxis) {
    const std::vector<double> h = {-2.0, -1.7, -0.4, 1.1, 0.5, 2.0, 2.3};
    ReflectorDesc r{.family = Family::Profile,
                    .parameters = {{"z0", -6.0}, {"cx", 1.5}, {"cy", -0.5}, {"radius_mm", 12.0}}};
    r.bspline = {.nx = int(h.size()), .ny = 1, .heights_mm = h};
    r.bspline.groups["h_3"] = {ControlGroup::Kind::Point, 3, 0};
    r.parameters["h_3"] = 0.9; // a parameter moves its height
    const Holder holder{{-20, -20, -30}, {20, 20, 30}};
    const Surface f = Surface::make(r, holder);
    const double spacing = 12.0 / double(h.size() - 1);
    for (std::size_t k = 0; k < h.size(); ++k)
        for (double angle : {0.0, 0.7, 2.9, -1.3}) {
            const double x = 1.5 + double(k) * spacing * std::cos(angle);
            const double y = -0.5 + double(k) * spacing * std::sin(angle);
            EXPECT_NEAR(f.height(x, y), -6.0 + (k == 3 ? 0.9 : h[k]), 1e-12) << k;
        }
    EXPECT_EQ(f.raw_gradient(1.5, -0.5), glm::dvec2(0.0));
    constexpr double e = 1e-4;
    EXPECT_NEAR((f.raw(1.5 + e, -0.5) - f.raw(1.5, -0.5)) / e, 0.0, 1e-3); // f'(0) = 0
    EXPECT_NEAR(f.height(1.5 + 13.0, -0.5), -6.0 + 2.3, 1e-12);            // held beyond
    EXPECT_EQ(f.raw_gradient(1.5 - 14.0, 3.0), glm::dvec2(0.0));
    const double x_n = 1.5 + 12.0;
    const double curvature =
        (f.raw(x_n - 2e-3, -0.5) - 2.0 * f.raw(x_n - 1e-3, -0.5) + f.raw(x_n, -0.5)) / 1e-6;
    EXPECT_NEAR(curvature, 0.0, 0.02); // f'' linear in a span: within ~2e-3 of the knot
}

// A box or spacing far outside the spans (a fuzzed scene found a profile's bounds converting
// r / spacing beyond int's range, which is undefined): the bounds still hold the surface,
// which is level beyond the last knot (the profile) or at the border's control heights (the
// spline), so their values are known without the bounds code.
TEST(Surface, BoundsFarBeyondTheSplineStayExactAndDefined) {
    ReflectorDesc profile{
        .family = Family::Profile,
        .parameters = {{"z0", -6.0}, {"cx", 0.0}, {"cy", 0.0}, {"radius_mm", 1e-200}}};
    profile.bspline = {.nx = 3, .ny = 1, .heights_mm = {-2.0, -1.0, 0.5}};
    const Holder holder{{-20, -20, -30}, {20, 20, 30}};
    const Surface p = Surface::make(profile, holder);
    const HeightRange level = p.bounds(1.0, 2.0, 1.0, 2.0); // r / spacing ~ 1e200
    EXPECT_NEAR(level.lo, -6.0 + 0.5, 1e-8); // the bounds' rounding margin, 2e-9 here
    EXPECT_NEAR(level.hi, -6.0 + 0.5, 1e-8);
    EXPECT_NEAR(p.height(1.5, 1.5), -6.0 + 0.5, 1e-12);

    ReflectorDesc spline{.family = Family::BSpline};
    spline.bspline = {.nx = 3, .ny = 2, .heights_mm = {-3.0, -2.0, -1.0, 4.0, 5.0, 6.0}};
    const Surface b = Surface::make(spline, holder);
    // (x - x0) / dx ~ 1e298: the convex hull of the last column's heights.
    const HeightRange far = b.bounds(1e300, 1.5e300, -1e300, -0.5e300);
    EXPECT_EQ(far.lo, -2.0);
    EXPECT_EQ(far.hi, 6.0);
}

} // namespace
} // namespace fird
