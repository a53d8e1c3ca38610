#include "compute_pipeline.hpp"

#include <stdexcept>

#include "check.hpp"
#include "shader_module.hpp"

namespace fird::vk {

ComputePipeline::ComputePipeline(const Context& ctx, std::span<const std::uint32_t> spirv,
                                 std::span<const VkDescriptorType> binding_types,
                                 std::uint32_t push_constant_bytes, std::string_view name,
                                 std::span<const std::uint32_t> specialization)
    : types_(binding_types.begin(), binding_types.end()), push_bytes_(push_constant_bytes) {
    const VkDevice dev = ctx.device();
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (std::uint32_t i = 0; i < types_.size(); ++i)
        bindings.push_back({.binding = i,
                            .descriptorType = types_[i],
                            .descriptorCount = 1,
                            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT});
    const VkDescriptorSetLayoutCreateInfo set_info{
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .flags = VK_DESCRIPTOR_SET_LAYOUT_CREATE_PUSH_DESCRIPTOR_BIT_KHR,
        .bindingCount = static_cast<std::uint32_t>(bindings.size()),
        .pBindings = bindings.data()};
    VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateDescriptorSetLayout(dev, &set_info, nullptr, &set_layout));
    set_layout_ = Owned<VkDescriptorSetLayout>(dev, set_layout);
    ctx.name(set_layout, VK_OBJECT_TYPE_DESCRIPTOR_SET_LAYOUT, name);

    const VkPushConstantRange range{
        .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT, .offset = 0, .size = push_constant_bytes};
    const VkPipelineLayoutCreateInfo layout_info{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 1,
        .pSetLayouts = &set_layout,
        .pushConstantRangeCount = push_constant_bytes ? 1u : 0u,
        .pPushConstantRanges = &range};
    VkPipelineLayout layout = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreatePipelineLayout(dev, &layout_info, nullptr, &layout));
    layout_ = Owned<VkPipelineLayout>(dev, layout);
    ctx.name(layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, name);

    const Owned<VkShaderModule> module = make_shader_module(dev, spirv);

    std::vector<VkSpecializationMapEntry> entries;
    for (std::uint32_t i = 0; i < specialization.size(); ++i)
        entries.push_back({.constantID = i,
                           .offset = i * std::uint32_t(sizeof(std::uint32_t)),
                           .size = sizeof(std::uint32_t)});
    const VkSpecializationInfo spec_info{.mapEntryCount = std::uint32_t(entries.size()),
                                         .pMapEntries = entries.data(),
                                         .dataSize = specialization.size_bytes(),
                                         .pData = specialization.data()};
    const VkComputePipelineCreateInfo info{
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                  .module = module.get(),
                  .pName = "main",
                  .pSpecializationInfo = specialization.empty() ? nullptr : &spec_info},
        .layout = layout};
    VkPipeline pipeline = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateComputePipelines(dev, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline));
    pipeline_ = Owned<VkPipeline>(dev, pipeline);
    ctx.name(pipeline, VK_OBJECT_TYPE_PIPELINE, name);

    push_descriptor_set_ = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(
        vkGetDeviceProcAddr(dev, "vkCmdPushDescriptorSetKHR"));
    if (!push_descriptor_set_)
        throw VulkanError("vkGetDeviceProcAddr(vkCmdPushDescriptorSetKHR): not available",
                          VK_ERROR_EXTENSION_NOT_PRESENT);
}

void ComputePipeline::dispatch(VkCommandBuffer cb, std::span<const Binding> bindings,
                               const void* push, std::uint32_t groups_x, std::uint32_t groups_y,
                               std::uint32_t groups_z) const {
    bind(cb, bindings, push);
    if (groups_x && groups_y && groups_z) vkCmdDispatch(cb, groups_x, groups_y, groups_z);
}

void ComputePipeline::dispatch_indirect(VkCommandBuffer cb, std::span<const Binding> bindings,
                                        const void* push, const Buffer& args,
                                        VkDeviceSize offset) const {
    bind(cb, bindings, push);
    vkCmdDispatchIndirect(cb, args.get(), offset);
}

void ComputePipeline::bind(VkCommandBuffer cb, std::span<const Binding> bindings,
                           const void* push) const {
    if (bindings.size() != types_.size())
        throw std::logic_error("ComputePipeline::dispatch: wrong number of bindings");
    std::vector<VkWriteDescriptorSet> writes;
    writes.reserve(bindings.size());
    for (std::uint32_t i = 0; i < bindings.size(); ++i) {
        if (bindings[i].type != types_[i])
            throw std::logic_error("ComputePipeline::dispatch: binding type mismatch");
        const bool is_buffer = types_[i] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER ||
                               types_[i] == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        const bool is_image = types_[i] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
        const bool is_texel = types_[i] == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER ||
                              types_[i] == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        writes.push_back({.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                          .dstBinding = i,
                          .descriptorCount = 1,
                          .descriptorType = types_[i],
                          .pImageInfo = is_image ? &bindings[i].image : nullptr,
                          .pBufferInfo = is_buffer ? &bindings[i].buffer : nullptr,
                          .pTexelBufferView = is_texel ? &bindings[i].texel_view : nullptr});
    }
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    push_descriptor_set_(cb, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0,
                         static_cast<std::uint32_t>(writes.size()), writes.data());
    if (push_bytes_)
        vkCmdPushConstants(cb, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, push_bytes_, push);
}

} // namespace fird::vk
