// The data behind the luminaire views against closed forms: the illuminance of an
// isotropic and of a cosine-law luminaire on a plane (the inverse square law times
// cos^3 gamma), the C orientation of the plane (C90 along +y), the gamma holding a share
// of the flux, and an isocandela line of a cosine-law beam (the pictures:
// luminaire_pictures_test.cpp).
#include <cmath>
#include <filesystem>
#include <numbers>
#include <utility>

#include <gtest/gtest.h>

#include "candela_tables.hpp"
#include "photometry/farfield_photometry.hpp"
#include "photometry/luminaire_pictures.hpp" // view_table
#include "photometry/luminaire_views.hpp"

namespace fird {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

using test::formula_table;

// Isotropic I0: E = I0 cos^3 gamma / d^2; the table is constant, so exact to rounding.
TEST(LuminaireViews, AnIsotropicLuminairesIlluminanceIsTheInverseSquareTimesCosCubed) {
    const CandelaTable t = formula_table({0.0}, [](std::size_t, double) { return 500.0; });
    const IlluminanceMap m = illuminance_on_plane(t, 2.0, 3.0, 31);
    for (int iy = 0; iy < 31; iy += 5)
        for (int ix = 0; ix < 31; ix += 3) {
            const double r = std::hypot(m.position_m(ix), m.position_m(iy));
            const double cos_g = 2.0 / std::hypot(2.0, r);
            EXPECT_NEAR(m.at(ix, iy), 500.0 * std::pow(cos_g, 3) / 4.0, 1e-12 * 500.0)
                << ix << ", " << iy;
        }
    EXPECT_DOUBLE_EQ(m.at(15, 15), 125.0); // under the luminaire: I0 / d^2
}

// Each quarter's plane its own intensity: the point at +y lies in C90, at -x in C180
// (the plane's x along C0, y along C90), at +x in C0; a cosine law within each, which
// the table's interpolation (linear in cos gamma) holds exactly.
TEST(LuminaireViews, ThePlanesAxesAreC0AndC90AndGammaFollowsTheCosineLaw) {
    const std::vector<double> cd0{100.0, 200.0, 300.0, 400.0};
    const CandelaTable t = formula_table({0.0, 90.0, 180.0, 270.0}, [&](std::size_t c, double g) {
        return g <= 90.0 ? cd0[c] * std::cos(g * kDeg) : 0.0;
    });
    const double d = 3.0;
    const IlluminanceMap m = illuminance_on_plane(t, d, 2.0, 5); // samples at -2, -1, 0, 1, 2
    const auto expected = [&](double i0, double r) {
        const double cos_g = d / std::hypot(d, r);
        return i0 * std::pow(cos_g, 4) / (d * d);
    };
    EXPECT_NEAR(m.at(4, 2), expected(100.0, 2.0), 1e-9); // +x: C0
    EXPECT_NEAR(m.at(2, 4), expected(200.0, 2.0), 1e-9); // +y: C90
    EXPECT_NEAR(m.at(0, 2), expected(300.0, 2.0), 1e-9); // -x: C180
    EXPECT_NEAR(m.at(2, 0), expected(400.0, 2.0), 1e-9); // -y: C270
}

// The share of flux within gamma: isotropic, half by 90 deg; cosine law (over the lower
// hemisphere), sin^2 gamma, half by 45 deg. The zones are 0.25 deg wide and the answer
// is a zone's outer edge: within 0.25 deg.
TEST(LuminaireViews, TheGammaHoldingAShareOfTheFluxIsTheClosedForms) {
    const CandelaTable iso = formula_table({0.0}, [](std::size_t, double) { return 1.0; });
    EXPECT_NEAR(gamma_holding_deg(iso, 0.5), 90.0, 0.25);
    const CandelaTable cosine = formula_table(
        {0.0}, [](std::size_t, double g) { return g <= 90.0 ? std::cos(g * kDeg) : 0.0; });
    EXPECT_NEAR(gamma_holding_deg(cosine, 0.5), 45.0, 0.25);
    EXPECT_NEAR(gamma_holding_deg(cosine, 0.9), std::asin(std::sqrt(0.9)) / kDeg, 0.25);
}

// A cosine-law beam's 50 % line is the circle gamma = 60 deg: marching squares on nodes
// 0.5 deg apart puts each crossing on the chord between nodes of cos gamma (exact in the
// table), off the true gamma by at most the chord's sag, ~(0.5 deg)^2 / 8 cot 60 deg: 1e-3
// deg bounds it. The segments go round the whole C range once.
TEST(LuminaireViews, ACosineBeamsHalfIntensityLineIsTheCircleAtSixtyDegrees) {
    const CandelaTable t = formula_table(
        {0.0}, [](std::size_t, double g) { return g <= 90.0 ? 800.0 * std::cos(g * kDeg) : 0.0; });
    const auto segments = isocandela_segments(t, {400.0}, 90.0);
    ASSERT_FALSE(segments.empty());
    double around = 0.0;
    for (const IsoSegment& s : segments) {
        EXPECT_NEAR(s.gamma0_deg, 60.0, 1e-3);
        EXPECT_NEAR(s.gamma1_deg, 60.0, 1e-3);
        around += std::abs(s.c1_deg - s.c0_deg);
    }
    EXPECT_NEAR(around, 360.0, 1e-9);
}

// The views' table of a far field whose rows are a whole degree or more: an isotropic
// luminaire reads I0 at nadir and everywhere (a node between two rows' centres, or a step
// of one row, would leave nadir at 0 cd). The far field holds I0 exactly per cell
// (farfield_from_table integrates it), so 1e-9 bounds the rounding.
TEST(LuminaireViews, TheViewsTableOfACoarseFarFieldReadsNadir) {
    const CandelaTable iso = formula_table({0.0}, [](std::size_t, double) { return 250.0; });
    for (const auto& [w, h] : {std::pair{360u, 180u}, std::pair{180u, 90u}, std::pair{72u, 36u}}) {
        const CandelaTable t = view_table(farfield_from_table(iso, w, h));
        for (const double g : {0.0, 0.5, 45.0, 90.0, 179.0})
            EXPECT_NEAR(intensity_cd(t, 30.0, g), 250.0, 1e-9 * 250.0)
                << w << "x" << h << " " << g << " " << t.gamma_deg[1] << " " << t.c_deg[1];
    }
}

// Steps, ranges and distances that make no grid or no plane are refused, never looped on
// or divided by.
TEST(LuminaireViews, BadStepsAndDistancesAreRefused) {
    const CandelaTable t = formula_table({0.0}, [](std::size_t, double) { return 1.0; });
    EXPECT_THROW((void)isocandela_segments(t, {0.5}, 90.0, 0.0), std::invalid_argument);
    EXPECT_THROW((void)isocandela_segments(t, {0.5}, 90.0, 1.0, -0.5), std::invalid_argument);
    EXPECT_THROW((void)isocandela_segments(t, {0.5}, std::nan("")), std::invalid_argument);
    EXPECT_THROW((void)illuminance_on_plane(t, 0.0, 1.0, 5), std::invalid_argument);
    EXPECT_THROW((void)illuminance_on_plane(t, -2.0, 1.0, 5), std::invalid_argument);
    EXPECT_THROW((void)illuminance_on_plane(t, 2.0, std::nan(""), 5), std::invalid_argument);
}

} // namespace
} // namespace fird
