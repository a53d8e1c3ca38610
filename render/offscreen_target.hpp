// An offscreen RGBA8 colour image (with depth) to draw into and read back: the
// screenshot path, and what the ui shows as a texture. Headless is only a flag.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "vk/context.hpp"
#include "vk/image.hpp"

namespace fird::render {

inline constexpr VkFormat kColourFormat = VK_FORMAT_R8G8B8A8_UNORM;
inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

class OffscreenTarget {
  public:
    OffscreenTarget(const vk::Context& ctx, std::uint32_t width, std::uint32_t height,
                    std::string_view name);

    // Starts dynamic rendering: clears colour to `clear` (linear RGBA) and depth to 1.
    void begin(VkCommandBuffer cb, std::array<float, 4> clear) const;
    // Ends rendering; the colour image is left ready to copy (TRANSFER_SRC_OPTIMAL).
    void end(VkCommandBuffer cb) const;

    // Reads the colour image back as tightly packed RGBA8 rows, top row first.
    std::vector<std::uint8_t> read_rgba(const vk::Context& ctx) const;

    std::uint32_t width() const { return colour_.width(); }
    std::uint32_t height() const { return colour_.height(); }
    const vk::Image& colour() const { return colour_; }

  private:
    vk::Image colour_;
    vk::Image depth_;
};

} // namespace fird::render
