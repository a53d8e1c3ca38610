#include "image.hpp"

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
    const VkMemoryAllocateInfo alloc{
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex =
            ctx.find_memory_type(req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)};
    VkDeviceMemory memory = VK_NULL_HANDLE;
    FIRD_VK_CHECK(vkAllocateMemory(dev, &alloc, nullptr, &memory));
    memory_ = Owned<VkDeviceMemory>(dev, memory);
    FIRD_VK_CHECK(vkBindImageMemory(dev, image, memory, 0));

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

void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to) {
    const bool depth = image.format() == VK_FORMAT_D32_SFLOAT;
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
        .image = image.get(),
        .subresourceRange = {.aspectMask = depth ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT)
                                                 : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT),
                             .levelCount = 1,
                             .layerCount = 1}};
    const VkDependencyInfo dep{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                               .imageMemoryBarrierCount = 1,
                               .pImageMemoryBarriers = &b};
    vkCmdPipelineBarrier2(cb, &dep);
}

} // namespace fird::vk
