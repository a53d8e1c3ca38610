// Device timestamps around the passes of one submission: pass k's begin and end are
// queries 2k and 2k + 1 of one pool, reset once per recording, so passes recorded into one
// command buffer keep their own device times.
#pragma once

#include <cstdint>
#include <vector>

#include "context.hpp"
#include "owned.hpp"

namespace fird::vk {

class GpuTimer {
  public:
    // `pairs`: the most passes one recording times.
    explicit GpuTimer(const Context& ctx, std::uint32_t pairs = 1);
    // Once per recording, before its first begin(): every query of the pool is reset.
    void reset(VkCommandBuffer cb);
    // Timestamps around one pass of the recording; begin() returns the pass's pair (passes
    // past the pool's `pairs` are a logic error). No-ops without timestamps.
    std::uint32_t begin(VkCommandBuffer cb);
    void end(VkCommandBuffer cb, std::uint32_t pair) const;
    // After the submission's wait: reads every pair recorded since reset() at once.
    void read();
    double elapsed_ms(std::uint32_t pair) const; // 0 when timestamps are unsupported
    bool supported() const { return static_cast<bool>(pool_); }

  private:
    const Context* ctx_;
    Owned<VkQueryPool> pool_;
    std::uint32_t pairs_ = 0;
    std::uint32_t used_ = 0;           // pairs begun since reset()
    std::vector<std::uint64_t> ticks_; // read(): 2 per pair
};

} // namespace fird::vk
