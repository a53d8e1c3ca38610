// The far-field conventions of DESIGN.md §2 and the .npy output.
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "farfield/farfield.hpp"
#include "io/npy.hpp"

namespace fird {
namespace {

TEST(FarField, BinningFollowsTheFixedConvention) {
    constexpr std::uint32_t W = 1800, H = 900;
    // Zenith -> row 0; nadir -> last row.
    EXPECT_EQ(farfield_cell({0, 0, 1}, W, H) / W, 0u);
    EXPECT_EQ(farfield_cell({0, 0, -1}, W, H) / W, H - 1);
    // +x: phi = 0 -> column W/2; -x: phi = pi -> clamped to the last column? atan2(0,-1) = pi.
    EXPECT_EQ(farfield_cell({1, 0, 0}, W, H) % W, W / 2);
    EXPECT_EQ(farfield_cell({-1, -1e-12, 0}, W, H) % W, 0u) << "phi just above -pi";
    EXPECT_EQ(farfield_cell({-1, 0, 0}, W, H) % W, W - 1) << "phi = pi is clamped";
    // Horizon: theta = 0 -> row H/2.
    EXPECT_EQ(farfield_cell({0, 1, 0}, W, H) / W, H / 2);
    // Cell centres map back to their cell.
    for (std::uint32_t r = 0; r < H; r += 37)
        for (std::uint32_t c = 0; c < W; c += 53)
            ASSERT_EQ(farfield_cell(farfield_cell_direction(c, r, W, H), W, H), r * W + c);
}

TEST(FarField, L2IsTheEuclideanDistance) {
    const FarField a{2, 1, {1.0, 2.0}}, b{2, 1, {4.0, -2.0}};
    EXPECT_DOUBLE_EQ(l2_distance(a, b), 5.0);
    const FarField c{1, 2, {1.0, 2.0}};
    EXPECT_THROW((void)l2_distance(a, c), std::invalid_argument);
}

TEST(Npy, WritesFloat32WithShapeAndReadsBack) {
    const std::string path = ::testing::TempDir() + "/ff.npy";
    std::vector<double> v(6);
    for (int i = 0; i < 6; ++i)
        v[i] = 0.5 * i;
    write_npy_f32(path, v, 2, 3);
    const NpyArray a = read_npy_f32(path);
    ASSERT_EQ(a.shape, (std::vector<std::uint64_t>{2, 3}));
    for (int i = 0; i < 6; ++i)
        EXPECT_FLOAT_EQ(a.values[i], float(v[i]));
    std::remove(path.c_str());
}

} // namespace
} // namespace fird
