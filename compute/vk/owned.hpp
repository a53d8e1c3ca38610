// Move-only owners of device-level Vulkan handles (pipelines, layouts, pools, ...).
#pragma once

#include <utility>

#include <vulkan/vulkan.h>

namespace fird::vk {

// One overload per handle type; Owned<T> finds the right one.
inline void destroy(VkDevice d, VkPipeline h) {
    vkDestroyPipeline(d, h, nullptr);
}
inline void destroy(VkDevice d, VkPipelineLayout h) {
    vkDestroyPipelineLayout(d, h, nullptr);
}
inline void destroy(VkDevice d, VkDescriptorSetLayout h) {
    vkDestroyDescriptorSetLayout(d, h, nullptr);
}
inline void destroy(VkDevice d, VkShaderModule h) {
    vkDestroyShaderModule(d, h, nullptr);
}
inline void destroy(VkDevice d, VkCommandPool h) {
    vkDestroyCommandPool(d, h, nullptr);
}
inline void destroy(VkDevice d, VkFence h) {
    vkDestroyFence(d, h, nullptr);
}
inline void destroy(VkDevice d, VkQueryPool h) {
    vkDestroyQueryPool(d, h, nullptr);
}
inline void destroy(VkDevice d, VkBuffer h) {
    vkDestroyBuffer(d, h, nullptr);
}
inline void destroy(VkDevice d, VkImage h) {
    vkDestroyImage(d, h, nullptr);
}
inline void destroy(VkDevice d, VkImageView h) {
    vkDestroyImageView(d, h, nullptr);
}
inline void destroy(VkDevice d, VkDeviceMemory h) {
    vkFreeMemory(d, h, nullptr);
}
inline void destroy(VkDevice d, VkBufferView h) {
    vkDestroyBufferView(d, h, nullptr);
}
inline void destroy(VkDevice d, VkSampler h) {
    vkDestroySampler(d, h, nullptr);
}

template <typename Handle> class Owned {
  public:
    Owned() = default;
    Owned(VkDevice device, Handle handle) : device_(device), handle_(handle) {}
    ~Owned() { reset(); }
    Owned(const Owned&) = delete;
    Owned& operator=(const Owned&) = delete;
    Owned(Owned&& o) noexcept
        : device_(o.device_), handle_(std::exchange(o.handle_, VK_NULL_HANDLE)) {}
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
        }
        return *this;
    }
    Handle get() const { return handle_; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }
    void reset() {
        if (handle_ != VK_NULL_HANDLE) destroy(device_, handle_);
        handle_ = VK_NULL_HANDLE;
    }

  private:
    VkDevice device_ = VK_NULL_HANDLE;
    Handle handle_ = VK_NULL_HANDLE;
};

} // namespace fird::vk
