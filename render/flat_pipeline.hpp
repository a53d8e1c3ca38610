// Draws coloured triangles (or lines) into an OffscreenTarget: the primitive the
// reflector mesh, ray paths, quadtree boxes and plots are built from.
#pragma once

#include <array>
#include <span>
#include <string_view>

#include "offscreen_target.hpp"
#include "vk/buffer.hpp"
#include "vk/graphics_pipeline.hpp"

namespace fird::render {

struct FlatVertex {
    float position[3];
    float colour[4];
};

class FlatPipeline {
  public:
    FlatPipeline(const vk::Context& ctx, VkPrimitiveTopology topology, std::string_view name);

    // Draws `vertex_count` vertices of `vertices` with the column-major 4x4 transform.
    void draw(VkCommandBuffer cb, const vk::Buffer& vertices, std::uint32_t vertex_count,
              const std::array<float, 16>& transform) const;

  private:
    vk::GraphicsPipeline pipeline_;
};

// The identity transform (vertices already in normalized device coordinates).
inline constexpr std::array<float, 16> kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

} // namespace fird::render
