// VkResult checking: every call goes through FIRD_VK_CHECK, which turns a failure
// into a VulkanError naming the call and the result ("vkAllocateMemory: out of device memory").
#pragma once

#include <stdexcept>
#include <string>

#include <vulkan/vulkan.h>

namespace fird::vk {

// The readable name of a VkResult, e.g. "VK_ERROR_DEVICE_LOST".
const char* result_name(VkResult result);

class VulkanError : public std::runtime_error {
  public:
    VulkanError(const std::string& what, VkResult result)
        : std::runtime_error(what), result_(result) {}
    VkResult result() const { return result_; }

  private:
    VkResult result_;
};

// No usable Vulkan device or driver at all (the `fird` command exits with code 1).
class NoDeviceError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

[[noreturn]] void throw_vk_error(const char* call_text, VkResult result);

} // namespace fird::vk

#define FIRD_VK_CHECK(call)                                                                        \
    do {                                                                                           \
        const VkResult fird_vk_result_ = (call);                                                   \
        if (fird_vk_result_ < 0) ::fird::vk::throw_vk_error(#call, fird_vk_result_);               \
    } while (0)
