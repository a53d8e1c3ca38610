// A far field's data-sheet figures (photometry/beam_metrics.hpp) against an analytic beam:
// a Gaussian in gamma, narrower in the C90 plane than in C0, binned cell by cell. Its beam
// and field angles are closed-form; its peak lies on the axis.
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "farfield/farfield.hpp"
#include "photometry/beam_metrics.hpp"

namespace fird {
namespace {

constexpr double kPi = std::numbers::pi;

// I(C, gamma) = peak exp(-(gamma cos C / sx)^2 - (gamma sin C / sy)^2), gamma from +z (the
// photometric nadir) and C = -phi (photometry/farfield_photometry.hpp), each cell's lumens
// its centre's intensity times its solid angle (cells of 0.2 deg: the midpoint rule's error
// is far below the patches' 1 degree).
FarField gaussian_beam(double peak_cd, double sx_deg, double sy_deg) {
    constexpr std::uint32_t w = 1800, h = 900;
    FarField f{w, h, std::vector<double>(std::size_t(w) * h)};
    for (std::uint32_t row = 0; row < h; ++row)
        for (std::uint32_t col = 0; col < w; ++col) {
            const glm::dvec3 d = farfield_cell_direction(col, row, w, h);
            const double gamma = std::acos(std::clamp(d.z, -1.0, 1.0)) * 180.0 / kPi;
            const double c = -std::atan2(d.y, d.x);
            const double u = gamma * std::cos(c) / sx_deg, v = gamma * std::sin(c) / sy_deg;
            f.lm[std::size_t(row) * w + col] =
                peak_cd * std::exp(-u * u - v * v) * farfield_cell_solid_angle_sr(row, w, h);
        }
    return f;
}

TEST(Photometrics, AGaussianBeamHasItsClosedFormBeamAndFieldAnglesInEachPlane) {
    const double sx = 12.0, sy = 7.0;
    const FarField f = gaussian_beam(5000.0, sx, sy);
    const Photometrics p = photometrics(f, 2.0 * f.total_lm());
    EXPECT_NEAR(p.efficiency, 0.5, 1e-12);
    // The peak patch is the 1-degree cap about the axis: over it gamma^2 averages R^2 / 2 and
    // cos^2 C, sin^2 C each 1/2, so its mean intensity is below the peak by about
    // (1/2)(1/2)(1/12^2 + 1/7^2) = 0.7 %.
    EXPECT_NEAR(p.peak_cd, 5000.0 * (1.0 - 0.25 * (1.0 / (sx * sx) + 1.0 / (sy * sy))),
                0.001 * 5000.0);
    EXPECT_LT(p.peak_gamma_deg, 1.0);
    // 50 %: 2 s sqrt(ln 2); 10 %: 2 s sqrt(ln 10). The patches average over 1 degree of
    // gamma and 5 of C, and the crossing is interpolated between patch centres 1 degree apart:
    // the Gaussian's curvature over that keeps the error under ~0.15 degrees here.
    EXPECT_NEAR(p.beam_angle_deg.c0_deg, 2.0 * sx * std::sqrt(std::log(2.0)), 0.15);
    EXPECT_NEAR(p.beam_angle_deg.c90_deg, 2.0 * sy * std::sqrt(std::log(2.0)), 0.15);
    EXPECT_NEAR(p.field_angle_deg.c0_deg, 2.0 * sx * std::sqrt(std::log(10.0)), 0.15);
    EXPECT_NEAR(p.field_angle_deg.c90_deg, 2.0 * sy * std::sqrt(std::log(10.0)), 0.15);
    const nlohmann::json j = photometrics_json(p);
    EXPECT_EQ(j["beam_angle_deg"]["C90"].get<double>(), p.beam_angle_deg.c90_deg);
    EXPECT_EQ(j["peak_direction_deg"].size(), 2u);
}

TEST(Photometrics, AnOffAxisBeamReportsItsDirectionInCAndGamma) {
    // A round beam of sigma 5 deg about gamma = 30.5, C = 92.5 deg: the centre of a patch
    // (bands of 1 deg of gamma from the axis; 5 deg of C from phi = -180, C = -phi).
    constexpr std::uint32_t w = 1800, h = 900;
    FarField f{w, h, std::vector<double>(std::size_t(w) * h)};
    const double g = 30.5 * kPi / 180.0, c = 92.5 * kPi / 180.0;
    const glm::dvec3 axis{std::sin(g) * std::cos(-c), std::sin(g) * std::sin(-c), std::cos(g)};
    for (std::uint32_t row = 0; row < h; ++row)
        for (std::uint32_t col = 0; col < w; ++col) {
            const glm::dvec3 d = farfield_cell_direction(col, row, w, h);
            const double angle =
                std::acos(std::clamp(glm::dot(d, axis), -1.0, 1.0)) * 180.0 / kPi / 5.0;
            f.lm[std::size_t(row) * w + col] =
                100.0 * std::exp(-angle * angle) * farfield_cell_solid_angle_sr(row, w, h);
        }
    const Photometrics p = photometrics(f, f.total_lm());
    EXPECT_NEAR(p.peak_gamma_deg, 30.5, 1e-9);
    EXPECT_NEAR(p.peak_c_deg, 92.5, 1e-9);
    // The patch spans 1 deg of gamma and 5 deg of C (2.5 deg of arc at gamma 30.5): the
    // squared angle averages (1^2 + 2.54^2) / 12 = 0.62 deg^2 over it, so its mean intensity
    // is ~0.62 / 25 = 2.5 % below the peak.
    EXPECT_NEAR(p.peak_cd, 100.0 * (1.0 - 0.62 / 25.0), 0.3);
}

TEST(Photometrics, AnEmptyFarFieldHasNoPeakAndNoAngles) {
    const FarField f{360, 180, std::vector<double>(360 * 180, 0.0)};
    const Photometrics p = photometrics(f, 100.0);
    EXPECT_EQ(p.efficiency, 0.0);
    EXPECT_EQ(p.peak_cd, 0.0);
    EXPECT_EQ(p.beam_angle_deg.c0_deg, 0.0);
    EXPECT_EQ(p.field_angle_deg.c90_deg, 0.0);
}

} // namespace
} // namespace fird
