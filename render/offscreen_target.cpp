#include "offscreen_target.hpp"

#include "vk/buffer.hpp"

namespace fird::render {

OffscreenTarget::OffscreenTarget(const vk::Context& ctx, std::uint32_t width, std::uint32_t height,
                                 std::string_view name)
    : colour_(ctx, width, height, kColourFormat,
              VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                  VK_IMAGE_USAGE_SAMPLED_BIT,
              std::string(name) + ".colour"),
      depth_(ctx, width, height, kDepthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
             std::string(name) + ".depth") {}

void OffscreenTarget::begin(VkCommandBuffer cb, std::array<float, 4> clear) const {
    vk::transition(cb, colour_, VK_IMAGE_LAYOUT_UNDEFINED,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    vk::transition(cb, depth_, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    const VkRenderingAttachmentInfo colour{
        .sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
        .imageView = colour_.view(),
        .imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
        .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
        .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
        .clearValue = {.color = {.float32 = {clear[0], clear[1], clear[2], clear[3]}}}};
    const VkRenderingAttachmentInfo depth{.sType = VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO,
                                          .imageView = depth_.view(),
                                          .imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                                          .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
                                          .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
                                          .clearValue = {.depthStencil = {1.0f, 0}}};
    const VkRenderingInfo info{.sType = VK_STRUCTURE_TYPE_RENDERING_INFO,
                               .renderArea = {{0, 0}, {width(), height()}},
                               .layerCount = 1,
                               .colorAttachmentCount = 1,
                               .pColorAttachments = &colour,
                               .pDepthAttachment = &depth};
    vkCmdBeginRendering(cb, &info);
    const VkViewport viewport{0.0f, 0.0f, float(width()), float(height()), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {width(), height()}};
    vkCmdSetViewport(cb, 0, 1, &viewport);
    vkCmdSetScissor(cb, 0, 1, &scissor);
}

void OffscreenTarget::end(VkCommandBuffer cb) const {
    vkCmdEndRendering(cb);
    vk::transition(cb, colour_, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                   VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

std::vector<std::uint8_t> OffscreenTarget::read_rgba(const vk::Context& ctx) const {
    const VkDeviceSize bytes = VkDeviceSize(width()) * height() * 4;
    vk::Buffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, vk::MemoryUse::Readback,
                       "fird.offscreen.readback");
    ctx.submit_and_wait([&](VkCommandBuffer cb) {
        const VkBufferImageCopy region{
            .bufferOffset = 0,
            .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT, .layerCount = 1},
            .imageExtent = {width(), height(), 1}};
        vkCmdCopyImageToBuffer(cb, colour_.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               staging.get(), 1, &region);
    });
    return staging.download_as<std::uint8_t>(ctx, bytes);
}

} // namespace fird::render
