// Graphics pipelines for dynamic rendering, as the engine and the renderer use them: a
// vertex and a fragment shader, one interleaved vertex buffer, push constants only,
// dynamic viewport and scissor, no culling, the same blend state on every colour
// attachment (independentBlend is an optional feature).
#pragma once

#include <cstdint>
#include <span>
#include <string_view>

#include "context.hpp"
#include "owned.hpp"

namespace fird::vk {

struct GraphicsPipelineDesc {
    std::span<const std::uint32_t> vertex_spirv;
    std::span<const std::uint32_t> fragment_spirv;
    VkShaderStageFlags push_stages = VK_SHADER_STAGE_VERTEX_BIT;
    std::uint32_t push_bytes = 0;
    std::uint32_t vertex_stride = 0;
    std::span<const VkVertexInputAttributeDescription> attributes; // of binding 0 unless...
    // ...several vertex buffers are bound (empty: one, binding 0, of vertex_stride).
    std::span<const VkVertexInputBindingDescription> bindings;
    VkPrimitiveTopology topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkCompareOp depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL; // depth test and write on
    std::span<const VkFormat> colour_formats;
    VkFormat depth_format = VK_FORMAT_UNDEFINED;
    VkPipelineColorBlendAttachmentState blend{};
    std::string_view name; // debug name of the layout and the pipeline
    // Bindings of a push-descriptor set 0 for the fragment stage (e.g. one combined image
    // sampler), pushed per draw with push_descriptors().
    std::span<const VkDescriptorType> fragment_descriptors;
};

// Refuses, in one line naming LP_NATIVE_VECTOR_WIDTH, a device that crashes compiling
// fragment shaders: Mesa 22's lavapipe at more than 256-bit vectors (more than 8 lanes a
// subgroup), where LLVM crashes in the variant's compile (docs/architecture.md, "CPU vector
// width"). make_graphics_pipeline calls it; the workbench and the screenshot's viewport call
// it first, before a window's set-up or a trace that would be wasted.
void require_fragment_shaders(const Context& ctx);

struct GraphicsPipeline {
    Owned<VkDescriptorSetLayout> set_layout; // when the desc has fragment_descriptors
    Owned<VkPipelineLayout> layout;
    Owned<VkPipeline> pipeline;
    PFN_vkCmdPushDescriptorSetKHR push_descriptor_set = nullptr;
};

// "Over" blending of straight alpha, writing all four channels (the overlays, ImGui).
inline constexpr VkPipelineColorBlendAttachmentState kAlphaBlend{
    .blendEnable = VK_TRUE,
    .srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA,
    .dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
    .colorBlendOp = VK_BLEND_OP_ADD,
    .srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
    .dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
    .alphaBlendOp = VK_BLEND_OP_ADD,
    .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                      VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT};

GraphicsPipeline make_graphics_pipeline(const Context& ctx, const GraphicsPipelineDesc& desc);

} // namespace fird::vk
