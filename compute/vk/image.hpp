// 2D images with memory of their own and a view (render targets, height textures).
#pragma once

#include <cstdint>
#include <string_view>

#include "buffer.hpp"
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
    Context::Memory memory_; // before the image: destroyed after it
    Owned<VkImage> image_;
    Owned<VkImageView> view_;
    VkFormat format_ = VK_FORMAT_UNDEFINED;
    std::uint32_t width_ = 0;
    std::uint32_t height_ = 0;
};

// Moves the whole colour image from one layout to another, waiting on all prior work.
void transition(VkCommandBuffer cb, const Image& image, VkImageLayout from, VkImageLayout to);
// The same for an image FIRD does not own (a swapchain's), by aspect.
void transition(VkCommandBuffer cb, VkImage image, VkImageAspectFlags aspect, VkImageLayout from,
                VkImageLayout to);

// An RGBA8 image to sample (the workbench's textures), filled from pixels, with its
// sampler (linear filtering, clamped edges).
class Texture {
  public:
    Texture() = default;
    Texture(const Context& ctx, std::uint32_t width, std::uint32_t height, std::string_view name);
    // Replaces the whole image with RGBA rows (top first); waits for the copy.
    void upload(const Context& ctx, const std::uint8_t* rgba);
    // Records the same from `staging` (RGBA rows, top first; it must outlive the
    // submission). Like every transition it waits on all work submitted before it on the
    // queue, so frames still sampling the image finish first.
    void record_upload(VkCommandBuffer cb, const Buffer& staging);
    // Records a copy of `source` (this size, RGBA8, in TRANSFER_SRC_OPTIMAL) into the image.
    void record_copy(VkCommandBuffer cb, const Image& source);
    const Image& image() const { return image_; }
    VkSampler sampler() const { return sampler_.get(); }
    std::uint32_t width() const { return image_.width(); }
    std::uint32_t height() const { return image_.height(); }

  private:
    Image image_;
    Owned<VkSampler> sampler_;
    bool initialized_ = false;
};

} // namespace fird::vk
