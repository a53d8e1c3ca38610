// Atomic histogram of integer keys on the device (the far field's binning primitive).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "fird_shared.h"
#include "vk/buffer.hpp"
#include "vk/typed_pass.hpp"

namespace fird {

// bin_keys.comp's bindings by name (vk::TypedPass).
struct BinKeysBindings {
    vk::Binding keys, bins;
    static constexpr auto fields() {
        using B = BinKeysBindings;
        return std::array<vk::BindingField<B>, 2>{{
            {gpu::kBinKeysBindingKeys, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &B::keys},
            {gpu::kBinKeysBindingBins, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &B::bins},
        }};
    }
};

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
    vk::TypedPass<BinKeysBindings, gpu::BinKeysPush> pipeline_;
};

} // namespace fird
