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
#include "vk/graphics_pipeline.hpp"
#include "vk/image.hpp"

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
std::vector<MeshVertex> triangle_list(const TriangleMesh& mesh, const glm::dvec3& origin) {
    std::vector<MeshVertex> out;
    out.reserve(mesh.triangles.size() * 3);
    for (const auto& t : mesh.triangles) {
        const glm::dvec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (std::abs(n.z) <= 1e-12 * glm::dot(n, n) || !std::isfinite(n.z)) continue;
        const float gx = float(-n.x / n.z), gy = float(-n.y / n.z);
        for (const glm::dvec3& p : {a - origin, b - origin, c - origin})
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
    const VkVertexInputAttributeDescription attributes[] = {
        {.location = 0,
         .binding = 0,
         .format = VK_FORMAT_R32G32B32_SFLOAT,
         .offset = offsetof(MeshVertex, position_mm)},
        {.location = 1,
         .binding = 0,
         .format = VK_FORMAT_R32G32_SFLOAT,
         .offset = offsetof(MeshVertex, gradient)}};
    const VkFormat colour_formats[] = {kHeightFormat, kGradientFormat};
    // No culling (a mesh's winding says nothing about up); depth GREATER keeps the highest
    // surface over a texel; heights and gradients are written, not blended.
    pipeline_ = vk::make_graphics_pipeline(
        ctx, {.vertex_spirv = fird_spv_mesh_height_vert,
              .fragment_spirv = fird_spv_mesh_height_frag,
              .push_stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
              .push_bytes = sizeof(gpu::MeshRasterPush),
              .vertex_stride = sizeof(MeshVertex),
              .attributes = attributes,
              .depth_compare = VK_COMPARE_OP_GREATER,
              .colour_formats = colour_formats,
              .depth_format = kDepthFormat,
              .blend = {.blendEnable = VK_FALSE,
                        .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                                          VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT},
              .name = "fird.mesh_raster"});
}

void MeshRasterizer::rasterize(const TriangleMesh& mesh, const glm::dvec3& origin,
                               const Holder& holder, std::uint32_t width, std::uint32_t height,
                               const vk::Buffer& heights, const vk::Buffer& gradients) const {
    const vk::Context& ctx = *ctx_;
    const std::vector<MeshVertex> vertices = triangle_list(mesh, origin);
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
        push.holder_min[k] = float(holder.min_mm[k] - origin[k]);
        push.holder_max[k] = float(holder.max_mm[k] - origin[k]);
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
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.pipeline.get());
        const VkBuffer vb = vertex_buffer.get();
        const VkDeviceSize offset = 0;
        vkCmdBindVertexBuffers(cb, 0, 1, &vb, &offset);
        vkCmdPushConstants(cb, pipeline_.layout.get(),
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
