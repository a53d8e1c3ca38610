#include "graphics_pipeline.hpp"

#include <cstdlib>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "check.hpp"
#include "shader_module.hpp"

namespace fird::vk {

void require_fragment_shaders(const Context& ctx) {
    const DeviceSummary& d = ctx.summary();
    const std::uint32_t lanes = ctx.limits().subgroup_size;
    if (d.driver_name != "llvmpipe" || d.driver_info.rfind("Mesa 22.", 0) != 0 || lanes <= 8)
        return;
    const char* width = std::getenv("LP_NATIVE_VECTOR_WIDTH");
    throw std::runtime_error(fmt::format(
        "lavapipe at {} bits (LP_NATIVE_VECTOR_WIDTH={}) cannot compile fragment shaders: {} "
        "crashes in LLVM there; unset LP_NATIVE_VECTOR_WIDTH (or set it to 256) to draw",
        lanes * 32, width ? width : "unset", d.driver_info));
}

GraphicsPipeline make_graphics_pipeline(const Context& ctx, const GraphicsPipelineDesc& desc) {
    require_fragment_shaders(ctx);
    const VkDevice dev = ctx.device();
    GraphicsPipeline out;
    const VkPushConstantRange range{
        .stageFlags = desc.push_stages, .offset = 0, .size = desc.push_bytes};
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    if (!desc.fragment_descriptors.empty()) {
        std::vector<VkDescriptorSetLayoutBinding> bindings;
        for (std::uint32_t i = 0; i < desc.fragment_descriptors.size(); ++i)
            bindings.push_back({.binding = i,
                                .descriptorType = desc.fragment_descriptors[i],
                                .descriptorCount = 1,
                                .stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT});
        const VkDescriptorSetLayoutCreateInfo set_info{
            .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
            .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
            .bindingCount = std::uint32_t(bindings.size()),
            .pBindings = bindings.data()};
        FIRD_VK_CHECK(vkCreateDescriptorSetLayout(dev, &set_info, nullptr, &set_layout));
        out.set_layout = Owned<VkDescriptorSetLayout>(dev, set_layout);
        ctx.name(set_layout, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, desc.name);
        out.push_descriptor_set = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
            vkGetDeviceProcAddr(dev, "vkCmdPushDescriptorSetKHR"));
        if (!out.push_descriptor_set)
            throw VulkanError("vkGetDeviceProcAddr(vkCmdPushDescriptorSetKHR): not available",
                              VK_ERROR_EXTENSION_NOT_PRESENT);
    }
    const VkPipelineLayoutCreateInfo layout_info{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_layout ? 1u : 0u,
        .pSetLayouts = &set_layout,
        .pushConstantRangeCount = desc.push_bytes > 0 ? 1u : 0u,
        .pPushConstantRanges = &range};
    VkPipelineLayout layout = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreatePipelineLayout(dev, &layout_info, nullptr, &layout));
    out.layout = Owned<VkPipelineLayout>(dev, layout);
    ctx.name(layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, desc.name);

    const auto vert = make_shader_module(dev, desc.vertex_spirv);
    const auto frag = make_shader_module(dev, desc.fragment_spirv);
    const VkPipelineShaderStageCreateInfo stages[] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vert.get(),
         .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = frag.get(),
         .pName = "main"}};
    const VkVertexInputBindingDescription binding{
        .binding = 0, .stride = desc.vertex_stride, .inputRate = VK_VERTEX_INPUT_RATE_VERTEX};
    const VkPipelineVertexInputStateCreateInfo vertex_input{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount =
            desc.bindings.empty() ? 1u : std::uint32_t(desc.bindings.size()),
        .pVertexBindingDescriptions = desc.bindings.empty() ? &binding : desc.bindings.data(),
        .vertexAttributeDescriptionCount = std::uint32_t(desc.attributes.size()),
        .pVertexAttributeDescriptions = desc.attributes.data()};
    const VkPipelineInputAssemblyStateCreateInfo assembly{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = desc.topology};
    const VkPipelineViewportStateCreateInfo viewport{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .scissorCount = 1};
    const VkPipelineRasterizationStateCreateInfo raster{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = VK_CULL_MODE_NONE,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .lineWidth = 1.0f};
    const VkPipelineMultisampleStateCreateInfo multisample{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    const VkPipelineDepthStencilStateCreateInfo depth{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = VK_TRUE,
        .depthWriteEnable = VK_TRUE,
        .depthCompareOp = desc.depth_compare};
    const std::vector<VkPipelineColorBlendAttachmentState> blends(desc.colour_formats.size(),
                                                                  desc.blend);
    const VkPipelineColorBlendStateCreateInfo blend{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = std::uint32_t(blends.size()),
        .pAttachments = blends.data()};
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    const VkPipelineDynamicStateCreateInfo dynamic{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = 2,
        .pDynamicStates = dynamic_states};
    const VkPipelineRenderingCreateInfo rendering{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
        .colorAttachmentCount = std::uint32_t(desc.colour_formats.size()),
        .pColorAttachmentFormats = desc.colour_formats.data(),
        .depthAttachmentFormat = desc.depth_format};
    const VkGraphicsPipelineCreateInfo info{.sType =
                                                VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
                                            .pNext = &rendering,
                                            .stageCount = 2,
                                            .pStages = stages,
                                            .pVertexInputState = &vertex_input,
                                            .pInputAssemblyState = &assembly,
                                            .pViewportState = &viewport,
                                            .pRasterizationState = &raster,
                                            .pMultisampleState = &multisample,
                                            .pDepthStencilState = &depth,
                                            .pColorBlendState = &blend,
                                            .pDynamicState = &dynamic,
                                            .layout = layout};
    VkPipeline pipeline = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateGraphicsPipelines(dev, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    out.pipeline = Owned<VkPipeline>(dev, pipeline);
    ctx.name(pipeline, VK_OBJECT_TYPE_PIPELINE, desc.name);
    return out;
}

} // namespace fird::vk
