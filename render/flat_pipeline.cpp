#include "flat_pipeline.hpp"

#include <cstddef>

#include "flat_frag.h"
#include "flat_vert.h"

namespace fird::render {

FlatPipeline::FlatPipeline(const vk::Context& ctx, VkPrimitiveTopology topology,
                           std::string_view name) {
    const VkVertexInputAttributeDescription attributes[] = {
        {.location = 0,
         .binding = 0,
         .format = VK_FORMAT_R32G32B32_SFLOAT,
         .offset = offsetof(FlatVertex, position)},
        {.location = 1,
         .binding = 0,
         .format = VK_FORMAT_R32G32B32A32_SFLOAT,
         .offset = offsetof(FlatVertex, colour)}};
    const VkFormat colour_format = kColourFormat;
    pipeline_ = vk::make_graphics_pipeline(ctx, {.vertex_spirv = fird_spv_flat_vert,
                                                 .fragment_spirv = fird_spv_flat_frag,
                                                 .push_stages = VK_SHADER_STAGE_VERTEX_BIT,
                                                 .push_bytes = sizeof(float) * 16,
                                                 .vertex_stride = sizeof(FlatVertex),
                                                 .attributes = attributes,
                                                 .topology = topology,
                                                 .depth_compare = VK_COMPARE_OP_LESS_OR_EQUAL,
                                                 .colour_formats = std::span(&colour_format, 1),
                                                 .depth_format = kDepthFormat,
                                                 .blend = vk::kAlphaBlend,
                                                 .name = name});
}

void FlatPipeline::draw(VkCommandBuffer cb, const vk::Buffer& vertices, std::uint32_t vertex_count,
                        const std::array<float, 16>& transform) const {
    if (vertex_count == 0) return;
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
    const VkBuffer buffer = vertices.get();
    const VkDeviceSize offset = 0;
    vkCmdBindVertexBuffers(cb, 0, 1, &buffer, &offset);
    vkCmdPushConstants(cb, pipeline_.layout.get(), VK_SHADER_STAGE_VERTEX_BIT, 0,
                       sizeof(float) * 16, transform.data());
    vkCmdDraw(cb, vertex_count, 1, 0, 0);
}

} // namespace fird::render
