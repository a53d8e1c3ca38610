// The device's atomic histogram against a CPU histogram: counts must agree exactly.
#include <random>
#include <vector>

#include "passes/bin_keys_pass.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

class BinKeysTest : public VulkanTest, public ::testing::WithParamInterface<std::uint32_t> {};

TEST_P(BinKeysTest, CountsMatchCpuExactly) {
    const std::uint32_t n = GetParam();
    constexpr std::uint32_t kBins = 1000;
    std::mt19937 rng(n);
    // Some keys fall past the last bin: they must be counted in the overflow slot.
    std::uniform_int_distribution<std::uint32_t> key(0, kBins + 10);
    std::vector<std::uint32_t> keys(n);
    std::vector<std::uint32_t> expected(kBins + 1, 0);
    for (auto& k : keys) {
        k = key(rng);
        ++expected[std::min(k, kBins)];
    }
    const BinKeysPass pass(ctx());
    const auto got = pass.run(ctx(), keys, kBins);
    ASSERT_EQ(got.size(), expected.size());
    EXPECT_EQ(got, expected);
}

TEST_F(VulkanTest, BinKeysAllInOneBinDoNotLoseCounts) {
    // Maximum contention on one counter.
    const std::vector<std::uint32_t> keys(100000, 3);
    const BinKeysPass pass(ctx());
    const auto got = pass.run(ctx(), keys, 8);
    EXPECT_EQ(got[3], 100000u);
}

INSTANTIATE_TEST_SUITE_P(Sizes, BinKeysTest, ::testing::Values(0u, 1u, 17u, 1000003u));

} // namespace
} // namespace fird::test
