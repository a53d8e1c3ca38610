// Device timestamps around one submission (host wall time where unsupported).
#pragma once

#include "context.hpp"
#include "owned.hpp"

namespace fird::vk {

class GpuTimer {
  public:
    explicit GpuTimer(const Context& ctx);
    // Call at the start and end of a command buffer; then elapsed_ms() after the wait.
    void begin(VkCommandBuffer cb) const;
    void end(VkCommandBuffer cb) const;
    double elapsed_ms() const; // 0 when timestamps are unsupported
    bool supported() const { return static_cast<bool>(pool_); }

  private:
    const Context* ctx_;
    Owned<VkQueryPool> pool_;
};

} // namespace fird::vk
