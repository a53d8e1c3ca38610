// The tailored start's solver (optimize/tailored_start.hpp) against reflectors known in
// closed form: an isotropic point source's own far field off a flat mirror gives back the
// flat mirror, a collimated beam gives the parabola with its focus at the source (both edge
// rays); the flux map holds equal shares of the source and the target at every angle and
// meets them at the ends; no light is refused in one line.
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "optimize/tailored_start.hpp"

namespace fird {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// An isotropic point source's flux per polar band of `bands` over [0, pi]: the band
// [a, b] holds (cos a - cos b) / 2 of it (exact, not sampled).
std::vector<double> isotropic_bands(std::size_t bands) {
    std::vector<double> b(bands);
    for (std::size_t k = 0; k < bands; ++k)
        b[k] = 0.5 * (std::cos(double(k) * kPi / double(bands)) -
                      std::cos(double(k + 1) * kPi / double(bands)));
    return b;
}

TEST(Tailoring, AFlatMirrorsOwnFarFieldGivesBackTheFlatMirror) {
    // A flat mirror 10 mm below the source, its rim where the cone of 56 degrees (a band's
    // edge) meets it: it reflects theta into gamma = theta, so its far field is the source's
    // own distribution within 56 degrees. gamma(theta) = theta exactly (the same bands on
    // both sides), d(ln rho)/d(theta) = tan theta, rho = d / cos theta: z = -d everywhere.
    const std::size_t bands = 1800;
    const double depth = 10.0, rim = 56.0 * kDeg;
    std::vector<double> target = isotropic_bands(bands);
    for (std::size_t k = std::size_t(std::lround(rim / kPi * double(bands))); k < bands; ++k)
        target[k] = 0.0;
    const TailoringProblem problem{.source_band_lm = isotropic_bands(bands),
                                   .target_band_lm = target,
                                   .apex_depth_mm = depth,
                                   .radius_mm = depth * std::tan(rim),
                                   .heights = 9,
                                   .edge = EdgeRay::Diverging};
    const TailoredProfile t = tailor_profile(problem);
    EXPECT_TRUE(t.reaches_rim);
    // The rim is bisected to 1e-16 rad; RK4's error at 4000 steps of 2.4e-4 rad on the
    // smooth tan theta is ~h^4 (3e-15) per unit: 1e-9 bounds both with room.
    EXPECT_NEAR(t.rim_polar_rad, rim, 1e-9);
    ASSERT_EQ(t.z_mm.size(), 9u);
    for (std::size_t k = 0; k < t.z_mm.size(); ++k)
        EXPECT_NEAR(t.z_mm[k], -depth, 1e-6) << "height " << k;
    // The isotropic source's share within the rim's cone: (1 - cos 56 deg) / 2.
    EXPECT_NEAR(t.source_share, 0.5 * (1.0 - std::cos(rim)), 1e-12);
}

TEST(Tailoring, ACollimatedBeamGivesTheParabolaFocusedAtTheSource) {
    // All of the target in its first band (0.01 degree about the zenith): the parabola with
    // its focus at the source and its apex f = 10 mm below, z = r^2 / 4f - f, out to r =
    // 16 mm (rho = 2f / (1 + cos theta): the rim at 2 atan(0.8) = 77.3 degrees).
    const std::size_t target_bands = 18000;
    std::vector<double> target(target_bands, 0.0);
    target[0] = 1.0;
    const double f = 10.0, radius = 16.0;
    for (const EdgeRay edge : {EdgeRay::Diverging, EdgeRay::Crossing}) {
        const TailoringProblem problem{.source_band_lm = isotropic_bands(1800),
                                       .target_band_lm = target,
                                       .apex_depth_mm = f,
                                       .radius_mm = radius,
                                       .heights = 17,
                                       .edge = edge};
        const TailoredProfile t = tailor_profile(problem);
        EXPECT_NEAR(t.rim_polar_rad, 2.0 * std::atan(radius / (2.0 * f)), 1e-3)
            << edge_ray_name(edge);
        // The band's width is the error: gamma in [0, 1.75e-4 rad] instead of 0 moves
        // d(ln rho)/d(theta) by at most beta_max / 2 sec^2((theta + beta) / 2) <= 1.43e-4,
        // over the 1.35 rad cone 1.9e-4 in ln rho, at rho <= 16.4 mm: 3.2e-3 mm.
        for (std::size_t k = 0; k < t.z_mm.size(); ++k) {
            const double r = radius * double(k) / 16.0;
            EXPECT_NEAR(t.z_mm[k], r * r / (4.0 * f) - f, 3.2e-3)
                << edge_ray_name(edge) << " r = " << r;
        }
    }
}

TEST(Tailoring, TheFluxMapHoldsEqualSharesAndMeetsAtTheEnds) {
    // A target of intensity proportional to cos gamma within 40 degrees (the band [a, b]
    // holds (sin^2 b - sin^2 a) / 2): its share within gamma is sin^2 gamma / sin^2 40 deg;
    // the isotropic source's within theta of the rim's cone (1 - cos theta) / (1 - cos
    // rim). Both closed forms, independent of the solver's band sums.
    const std::size_t bands = 1800;
    const double edge = 40.0 * kDeg;
    std::vector<double> target(bands, 0.0);
    for (std::size_t k = 0; k < bands; ++k) {
        const double a = double(k) * kPi / double(bands), b = double(k + 1) * kPi / double(bands);
        if (b <= edge + 1e-12)
            target[k] = 0.5 * (std::sin(b) * std::sin(b) - std::sin(a) * std::sin(a));
    }
    for (const EdgeRay ray : {EdgeRay::Diverging, EdgeRay::Crossing}) {
        const TailoredProfile t = tailor_profile({.source_band_lm = isotropic_bands(bands),
                                                  .target_band_lm = target,
                                                  .apex_depth_mm = 8.0,
                                                  .radius_mm = 20.0,
                                                  .heights = 8,
                                                  .edge = ray});
        ASSERT_GE(t.theta_rad.size(), 100u);
        // The ends: the axis ray goes to the zenith, the rim's ray to the target's edge.
        EXPECT_EQ(t.theta_rad.front(), 0.0);
        EXPECT_NEAR(t.gamma_rad.front(), 0.0, 1e-12);
        EXPECT_NEAR(t.theta_rad.back(), t.rim_polar_rad, 1e-12);
        EXPECT_NEAR(t.gamma_rad.back(), edge, 1e-9);
        // Linear interpolation inside a 0.1 degree band misses a smooth share by at most
        // w^2 / 8 max|share''|: (1.75e-3)^2 / 8 * 2 / sin^2 40 deg = 1.9e-6 (the target's),
        // less for the source's; 1e-5 bounds the difference of the two.
        for (std::size_t i = 0; i < t.theta_rad.size(); ++i) {
            const double source_share =
                (1.0 - std::cos(t.theta_rad[i])) / (1.0 - std::cos(t.rim_polar_rad));
            const double target_share =
                std::pow(std::sin(t.gamma_rad[i]), 2) / std::pow(std::sin(edge), 2);
            EXPECT_NEAR(source_share, target_share, 1e-5)
                << edge_ray_name(ray) << " theta " << t.theta_rad[i];
        }
        for (double z : t.z_mm)
            EXPECT_TRUE(std::isfinite(z));
    }
}

TEST(Tailoring, LightBelowTheHorizonIsLeftOutAndTheCurveStaysFinite) {
    // An isotropic target: half of it below the horizon, where a diverging map would drive
    // (theta + gamma) / 2 past 90 degrees. Only the upper half is mapped: the rim's ray goes
    // to the horizon and every height is finite. The map spreads the source's cone over the
    // whole upper half (gamma > theta), wider than a flat mirror's gamma = theta, so
    // tan((theta + gamma) / 2) > tan theta: rho grows faster than d / cos theta and the
    // curve falls away from the apex (a dome), height after height.
    const TailoredProfile t = tailor_profile({.source_band_lm = isotropic_bands(1800),
                                              .target_band_lm = isotropic_bands(1800),
                                              .apex_depth_mm = 10.0,
                                              .radius_mm = 30.0,
                                              .heights = 8,
                                              .edge = EdgeRay::Diverging});
    EXPECT_NEAR(t.target_share_left_out, 0.5, 1e-12);
    EXPECT_NEAR(t.gamma_rad.back(), 0.5 * kPi, 1e-9);
    EXPECT_GT(t.rim_polar_rad, 10.0 * kDeg);
    for (std::size_t k = 1; k < t.z_mm.size(); ++k) {
        EXPECT_TRUE(std::isfinite(t.z_mm[k]));
        EXPECT_LT(t.z_mm[k], t.z_mm[k - 1]) << k;
    }
}

TEST(Tailoring, NoLightOrNoRoomIsRefusedInOneLine) {
    const auto refusal = [](const TailoringProblem& p) {
        try {
            (void)tailor_profile(p);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    TailoringProblem p{.source_band_lm = isotropic_bands(180),
                       .target_band_lm = std::vector<double>(180, 0.0),
                       .apex_depth_mm = 5.0,
                       .radius_mm = 10.0,
                       .heights = 4};
    EXPECT_EQ(refusal(p), "the tailored start: the desired far field holds no light above the "
                          "horizon");
    p.target_band_lm = isotropic_bands(180);
    p.apex_depth_mm = -1.0;
    EXPECT_NE(refusal(p).find("apex below the source"), std::string::npos) << refusal(p);
    for (const std::string& why : {refusal(p)})
        EXPECT_EQ(why.find('\n'), std::string::npos);
}

} // namespace
} // namespace fird
