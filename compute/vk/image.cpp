#include "image.hpp"

#include <span>

#include "buffer.hpp"

#include "check.hpp"

namespace fird::vk {

Image::Image(const Context& ctx, std::uint32_t width, std::uint32_t height, VkFormat format,
             VkImageUsageFlags usage, std::string_view name)
    : format_(format), width_(width), height_(height) {
    const VkDevice dev = ctx.device();
    const VkImageCreateInfo info{.sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
                                 .imageType = VK_IMAGE_TYPE_2D,
                                 .format = format,
                                 .extent = {width, height, 1},
                                 .mipLevels = 1,
                                 .arrayLayers = 1,
                                 .samples = VK_SAMPLE_COUNT_1_BIT,
                                 .tiling = VK_IMAGE_TILING_OPTIMAL,
                                 .usage = usage,
                                 .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
                                 .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED};
    VkImage image = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateImage(dev, &info, nullptr, &image));
    image_ = Owned<VkImage>(dev, image);
    ctx.name(image, VK_OBJECT_TYPE_IMAGE, name);

    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(dev, image, &req);
    // Images get memory of their own, not a block's range: they are few (render targets,
    // the workbench's textures, a mesh's corner raster), sized by the window or the height
    // field, and an image beside a buffer in one block would have to keep
    // bufferImageGranularity apart from it (optimal tiling); drivers also prefer render
    // targets in dedicated memory.
    const std::uint32_t type =
        ctx.find_memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    memory_ = ctx.allocate_memory(req, type, name, true);
    FIRD_VK_CHECK(vkBindImageMemory(dev, image, memory_.allocation.memory(), 0));

    const bool depth = format == VK_FORMAT_D32_SFLOAT;
    const VkImageViewCreateInfo view_info{
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = image,
        .viewType = VK_IMAGE_VIEW_TYPE_2D,
        .format = format,
        .subresourceRange = {.aspectMask = depth ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                                                 : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT),
                             .levelCount = 1,
                             .layerCount = 1}};
    VkImageView view = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateImageView(dev, &view_info, nullptr, &view));
    view_ = Owned<VkImageView>(dev, view);
    ctx.name(view, VK_OBJECT_TYPE_IMAGE_VIEW, name);
}

void transition(VkCommandBuffer cb, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                VkImageLayout to) {
    const VkImageMemoryBarrier2 b{
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
        .srcStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .srcAccessMask = VK_ACCESS_2_MEMORY_WRITE_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT,
        .dstAccessMask = VK_ACCESS_2_MEMORY_READ_BIT | VK_ACCESS_2_MEMORY_WRITE_BIT,
        .oldLayout = from,
        .newLayout = to,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = image,
        .subresourceRange = {.aspectMask = aspect, .levelCount = 1, .layerCount = 1}};
    const VkDependencyInfo dep{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                               .imageMemoryBarrierCount = 1,
                               .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cb, &dep);
}

void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to) {
    const bool depth = image.format() == VK_FORMAT_D32_SFLOAT;
    transition(cb, image.get(),
               depth ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                     : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT),
               from, to);
}

Texture::Texture(const Context& ctx, std::uint32_t width, std::uint32_t height,
                 std::string_view name)
    : image_(ctx, width, height, VK_FORMAT_R8G8B8A8_UNORM,
             VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, name) {
    const VkSamplerCreateInfo info{.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
                                   .magFilter = VK_FILTER_LINEAR,
                                   .minFilter = VK_FILTER_LINEAR,
                                   .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
                                   .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                   .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                   .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                                   .maxLod = 0.0f};
    VkSampler sampler = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkCreateSampler(ctx.device(), &info, nullptr, &sampler));
    sampler_ = Owned<VkSampler>(ctx.device(), sampler);
    ctx.name(sampler, VK_OBJECT_TYPE_SAMPLER, name);
}

void Texture::upload(const Context& ctx, const std::uint8_t* rgba) {
    const VkDeviceSize bytes = VkDeviceSize(width()) * height() * 4;
    Buffer staging(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUse::Upload,
                   "fird.texture.staging");
    staging.upload(ctx,
                   std::span<const std::byte>(reinterpret_cast<const std::byte*>(rgba), bytes));
    ctx.submit_and_wait([&](VkCommandBuffer cb) { record_upload(cb, staging); });
}

void Texture::record_upload(VkCommandBuffer cb, const Buffer& staging) {
    transition(cb, image_,
               initialized_ ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    const VkBufferImageCopy region{
        .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT, .layerCount = 1},
        .imageExtent = {width(), height(), 1}};
    vkCmdCopyBufferToImage(cb, staging.get(), image_.get(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
    transition(cb, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    initialized_ = true;
}

void Texture::record_copy(VkCommandBuffer cb, const Image& source) {
    transition(cb, image_,
               initialized_ ? VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL : VK_IMAGE_LAYOUT_UNDEFINED,
               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    const VkImageSubresourceLayers layers{.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT, .layerCount = 1};
    const VkImageCopy region{
        .srcSubresource = layers, .dstSubresource = layers, .extent = {width(), height(), 1}};
    vkCmdCopyImage(cb, source.get(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, image_.get(),
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    transition(cb, image_, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
               VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    initialized_ = true;
}

} // namespace fird::vk
