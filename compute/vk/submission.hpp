// A submission the host does not wait for: recorded into a command buffer of its own,
// submitted on the shared queue, and asked later whether the device has finished it (the
// workbench redraws its views this way, so that a frame never waits behind the worker's
// compute for a picture it can show one frame later).
#pragma once

#include <functional>

#include <vulkan/vulkan.h>

#include "owned.hpp"

namespace fird::vk {

class Context;

class Submission {
  public:
    Submission() = default;
    // Records into a fresh command buffer and submits it without waiting.
    Submission(const Context& ctx, const std::function<void(VkCommandBuffer)>& record,
               const char* name);
    // Waits (bounded) for an unfinished submission: what it uses is never freed in flight.
    ~Submission();
    Submission(Submission&&) noexcept = default;
    Submission& operator=(Submission&&) noexcept;

    bool submitted() const { return fence_.get() != VK_NULL_HANDLE; }
    // Whether the device has finished it (a poll; never blocks).
    bool done() const;
    // Blocks until it has finished (bounded: a device that hangs is a VulkanError).
    void wait() const;

  private:
    const Context* ctx_ = nullptr;
    Owned<VkCommandPool> pool_; // its command buffer is freed with it
    Owned<VkFence> fence_;
};

} // namespace fird::vk
