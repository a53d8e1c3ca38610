// Draw into an offscreen image on the shared device and read the pixels back.
#include <vector>

#include "flat_pipeline.hpp"
#include "offscreen_target.hpp"
#include "vk/buffer.hpp"
#include "vulkan_fixture.hpp"

namespace fird::test {
namespace {

using render::FlatVertex;

std::array<std::uint8_t, 4> pixel(const std::vector<std::uint8_t>& rgba, std::uint32_t width,
                                  std::uint32_t x, std::uint32_t y) {
    const std::size_t i = (std::size_t(y) * width + x) * 4;
    return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
}

TEST_F(VulkanTest, ClearAndDrawARectangleReadsBackExpectedPixels) {
    constexpr std::uint32_t kW = 64;
    constexpr std::uint32_t kH = 48;
    const render::OffscreenTarget target(ctx(), kW, kH, "test.offscreen");
    const render::FlatPipeline pipeline(ctx(), VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST, "test.flat");
    // A red rectangle covering the left half of the image (NDC x in [-1, 0]), and a
    // half-transparent green one over the bottom half, drawn after it at the same depth.
    const std::vector<FlatVertex> vertices = {
        {{-1, -1, 0.5f}, {1, 0, 0, 1}},   {{0, -1, 0.5f}, {1, 0, 0, 1}},
        {{0, 1, 0.5f}, {1, 0, 0, 1}},     {{-1, -1, 0.5f}, {1, 0, 0, 1}},
        {{0, 1, 0.5f}, {1, 0, 0, 1}},     {{-1, 1, 0.5f}, {1, 0, 0, 1}},
        {{-1, 0, 0.5f}, {0, 1, 0, 0.5f}}, {{1, 0, 0.5f}, {0, 1, 0, 0.5f}},
        {{1, 1, 0.5f}, {0, 1, 0, 0.5f}},  {{-1, 0, 0.5f}, {0, 1, 0, 0.5f}},
        {{1, 1, 0.5f}, {0, 1, 0, 0.5f}},  {{-1, 1, 0.5f}, {0, 1, 0, 0.5f}},
    };
    vk::Buffer vb(ctx(), vertices.size() * sizeof(FlatVertex), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                  vk::MemoryUse::Upload, "test.vertices");
    vb.upload(ctx(), std::span<const FlatVertex>(vertices));
    ctx().submit_and_wait([&](VkCommandBuffer cb) {
        target.begin(cb, {0, 0, 1, 1});
        pipeline.draw(cb, vb, static_cast<std::uint32_t>(vertices.size()), render::kIdentity);
        target.end(cb);
    });
    const auto rgba = target.read_rgba(ctx());
    ASSERT_EQ(rgba.size(), std::size_t(kW) * kH * 4);
    // Vulkan's NDC +y points down the image: y in [0, 1] is the bottom half.
    using P = std::array<std::uint8_t, 4>;
    EXPECT_EQ(pixel(rgba, kW, 10, 10), (P{255, 0, 0, 255})); // top-left: red
    EXPECT_EQ(pixel(rgba, kW, 50, 10), (P{0, 0, 255, 255})); // top-right: clear blue
    const auto bl = pixel(rgba, kW, 10, 40);                 // red under 50 % green
    EXPECT_NEAR(bl[0], 128, 2);
    EXPECT_NEAR(bl[1], 128, 2);
    EXPECT_EQ(bl[2], 0);
    const auto br = pixel(rgba, kW, 50, 40); // blue under 50 % green
    EXPECT_EQ(br[0], 0);
    EXPECT_NEAR(br[1], 128, 2);
    EXPECT_NEAR(br[2], 128, 2);
}

} // namespace
} // namespace fird::test
