// The device reduction against a double-precision CPU sum over random inputs.
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "passes/reduce_pass.hpp"
#include "reduction_bound.hpp"
#include "vk/buffer.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

class ReduceTest : public VulkanTest, public ::testing::WithParamInterface<std::uint32_t> {};

std::vector<float> random_floats(std::uint32_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 4.0f);
    std::vector<float> v(n);
    for (auto& x : v)
        x = u(rng);
    return v;
}

FloatTable upload(const vk::Context& c, const std::vector<float>& v) {
    FloatTable t = make_float_table(c, v.size(), vk::MemoryUse::Device, "test.reduce.input");
    if (!v.empty()) t.values.upload(c, std::span<const float>(v));
    return t;
}

TEST_P(ReduceTest, SumMatchesCpu) {
    const std::uint32_t n = GetParam();
    const auto values = random_floats(n, 7 + n);
    double expected = 0.0;
    double magnitude = 0.0;
    for (float x : values) {
        expected += x;
        magnitude += std::abs(x);
    }
    const ReducePass pass(ctx());
    const double got = pass.sum(ctx(), upload(ctx(), values), n);
    // Float accumulation along a tree: error grows like eps * log2(n) * sum |x|.
    EXPECT_NEAR(got, expected, 1e-6 * (1.0 + magnitude));
}

TEST_P(ReduceTest, SquaredDifferenceMatchesCpu) {
    const std::uint32_t n = GetParam();
    const auto a = random_floats(n, 100 + n);
    const auto b = random_floats(n, 200 + n);
    double expected = 0.0;
    for (std::uint32_t i = 0; i < n; ++i) {
        const double d = double(a[i]) - double(b[i]);
        expected += d * d;
    }
    const ReducePass pass(ctx());
    const double got = pass.sum_squared_difference(ctx(), upload(ctx(), a), upload(ctx(), b), n);
    EXPECT_NEAR(got, expected, 1e-5 * (1.0 + expected));
}

// 5000003 takes three levels: the third reads the second's partials past the first's in the
// scratch (ReducePush::a_offset), where the others read from its start.
INSTANTIATE_TEST_SUITE_P(Sizes, ReduceTest,
                         ::testing::Values(0u, 1u, 17u, 2049u, 1000003u, 5000003u));

// The reduction reads its inputs through texel views, which hold at most the device's
// maxTexelBufferElements texels: a table past it is refused in one line naming the table and
// the limit, before any allocation (the far fields stay below it: FastTracer checks their
// cells against it); one within it is made.
TEST_F(VulkanTest, AFloatTablePastTheTexelBufferLimitIsRefusedNamingIt) {
    const std::uint64_t limit = ctx().limits().max_texel_buffer_elements;
    ASSERT_GT(limit, 0u);
    try {
        (void)make_float_table(ctx(), limit + 1, vk::MemoryUse::Device, "fird.test.farfield");
        FAIL() << "a table of " << limit + 1 << " floats was made";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("fird.test.farfield"), std::string::npos) << what;
        // Refused by the table before allocating, not by its view (named "....texels") after.
        EXPECT_EQ(what.find(".texels"), std::string::npos) << what;
        EXPECT_NE(what.find(std::to_string(limit)), std::string::npos) << what;
        EXPECT_NE(what.find("texel buffer limit"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    }
    const FloatTable small = make_float_table(ctx(), 1000, vk::MemoryUse::Device, "fird.test.lm");
    EXPECT_NE(small.texels.get(), VK_NULL_HANDLE);
    EXPECT_EQ(small.values.size(), 1000u * sizeof(float));
}

// The candela metric's weighting on the device (each cell's squared difference over 4 pi
// times its solid angle, the weights computed per row in double on the host and read as
// floats) against the CPU's farfield_distance in double, on the paper's grid, whose polar
// cells are ~570x smaller than its equatorial ones. The bound is float rounding alone
// (reduction_bound.hpp): each term (a - b)^2 w carries at most 5 roundings (the
// difference, the square, the weight's float, the product, its first addition), then the
// additions of two levels for 1.62 M cells, each 8 per thread, up to S - 1 in a subgroup
// of S lanes and 256 / S - 1 over the workgroup's subgroups: for the square root, 2.4e-6 at
// S = 16 (lavapipe at 512 bits), 2.9e-6 at 8 or 32, at most 4.6e-6 for any S from 2 to 128.
// (Weights computed in the shader with sin missed it 23-fold on NVIDIA's driver, 2026-12-04: Vulkan
// allows sin an absolute error of 2^-11.)
TEST_F(VulkanTest, CandelaWeightedDifferenceMatchesTheCpuMetric) {
    constexpr std::uint32_t w = 1800, h = 900;
    const auto a = random_floats(w * h, 11);
    const auto b = random_floats(w * h, 12);
    const FarField fa{w, h, {a.begin(), a.end()}}, fb{w, h, {b.begin(), b.end()}};
    const double expected = farfield_distance(fa, fb, FarFieldMetric::CandelaL2);
    const ReducePass pass(ctx());
    const double got = std::sqrt(pass.sum_squared_difference(
        ctx(), upload(ctx(), a), upload(ctx(), b), w * h, {FarFieldMetric::CandelaL2, w}));
    const std::uint32_t lanes = ctx().limits().subgroup_size;
    const double bound = reduction_relative_bound(std::uint64_t(w) * h, 5, true, lanes);
    EXPECT_LT(bound, 4.6e-6); // the figures stated above
    EXPECT_NEAR(got, expected, bound * expected);
    // And a constant intensity difference of 3 cd everywhere is 3 cd: the metric is an RMS
    // over the sphere (cells of lm = cd x solid angle).
    FarField c{w, h, std::vector<double>(std::size_t(w) * h)};
    for (std::uint32_t row = 0; row < h; ++row)
        for (std::uint32_t col = 0; col < w; ++col)
            c.lm[std::size_t(row) * w + col] = 3.0 * farfield_cell_solid_angle_sr(row, w, h);
    const FarField zero{w, h, std::vector<double>(std::size_t(w) * h, 0.0)};
    EXPECT_NEAR(farfield_distance(c, zero, FarFieldMetric::CandelaL2), 3.0, 1e-9);
}

} // namespace
} // namespace fird::test
