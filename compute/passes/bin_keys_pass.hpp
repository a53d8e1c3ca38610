// Atomic histogram of integer keys on the device (the far field's binning primitive).
#pragma once

#include <cstdint>
#include <vector>

#include "vk/buffer.hpp"
#include "vk/compute_pipeline.hpp"

namespace fird {

class BinKeysPass {
  public:
    explicit BinKeysPass(const vk::Context& ctx);

    // bins must hold bin_count + 1 uints (last: keys >= bin_count) and be zeroed.
    void record(VkCommandBuffer cb, const vk::Buffer& keys, std::uint32_t count,
                const vk::Buffer& bins, std::uint32_t bin_count) const;

    // Convenience: upload keys, bin, read back bin_count + 1 counts.
    std::vector<std::uint32_t> run(const vk::Context& ctx, const std::vector<std::uint32_t>& keys,
                                   std::uint32_t bin_count) const;

  private:
    vk::ComputePipeline pipeline_;
};

} // namespace fird
