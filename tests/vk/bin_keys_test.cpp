// The device's atomic histogram against a CPU histogram: counts must agree exactly.
#include <random>
#include <stdexcept>
#include <vector>

#include "bin_keys_comp.h"
#include "passes/bin_keys_pass.hpp"
#include "vk/buffer.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

class BinKeysTest : public VulkanTest, public ::testing::WithParamInterface<std::uint32_t> {};

// A pass's bindings are checked against its shader's table (pass_bindings.hpp, the
// vk::TypedPass fields) before anything reaches the device: a member of the wrong kind (a
// texel view where bin_keys.comp reads a storage buffer) is refused, not recorded.
TEST_F(VulkanTest, ATypedPassRefusesABindingOfTheWrongKindBeforeRecording) {
    const vk::TypedPass<BinKeysBindings, gpu::BinKeysPush> pass(ctx(), fird_spv_bin_keys_comp,
                                                                "test.bin_keys");
    vk::Buffer bins(ctx(), 16, vk::kStorageUsage, vk::MemoryUse::Device, "test.bins");
    const BinKeysBindings wrong{.keys = {.type = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER},
                                .bins = vk::storage(bins)};
    EXPECT_THROW(
        pass.dispatch(VK_NULL_HANDLE, wrong, gpu::BinKeysPush{.count = 1, .bin_count = 3}, 1),
        std::logic_error);
    // The table names every slot once, each with the shader's own binding constant.
    static_assert(vk::TypedPass<BinKeysBindings, gpu::BinKeysPush>::kCount == 2);
    static_assert(BinKeysBindings::fields()[0].slot == gpu::kBinKeysBindingKeys);
}

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
