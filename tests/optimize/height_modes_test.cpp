// The cosine modes a population samples a freed height grid in (optimize/height_modes.hpp),
// against the discrete cosine transform's closed forms: mode (0, 0) moves every height by
// its coefficient, mode (kx, ky) is the product of the two cosines at the heights' places,
// distinct modes are orthogonal with the stated RMS, the start is at coordinates 0, and
// only a whole free grid is sampled as modes.
#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "io/scene_file.hpp"
#include "optimize/height_modes.hpp"
#include "optimize/parameter_space.hpp"

namespace fird::test {
namespace {

Scene scene(const std::string& name) {
    return load_scene(std::string(FIRD_SOURCE_DIR) + "/scenes/" + name);
}

std::size_t index_of(const ParameterSpace& space, const std::string& name) {
    const auto it = std::find(space.names.begin(), space.names.end(), name);
    EXPECT_NE(it, space.names.end()) << name;
    return std::size_t(it - space.names.begin());
}

// A unit coefficient of mode `m` (at the coordinate of the m-th height) from coordinates 0.
std::vector<double> mode_heights(const SampleCoordinates& c, std::size_t at) {
    std::vector<double> unit(c.size(), 0.0);
    unit[at] = 1.0;
    std::vector<double> x = c.parameters(unit);
    for (std::size_t k = 0; k < x.size(); ++k)
        x[k] -= c.origin[k];
    return x;
}

TEST(HeightModes, TheModesOfASixBySixGridAreTheCosineTransformsWeighted) {
    const Scene s = scene("freeform_36.toml");
    const ParameterSpace space = parameter_space(s);
    ASSERT_EQ(space.size(), 36u);
    const SampleCoordinates c =
        sample_coordinates(s.reflector, space, space.start, HeightSampling::Modes);
    EXPECT_EQ(c.modes, 36u);
    EXPECT_EQ(c.grid, "6 x 6");
    // Coordinates 0 are the start.
    EXPECT_EQ(c.parameters(std::vector<double>(36, 0.0)), space.start);
    // Mode m sits at the coordinate of height m (column fastest): mode (kx, ky) = (m % 6,
    // m / 6) at h_<kx>_<ky>'s place.
    const double pi = std::numbers::pi;
    for (std::size_t kx = 0; kx < 6; ++kx)
        for (std::size_t ky = 0; ky < 6; ++ky) {
            SCOPED_TRACE(testing::Message() << "mode " << kx << ", " << ky);
            const auto x = mode_heights(c, index_of(space, fmt::format("h_{}_{}", kx, ky)));
            const double weight = 1.0 / ((1.0 + double(kx + ky)) * (1.0 + double(kx + ky)));
            double rms = 0.0;
            for (std::size_t i = 0; i < 6; ++i)
                for (std::size_t j = 0; j < 6; ++j) {
                    const double ax = kx == 0 ? 1.0 : std::sqrt(2.0);
                    const double ay = ky == 0 ? 1.0 : std::sqrt(2.0);
                    // The orthonormal DCT-II pair, times sqrt(36) / 6 = 1: unit RMS.
                    const double expected =
                        weight * ax * std::cos(pi * (double(i) + 0.5) * double(kx) / 6.0) * ay *
                        std::cos(pi * (double(j) + 0.5) * double(ky) / 6.0);
                    const double h = x[index_of(space, fmt::format("h_{}_{}", i, j))];
                    EXPECT_NEAR(h, expected, 1e-12);
                    rms += h * h / 36.0;
                }
            EXPECT_NEAR(std::sqrt(rms), weight, 1e-12);
            if (kx == 0 && ky == 0) {
                for (double h : x)
                    EXPECT_NEAR(h, 1.0, 1e-12); // the mean mode lifts every height by 1 mm
            }
        }
    // Distinct modes are orthogonal.
    for (std::size_t a = 0; a < 36; ++a)
        for (std::size_t b = a + 1; b < 36; ++b) {
            const auto xa = mode_heights(c, a), xb = mode_heights(c, b);
            double dot = 0.0;
            for (std::size_t k = 0; k < 36; ++k)
                dot += xa[k] * xb[k];
            EXPECT_NEAR(dot, 0.0, 1e-12) << a << " . " << b;
        }
    // Each mode's box is the heights' width, centred on the start.
    for (std::size_t k = 0; k < 36; ++k) {
        EXPECT_DOUBLE_EQ(c.hi[k] - c.lo[k], 16.0);
        EXPECT_DOUBLE_EQ(c.hi[k], -c.lo[k]);
    }
}

// A profile's heights are a row of modes; its other parameters are coordinates of their own.
TEST(HeightModes, AProfilesHeightsAreOneRowOfModesAndItsOtherParametersThemselves) {
    Scene s = scene("test/profile_search.toml");
    s.reflector.optimize.clear();
    for (std::size_t k = 0; k < std::size_t(s.reflector.bspline.nx); ++k)
        s.reflector.optimize[fmt::format("h_{}", k)] = {-5.0, 10.0, 0.25};
    s.reflector.optimize["z0"] = {-12.0, -6.0, 0.5};
    const ParameterSpace space = parameter_space(s);
    const std::size_t n = std::size_t(s.reflector.bspline.nx);
    ASSERT_EQ(space.size(), n + 1);
    const SampleCoordinates c =
        sample_coordinates(s.reflector, space, space.start, HeightSampling::Modes);
    EXPECT_EQ(c.modes, n);
    EXPECT_EQ(c.grid, std::to_string(n));
    const std::size_t z0 = index_of(space, "z0");
    const auto moved = mode_heights(c, z0);
    for (std::size_t k = 0; k < moved.size(); ++k)
        EXPECT_EQ(moved[k], k == z0 ? 1.0 : 0.0);
    // An offset from the start, its box moved with it.
    EXPECT_EQ(c.lo[z0], space.lo[z0] - space.start[z0]);
    EXPECT_EQ(c.hi[z0], space.hi[z0] - space.start[z0]);
    // Mode 1: the first cosine over the profile's radii, weight 1/4.
    const auto x = mode_heights(c, index_of(space, "h_1"));
    for (std::size_t k = 0; k < n; ++k)
        EXPECT_NEAR(x[index_of(space, fmt::format("h_{}", k))],
                    0.25 * std::sqrt(2.0) *
                        std::cos(std::numbers::pi * (double(k) + 0.5) / double(n)),
                    1e-12);
}

// Independent sampling, or a grid not wholly free (groups), leaves the parameters as they are.
TEST(HeightModes, OnlyAWholeFreeGridIsSampledAsModes) {
    const Scene s = scene("freeform_36.toml");
    const ParameterSpace space = parameter_space(s);
    const SampleCoordinates independent =
        sample_coordinates(s.reflector, space, space.start, HeightSampling::Independent);
    EXPECT_EQ(independent.modes, 0u);
    EXPECT_TRUE(independent.transform.empty());
    EXPECT_EQ(independent.lo, space.lo);
    const std::vector<double> x(36, -7.25);
    EXPECT_EQ(independent.parameters(x), x);

    const Scene grouped = scene("test/bspline_dish.toml"); // two groups, not the whole grid
    const ParameterSpace gs = parameter_space(grouped);
    const SampleCoordinates g =
        sample_coordinates(grouped.reflector, gs, gs.start, HeightSampling::Modes);
    EXPECT_EQ(g.modes, 0u);
    EXPECT_TRUE(g.transform.empty());
}

TEST(HeightModes, TheSceneFileNamesTheSamplingAndRefusesOthers) {
    Scene s = scene("freeform_36.toml");
    EXPECT_EQ(s.optimize.height_sampling, HeightSampling::Modes);
    s.optimize.height_sampling = HeightSampling::Independent;
    const Scene back = parse_scene(scene_to_toml(s), "round trip");
    EXPECT_EQ(back.optimize.height_sampling, HeightSampling::Independent);
    std::string text = scene_to_toml(s);
    const auto at = text.find("independent");
    ASSERT_NE(at, std::string::npos) << text;
    text.replace(at, std::string("independent").size(), "smooth");
    try {
        (void)parse_scene(text, "bad.toml");
        FAIL() << "accepted height_sampling = 'smooth'";
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("bad.toml"), std::string::npos) << what;
        EXPECT_NE(what.find("height_sampling"), std::string::npos) << what;
    }
}

} // namespace
} // namespace fird::test
