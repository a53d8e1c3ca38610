#include "check.hpp"

#include <fmt/format.h>

namespace fird::vk {

const char* result_name(VkResult result) {
    switch (result) {
#define FIRD_CASE(r)                                                                               \
    case r:                                                                                        \
        return #r;
        FIRD_CASE(VK_SUCCESS)
        FIRD_CASE(VK_NOT_READY)
        FIRD_CASE(VK_TIMEOUT)
        FIRD_CASE(VK_INCOMPLETE)
        FIRD_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        FIRD_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        FIRD_CASE(VK_ERROR_INITIALIZATION_FAILED)
        FIRD_CASE(VK_ERROR_DEVICE_LOST)
        FIRD_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        FIRD_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        FIRD_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        FIRD_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        FIRD_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        FIRD_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        FIRD_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        FIRD_CASE(VK_ERROR_FRAGMENTED_POOL)
        FIRD_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
        FIRD_CASE(VK_ERROR_SURFACE_LOST_KHR)
        FIRD_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        FIRD_CASE(VK_SUBOPTIMAL_KHR)
#undef FIRD_CASE
    default:
        return "VK_ERROR_UNKNOWN";
    }
}

namespace {
const char* explain(VkResult result) {
    switch (result) {
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return "out of device memory (use fewer rays per batch or a smaller height field)";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return "out of host memory";
    case VK_ERROR_DEVICE_LOST:
        return "the device was lost (driver reset or crash); results are unavailable";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
        return "no compatible Vulkan driver";
    default:
        return "failed";
    }
}
} // namespace

void throw_vk_error(const char* call_text, VkResult result) {
    // Keep just the function name of the call expression: "vkCreateBuffer(dev, ...)" ->
    // "vkCreateBuffer".
    std::string call(call_text);
    if (const auto paren = call.find('('); paren != std::string::npos) call.resize(paren);
    throw VulkanError(fmt::format("{}: {} ({})", call, explain(result), result_name(result)),
                      result);
}

} // namespace fird::vk
