// 2D images with their own memory and a view (render targets, height textures).
#pragma once

#include <cstdint>
#include <string_view>

#include "context.hpp"
#include "owned.hpp"

namespace fird::vk {

class Image {
  public:
    Image() = default;
    Image(const Context& ctx, std::uint32_t width, std::uint32_t height, VkFormat format,
          VkImageUsageFlags usage, std::string_view name);

    VkImage get() const { return image_.get(); }
    VkImageView view() const { return view_.get(); }
    VkFormat format() const { return format_; }
    std::uint32_t width() const { return width_; }
    std::uint32_t height() const { return height_; }

  private:
    Owned<VkImage> image_;
    Owned<VkDeviceMemory> memory_;
    Owned<VkImageView> view_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    std::uint32_t width_ = 0;
    std::uint32_t height_ = 0;
};

// Moves the whole colour image from one layout to another, waiting on all prior work.
void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to);

} // namespace fird::vk
