#include "mesh_raster.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <glm/geometric.hpp>

#include "fird_shared.h"
#include "mesh_height_frag.h"
#include "mesh_height_vert.h"
#include "vk/check.hpp"
#include "vk/image.hpp"
#include "vk/shader_module.hpp"

namespace fird {

namespace {

constexpr VkFormat kHeightFormat = VK_FORMAT_R32_SFLOAT;
constexpr VkFormat kGradientFormat = VK_FORMAT_R32G32_SFLOAT;
constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

struct MeshVertex {
    float position_mm[3];
    float gradient[2]; // of the triangle's plane, the same at its three corners
};

// Every triangle that is not vertical, as three vertices carrying its plane's gradient
// (a vertical triangle covers no texel centre of a height field).
std::vector<MeshVertex> triangle_list(const TriangleMesh& mesh) {
    std::vector<MeshVertex> out;
    out.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (std::abs(n.z) <= 1e-12 * glm::dot(n, n) || !std::isfinite(n.z)) continue;
        const float gx = float(-n.x / n.z), gy = float(-n.y / n.z);
        for (const glm::dvec3& p : {a, b, c})
            out.push_back({{float(p.x), float(p.y), float(p.z)}, {gx, gy}});
    }
    return out;
}

VkRenderingAttachmentInfo colour_attachment(const vk::Image& image, float clear) {
    return {.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
            .imageView = image.view(),
            .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .clearValue = {.color = {.float32 = {clear, 0.0f, 0.0f, 0.0f}}}};
}

void copy_to_buffer(VkCommandBuffer cb, const vk::Image& image, const vk::Buffer& buffer) {
    const VkBufferImageCopy region{
        .bufferOffset = 0,
        .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT, .layerCount = 1},
        .imageExtent = {image.width(), image.height(), 1}};
    vkCmdCopyImageToBuffer(cb, image.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.get(), 1,
                           &region);
}

} // namespace

MeshRasterizer::MeshRasterizer(const vk::Context& ctx) : ctx_(&ctx) {
    const VkDevice dev = ctx.device();
    const VkPushConstantRange range{.stageFlags =
                                        VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                    .offset = 0,
                                    .size = sizeof(gpu::MeshRasterPush)};
    const VkPipelineLayoutCreateInfo layout_info{.sType =
                                                     VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                                 .pushConstantRangeCount = 1,
                                                 .pPushConstantRanges = &range};
    VkPipelineLayout layout = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreatePipelineLayout(dev, &layout_info, nullptr, &layout));
    layout_ = vk::Owned<VkPipelineLayout>(dev, layout);
    ctx.name(layout, VK_OBJECT_TYPE_PIPELINE_LAYOUT, "fird.mesh_raster");

    const auto vert = vk::make_shader_module(dev, fird_spv_mesh_height_vert);
    const auto frag = vk::make_shader_module(dev, fird_spv_mesh_height_frag);
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
        .binding = 0, .stride = sizeof(MeshVertex), .inputRate = VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[] = {
        {.location = 0,
         .binding = 0,
         .format = VK_FORMAT_R32G32B32_SFLOAT,
         .offset = offsetof(MeshVertex, position_mm)},
        {.location = 1,
         .binding = 0,
         .format = VK_FORMAT_R32G32_SFLOAT,
         .offset = offsetof(MeshVertex, gradient)}};
    const VkPipelineVertexInputStateCreateInfo vertex_input{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = 1,
        .pVertexBindingDescriptions = &binding,
        .vertexAttributeDescriptionCount = 2,
        .pVertexAttributeDescriptions = attributes};
    const VkPipelineInputAssemblyStateCreateInfo assembly{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    const VkPipelineViewportStateCreateInfo viewport{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .scissorCount = 1};
    const VkPipelineRasterizationStateCreateInfo raster{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = VK_CULL_MODE_NONE, // a mesh's winding says nothing about up
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .lineWidth = 1.0f};
    const VkPipelineMultisampleStateCreateInfo multisample{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    const VkPipelineDepthStencilStateCreateInfo depth{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = VK_TRUE,
        .depthWriteEnable = VK_TRUE,
        .depthCompareOp = VK_COMPARE_OP_GREATER}; // the highest surface over a texel
    // Identical for both attachments (independentBlend is an optional feature).
    constexpr VkPipelineColorBlendAttachmentState kWrite{
        .blendEnable = VK_FALSE,
        .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                          VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT};
    const VkPipelineColorBlendAttachmentState no_blend[] = {kWrite, kWrite};
    const VkPipelineColorBlendStateCreateInfo blend{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = 2,
        .pAttachments = no_blend};
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    const VkPipelineDynamicStateCreateInfo dynamic{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = 2,
        .pDynamicStates = dynamic_states};
    const VkFormat colour_formats[] = {kHeightFormat, kGradientFormat};
    const VkPipelineRenderingCreateInfo rendering{
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO,
        .colorAttachmentCount = 2,
        .pColorAttachmentFormats = colour_formats,
        .depthAttachmentFormat = kDepthFormat};
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
    pipeline_ = vk::Owned<VkPipeline>(dev, pipeline);
    ctx.name(pipeline, VK_OBJECT_TYPE_PIPELINE, "fird.mesh_raster");
}

void MeshRasterizer::rasterize(const TriangleMesh& mesh, const Holder& holder, std::uint32_t width,
                               std::uint32_t height, const vk::Buffer& heights,
                               const vk::Buffer& gradients) const {
    const vk::Context& ctx = *ctx_;
    const std::vector<MeshVertex> vertices = triangle_list(mesh);
    if (vertices.empty()) throw std::invalid_argument("the mesh has no non-vertical triangle");
    const VkDeviceSize vertex_bytes = vertices.size() * sizeof(MeshVertex);
    vk::Buffer vertex_buffer(ctx, vertex_bytes, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                             vk::MemoryUse::Upload, "fird.mesh_raster.vertices");
    vertex_buffer.upload(ctx, std::span<const MeshVertex>(vertices));

    const auto usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    const vk::Image height_image(ctx, width, height, kHeightFormat, usage,
                                 "fird.mesh_raster.height");
    const vk::Image gradient_image(ctx, width, height, kGradientFormat, usage,
                                   "fird.mesh_raster.gradient");
    const vk::Image depth_image(ctx, width, height, kDepthFormat,
                                VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                "fird.mesh_raster.depth");

    // Depth 0 .. 1 spans the mesh's own z range (padded), so nothing is clipped.
    float z0 = vertices[0].position_mm[2], z1 = z0;
    for (const MeshVertex& v : vertices) {
        z0 = std::min(z0, v.position_mm[2]);
        z1 = std::max(z1, v.position_mm[2]);
    }
    const float pad = 0.01f * (z1 - z0) + 1e-3f;
    gpu::MeshRasterPush push{.depth_z0_mm = z0 - pad, .depth_z1_mm = z1 + pad};
    for (int k = 0; k < 3; ++k) {
        push.holder_min[k] = float(holder.min_mm[k]);
        push.holder_max[k] = float(holder.max_mm[k]);
    }

    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        vk::transition(cb, height_image, VK_IMAGE_LAYOUT_UNDEFINED,
                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        vk::transition(cb, gradient_image, VK_IMAGE_LAYOUT_UNDEFINED,
                       VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        vk::transition(cb, depth_image, VK_IMAGE_LAYOUT_UNDEFINED,
                       VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        // A texel no triangle covers (the mesh check forbids them) reads as the floor.
        const VkRenderingAttachmentInfo colours[] = {
            colour_attachment(height_image, float(holder.min_mm.z)),
            colour_attachment(gradient_image, 0.0f)};
        const VkRenderingAttachmentInfo depth{.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                              .imageView = depth_image.view(),
                                              .imageLayout =
                                                  VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                                              .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
                                              .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                              .clearValue = {.depthStencil = {0.0f, 0}}};
        const VkRenderingInfo info{.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                                   .renderArea = {{0, 0}, {width, height}},
                                   .layerCount = 1,
                                   .colorAttachmentCount = 2,
                                   .pColorAttachments = colours,
                                   .pDepthAttachment = &depth};
        vkCmdBeginRendering(cb, &info);
        const VkViewport viewport{0.0f, 0.0f, float(width), float(height), 0.0f, 1.0f};
        const VkRect2D scissor{{0, 0}, {width, height}};
        vkCmdSetViewport(cb, 0, 1, &viewport);
        vkCmdSetScissor(cb, 0, 1, &scissor);
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
        const VkBuffer vb = vertex_buffer.get();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cb, 0, 1, &vb, &offset);
        vkCmdPushConstants(cb, layout_.get(),
                           VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof(push), &push);
        vkCmdDraw(cb, std::uint32_t(vertices.size()), 1, 0, 0);
        vkCmdEndRendering(cb);
        vk::transition(cb, height_image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        vk::transition(cb, gradient_image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                       VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        copy_to_buffer(cb, height_image, heights);
        copy_to_buffer(cb, gradient_image, gradients);
        vk::barrier_all(cb);
    });
}

} // namespace fird
