// A shader module from embedded SPIR-V (the build compiles GLSL into headers).
#pragma once

#include <cstdint>
#include <span>

#include "check.hpp"
#include "owned.hpp"

namespace fird::vk {

inline Owned<VkShaderModule> make_shader_module(VkDevice dev, std::span<const std::uint32_t> code) {
    const VkShaderModuleCreateInfo info{.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                        .codeSize = code.size_bytes(),
                                        .pCode = code.data()};
    VkShaderModule m = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateShaderModule(dev, &info, nullptr, &m));
    return {dev, m};
}

} // namespace fird::vk
