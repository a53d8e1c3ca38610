#include "bin_keys_pass.hpp"

#include "bin_keys_comp.h"
#include "fird_shared.h"

namespace fird {

BinKeysPass::BinKeysPass(const vk::Context& ctx)
    : pipeline_(ctx, fird_spv_bin_keys_comp, "fird.bin_keys") {}

void BinKeysPass::record(VkCommandBuffer cb, const vk::Buffer& keys, std::uint32_t count,
                         const vk::Buffer& bins, std::uint32_t bin_count) const {
    if (count == 0) return; // nothing to dispatch
    const gpu::BinKeysPush push{.count = count, .bin_count = bin_count};
    pipeline_.dispatch(cb, {.keys = vk::storage(keys), .bins = vk::storage(bins)}, push,
                       (count + gpu::kBinKeysWorkgroupSize - 1) / gpu::kBinKeysWorkgroupSize);
}

std::vector<std::uint32_t> BinKeysPass::run(const vk::Context& ctx,
                                            const std::vector<std::uint32_t>& keys,
                                            std::uint32_t bin_count) const {
    const auto count = static_cast<std::uint32_t>(keys.size());
    vk::Buffer key_buffer(ctx, keys.size() * sizeof(std::uint32_t), vk::kStorageUsage,
                          vk::MemoryUse::Device, "fird.bin_keys.keys");
    key_buffer.upload(ctx, std::span<const std::uint32_t>(keys));
    // Device-local: the pass adds to it atomically; download_as copies it out.
    vk::Buffer bins(ctx, (bin_count + 1ull) * sizeof(std::uint32_t), vk::kStorageUsage,
                    vk::MemoryUse::Device, "fird.bin_keys.bins");
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        vkCmdFillBuffer(cb, bins.get(), 0, VK_WHOLE_SIZE, 0);
        vk::barrier_all(cb);
        record(cb, key_buffer, count, bins, bin_count);
    });
    return bins.download_as<std::uint32_t>(ctx, bin_count + 1ull);
}

} // namespace fird
