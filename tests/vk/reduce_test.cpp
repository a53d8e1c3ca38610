// The device reduction against a double-precision CPU sum over random inputs.
#include <cmath>
#include <random>
#include <vector>

#include "passes/reduce_pass.hpp"
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

vk::Buffer upload(const vk::Context& c, const std::vector<float>& v) {
    vk::Buffer b(c, v.size() * sizeof(float), vk::kStorageUsage, vk::MemoryUse::Device,
                 "test.reduce.input");
    b.upload(c, std::span<const float>(v));
    return b;
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

INSTANTIATE_TEST_SUITE_P(Sizes, ReduceTest, ::testing::Values(0u, 1u, 17u, 2049u, 1000003u));

} // namespace
} // namespace fird::test
